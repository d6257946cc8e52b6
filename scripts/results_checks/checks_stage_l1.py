"""results/model/stage-l1-term/README.md: the stage model with its L1/TEX term. Its table rows and every figure its
prose quotes, recomputed from the committed prediction (prediction.csv), the comparison the check makes again
(model-vs-measured.md, from prediction-stages.csv and the measured H200 rows) and the Nsight Compute log beside
those rows."""
import re

from results_checks.checks_stages import MEASURED, NCU_LOG
from results_checks.core import Embedded, Figure, Generated, Unrecorded
from results_checks.logs import ncu
from results_checks.rows import ROOT, load, median

L1 = "results/model/stage-l1-term"
README = f"{L1}/README.md"
NCU = "results/stages/h200-6ebd003/ncu-stages.log.xz"
NOOPT_LAUNCH = 1  # the log's second launch: noopt_kernel (the first is tile_hits)


def prediction(preset, gbuffer, method, column):
    """prediction.csv's `column` of sibenik 8x8 `method` on `preset` with kernels `gbuffer`."""
    (row,) = [r for r in load(f"{L1}/prediction.csv") if r["preset"] == preset and r["gbuffer"] == gbuffer and
              r["scene"] == "sibenik" and r["tile"] == "8x8" and r["method"] == method]
    return float(row[column])


def l1_row(preset, gbuffer):
    """The README's table row of `preset` and kernels `gbuffer` (sibenik noopt and ours, 8x8)."""
    return tuple(prediction(preset, gbuffer, m, c) for m, c in (
        ("noopt", "gen_ms"), ("ours", "gen_ms"), ("noopt", "gen_l1_ms"), ("noopt", "gen_issue_ms"),
        ("ours", "gen_l1_ms"), ("ours", "gen_issue_ms"), ("noopt", "gen_l1_wavefronts"),
        ("ours", "gen_l1_wavefronts")))


def partition_cycles(kernel="noopt"):
    """The a26f7f6 kernel's partition cycles a warp (../h200-stages/instructions-sm_90.txt, made by
    count-stage-instructions)."""
    text = (ROOT / "results/model/h200-stages/instructions-sm_90.txt").read_text()
    return float(re.search(rf"^{kernel}\s+instructions\s+\d+\s+partition cycles\s+(\d+)", text, re.M).group(1))


def l1_needed():
    """Wavefronts a warp needs to reach noopt's issue term (partition cycles over 4 partitions), and that over the
    hit rule's count."""
    need = partition_cycles() / 4
    return need, partition_cycles(), need / prediction("h200", "fields60", "noopt", "gen_l1_wavefronts")


def saving(preset="h200", method="noopt"):
    """1 - after / before of the generation time (the fewer instructions)."""
    return 1 - prediction(preset, "wide64", method, "gen_ms") / prediction(preset, "fields60", method, "gen_ms")


def compared(stage, method):
    """model-vs-measured.md's rows of `stage` whose method `method` matches: (measured ms, modeled ms, ratio)."""
    out = []
    for line in (ROOT / L1 / "model-vs-measured.md").read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 7 and cells[2] == stage and re.fullmatch(method, cells[1]):
            out.append((float(cells[3]), float(cells[4]), float(cells[5])))
    return out


def band(stage, method, missed=False):
    """(count, lowest ratio, highest ratio) of the compared rows (missed: only those outside ±25%)."""
    ratios = [r for _, _, r in compared(stage, method) if not missed or abs(r - 1) > 0.25]
    return len(ratios), min(ratios), max(ratios)


def within(stage, method):
    """How many of the compared rows lie within ±25%."""
    return sum(abs(r - 1) <= 0.25 for _, _, r in compared(stage, method))


def waves(method, gbuffer="fields60", column="gen_l1_wavefronts"):
    """L1 wavefronts a warp of h200 sibenik 8x8 `method` (prediction.csv)."""
    return prediction("h200", gbuffer, method, column)


def column_of(stage, method, i):
    """Column i (0 measured, 1 modeled, 2 their ratio) of the compared rows."""
    return [row[i] for row in compared(stage, method)]


def noopt_ncu(metric):
    return ncu(NCU, NOOPT_LAUNCH, metric)


NOOPT_GEN = r"noopt.*"
GROUP_GEN = r"(ours|contiguous).*"

CHECKS = [Figure(README, f"| {p} | {label} | {{:.4f}} | {{:.4f}} | {{:.4f}} / {{:.4f}} | {{:.4f}} / {{:.4f}} | "
                 "{:.2f}, {:.2f} |", lambda p=p, g=g: l1_row(p, g))
          for p in ("h200", "h100") for g, label in (("fields60", "before 63b5750"), ("wide64", "after"))]

CHECKS += [
    Generated(f"{L1}/model-vs-measured.md", ["scripts/stage_model_check.py", "compare", "--l1-term", "--ncu", NCU_LOG,
                                              "prediction-stages.csv", *MEASURED], cwd=L1),
    Embedded(README, f"{L1}/model-vs-measured.md", "Summary of `model-vs-measured.md`"),
    Figure(README, "repeats `../wide-gbuffer-loads/prediction.md` (~{:.0%} less: the fewer instructions)",
           lambda: saving()),
    Figure(README, "noopt goes from {:.0f} to {:.0f} wavefronts a warp", lambda: (
        waves("noopt"), waves("noopt", "wide64"))),
    Figure(README, "take it from {:.0f} to {:.0f}; `tile_hits`'s one 4-byte load of `prim` from {:.1f} to {:.0f}",
           lambda: (waves("ours"), waves("ours", "wide64"), waves("noopt", column="tile_hits_l1_wavefronts"),
                    waves("noopt", "wide64", "tile_hits_l1_wavefronts"))),
    Figure(README, "generation about {:.0%} faster on both presets", lambda: saving()),
    Figure(README, "**noopt generation ({} stages, {:.2f}–{:.2f}).**", lambda: band("gen", NOOPT_GEN)),
    Figure(README, "The model prices it issue-bound at {:.3f} ms (MODELED); the H200 measured ~{:.2f} ms (GPU), and "
           "Nsight Compute put the kernel at {:.0f}% L1/TEX throughput against {:.0f}% SM", lambda: (
               median(column_of("gen", NOOPT_GEN, 1)), median(column_of("gen", NOOPT_GEN, 0)),
               noopt_ncu("L1/TEX Cache Throughput"), noopt_ncu("Compute (SM) Throughput"))),
    Figure(README, "need about {:.0f} ({:.0f} partition cycles over 4 partitions), {:.0f}× what the hit rule counts",
           l1_needed),
    Figure(README, "or the {:.0f}% is a sub-unit's peak", lambda: noopt_ncu("L1/TEX Cache Throughput")),
    Figure(README, "the unit behind the {:.0f}% is named", lambda: noopt_ncu("L1/TEX Cache Throughput")),
    # The per-load average is the L1 rule's inner figure (simt/stage_l1.cpp), which no committed file holds.
    Unrecorded(README, "field loads take 5.8 wavefronts each on average", "simt/stage_l1.cpp"),
    Figure(README, "is {:.0f} wavefronts a warp, {:.3f} ms", lambda: (
        waves("noopt"), prediction("h200", "fields60", "noopt", "gen_l1_ms"))),
    Figure(README, "Occupancy ({:.0f} registers, half the SM's warps)", lambda: noopt_ncu("Registers Per Thread")),
    Figure(README, "**group generation ({} stages, {:.2f}–{:.2f}; {} within ±25% at k = 64", lambda: (
        *band("gen", GROUP_GEN, missed=True), within("gen", GROUP_GEN))),
    Figure(README, "the L1 term ({:.0f} a warp) stays a quarter of that", lambda: waves("ours")),
    Figure(README, "**costa's gather ({}, {:.2f}–{:.2f})** and **MLHCC's key ({}, {:.2f}–{:.2f})**", lambda: (
        *band("permute", r"noopt\+costa"), *band("key", r"noopt\+mlhcc"))),
    Figure(README, "generation ~{:.0%} faster than the a26f7f6 kernels (h200 noopt {:.4f} → {:.4f} ms, "
           "ours {:.4f} → {:.4f} ms on the model's own scale; the measured baseline is ~{:.2f} ms noopt, "
           "~{:.2f} ms ours)", lambda: (
               saving(), prediction("h200", "fields60", "noopt", "gen_ms"),
               prediction("h200", "wide64", "noopt", "gen_ms"),
               prediction("h200", "fields60", "ours", "gen_ms"), prediction("h200", "wide64", "ours", "gen_ms"),
               median(column_of("gen", NOOPT_GEN, 0)), median(column_of("gen", "ours", 0)))),
    Figure(README, "16-way bank-conflicted under the rule ({:.0f} → {:.0f} wavefronts a warp)", lambda: (
        waves("ours"), waves("ours", "wide64"))),
]
