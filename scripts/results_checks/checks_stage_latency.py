"""results/model/stage-latency/README.md: the stage model with its latency term. Its tables and every figure its
prose quotes, recomputed from the committed predictions (prediction-a26f7f6.csv, prediction.csv, and
../stage-trip-counts/noopt-path/prediction-a26f7f6.csv for the model before), the terms (terms-a26f7f6.csv), the
ptxas counts (registers-sm_90.txt), the constants in simt/ and the comparison the check makes again
(model-vs-measured.md, from prediction-a26f7f6.csv and the measured H200 rows)."""
import math
import re

from results_checks.checks_stages import MEASURED, NCU_LOG
from results_checks.core import Embedded, Figure, Generated
from results_checks.logs import ncu
from results_checks.rows import ROOT, load

L = "results/model/stage-latency"
README = f"{L}/README.md"
MVM = f"{L}/model-vs-measured.md"
BEFORE = "results/model/stage-trip-counts/noopt-path"
BEFORE_MVM = f"{BEFORE}/model-vs-measured.md"
TILES = ("8x8", "16x8", "16x16", "32x8")
SWEEP = "ours:tile={},k={},order=tile"
STAGES = ("gen", "key", "sort", "permute")


def key(r):
    return (r["file"], r["scene"], r["method"], r["stage"])


def modeled(path):
    return {key(r): float(r["modeled_ms"]) for r in load(path)}


def sweep_row(tile, k):
    name = ("stages-sweep.csv", "sibenik", SWEEP.format(tile, k), "gen")
    return tuple(modeled(p)[name] for p in (f"{BEFORE}/prediction-a26f7f6.csv", f"{L}/prediction-a26f7f6.csv",
                                             f"{L}/prediction.csv"))


def changed():
    before, after = modeled(f"{BEFORE}/prediction-a26f7f6.csv"), modeled(f"{L}/prediction-a26f7f6.csv")
    return sum(abs(before[k] - after[k]) > 1e-9 for k in before), len(before)


def head_vs_a26():
    """The largest |HEAD / a26f7f6 - 1| of the stages the term moved."""
    before, a, h = (modeled(p) for p in (f"{BEFORE}/prediction-a26f7f6.csv", f"{L}/prediction-a26f7f6.csv",
                                         f"{L}/prediction.csv"))
    return max(abs(h[k] / a[k] - 1) for k in a if abs(before[k] - a[k]) > 1e-9)


def terms(method, column, scene="sibenik"):
    """terms-a26f7f6.csv's `column` of the pass `method` (the first row of it: stages-SCENE*.csv or the sweep)."""
    rows = [r for r in load(f"{L}/terms-a26f7f6.csv") if r["scene"] == scene and r["method"] == method]
    return float(rows[0][column])


def terms_all(method_re, column):
    return [float(r[column]) for r in load(f"{L}/terms-a26f7f6.csv") if re.fullmatch(method_re, r["method"])]


def compared(path, stage, method, scene=None):
    """A model-vs-measured.md's rows of `stage` whose method matches: (measured, modeled, ratio, within ±25%: the
    table's own verdict, made on the unrounded ratio)."""
    out = []
    for line in (ROOT / path).read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 7 and cells[2] == stage and re.fullmatch(method, cells[1]) and scene in (None, cells[0]):
            out.append((float(cells[3]), float(cells[4]), float(cells[5]), cells[6] == "yes"))
    return out


def ratios(stage, method, path=MVM, missed=None, scene=None):
    return [x[2] for x in compared(path, stage, method, scene) if missed is None or (not x[3]) == missed]


def verdicts(stage, method, path=MVM):
    return [x[3] for x in compared(path, stage, method)]


def band(stage, method, path=MVM, missed=None, scene=None):
    r = ratios(stage, method, path, missed, scene)
    return min(r), max(r)


def summary(path, stage):
    r = ratios(stage, r".*", path)
    return sum(verdicts(stage, r".*", path)), len(r), min(r), max(r)


def within_all(path):
    return sum(summary(path, s)[0] for s in STAGES)


def gap(tile, k):
    """measured - modeled ms of a sweep pass in model-vs-measured.md."""
    ((measured, model, _, _),) = compared(MVM, "gen", re.escape(SWEEP.format(tile, k)))
    return measured - model


def moved():
    """The sweep passes the term moved: (how many within ±25%, how many)."""
    before, after = modeled(f"{BEFORE}/prediction-a26f7f6.csv"), modeled(f"{L}/prediction-a26f7f6.csv")
    names = [k[2] for k in before if abs(before[k] - after[k]) > 1e-9]
    return sum(verdicts("gen", re.escape(n))[0] for n in names), len(names)


def source_constant(path, name, occurrence=0):
    return int(float(re.findall(rf"{re.escape(name)} = ([\d.]+)", (ROOT / path).read_text())[occurrence]))


def dram_latency():
    """The h100 preset's DRAM latency, written as the L2's plus the DRAM's (simt/gpu_presets.cpp)."""
    a, b = re.findall(r"g.dram_latency = (\d+) \+ (\d+);", (ROOT / "simt/gpu_presets.cpp").read_text())[1]
    return int(a) + int(b)


def registers(kernel, revision="head"):
    text = (ROOT / f"{L}/registers-sm_90.txt").read_text()
    return int(re.search(rf"^{revision}\s+{re.escape(kernel)}\s+registers\s+(\d+)", text, re.M).group(1))


def resident(threads, regs, unit=256, regs_per_sm=65536, max_warps=64, max_blocks=32):
    """The CUDA occupancy rule of simt/stage_latency.cpp (shared memory never binds these kernels)."""
    warps = math.ceil(threads / 32)
    warp_regs = math.ceil(regs * 32 / unit) * unit
    return min(max_blocks, max_warps // warps, regs_per_sm // (warps * warp_regs))


def key_residents():
    kinds = ("origin", "reis", "costa", "aila", "twopoint", "mlhcc")
    blocks = [resident(256, registers(f"key_kernel<{k},u32>")) for k in kinds]
    return min(blocks), max(blocks)


NCU = "results/stages/h200-6ebd003/ncu-stages.log.xz"
NOOPT_LAUNCH, GROUP_LAUNCH = 1, 7  # the log's first noopt_kernel and group_kernel launches
GROUP_MISS = r"(ours|contiguous).*"
MLHCC = r"noopt\+mlhcc"
NOOPT = r"noopt.*"
DEFAULT = r"ours|ours:order=group|contiguous"

CHECKS = [Figure(README, f"| {t} | {k} | {{:.4f}} | {{:.4f}} | {{:.4f}} |", lambda t=t, k=k: sweep_row(t, k))
          for t in TILES for k in (8, 16, 32, 64)]
CHECKS += [
    Generated(MVM, ["scripts/stage_model_check.py", "compare", "--trip-counts", "--noopt-path", "--latency", "--ncu",
                    NCU_LOG, "prediction-a26f7f6.csv", *MEASURED], cwd=L),
    Embedded(README, MVM, "Summary of `model-vs-measured.md`"),
    Figure(README, "| dependent ALU latency | {} cycles |", lambda: source_constant("simt/stage_model.cpp",
                                                                                   "c.alu_latency")),
    Figure(README, "| shared-memory load | {} cycles |", lambda: source_constant("simt/stage_model.cpp",
                                                                                "c.shared_latency")),
    Figure(README, "(`-gpgpu_smem_latency {}`, ALU {}), the rtx3060 preset's", lambda: (
        source_constant("simt/stage_model.cpp", "c.shared_latency", 1),
        source_constant("simt/stage_model.cpp", "c.alu_latency", 1))),
    Figure(README, "| L1 hit / L2 hit / DRAM | {} / {} / {} cycles |", lambda: (
        source_constant("simt/gpu_presets.cpp", "g.l1_latency", 1),
        source_constant("simt/gpu_presets.cpp", "g.l2_latency", 1), dram_latency())),
    Figure(README, "| shared memory per SM | {} KB (sm_90), {} KB (sm_86) |", lambda: (
        int(re.findall(r"c.shared_per_sm = (\d+) \* 1024", (ROOT / "simt/stage_model.cpp").read_text())[0]),
        int(re.findall(r"c.shared_per_sm = (\d+) \* 1024", (ROOT / "simt/stage_model.cpp").read_text())[1]))),
    Figure(README, "the group kernel {} blocks on 8×8 tiles, {} on 16×8, {} on 16×16 and 32×8 ({} registers); noopt "
           "{} ({} registers, a26f7f6) or {} ({}, HEAD); the key kernels {} to {} blocks of 256 threads", lambda: (
               resident(64, registers("group_kernel")), resident(128, registers("group_kernel")),
               resident(256, registers("group_kernel")), registers("group_kernel"),
               resident(64, registers("noopt_kernel", "a26")), registers("noopt_kernel", "a26"),
               resident(64, registers("noopt_kernel")), registers("noopt_kernel"), *key_residents())),
    Figure(README, "The term changes {} of the {} stages", changed),
    Figure(README, "({:.3f}–{:.3f} ms at k = 64:", lambda: (
        min(terms(SWEEP.format(t, 64), "gen_latency_ms") for t in TILES),
        max(terms(SWEEP.format(t, 64), "gen_latency_ms") for t in TILES))),
    Figure(README, "(sibenik {:.4f} against {:.4f} ms; country_kitchen {:.4f} against {:.4f} ms)", lambda: (
        terms("ours", "gen_latency_ms"), terms("ours", "gen_issue_ms"),
        terms("ours", "gen_latency_ms", "country_kitchen"), terms("ours", "gen_issue_ms", "country_kitchen"))),
    Figure(README, "of 8 warps gives {:.3f}–{:.3f} ms, under its issue term (the stage {:.3f}–{:.3f} ms)", lambda: (
        min(terms_all(MLHCC, "key_latency_ms")), max(terms_all(MLHCC, "key_latency_ms")),
        min(x[1] for x in compared(MVM, "key", MLHCC)), max(x[1] for x in compared(MVM, "key", MLHCC)))),
    Figure(README, "**noopt does not move**: {:.3f}–{:.3f} ms, under its bytes ({:.3f} ms)", lambda: (
        min(terms_all(NOOPT, "gen_latency_ms")), max(terms_all(NOOPT, "gen_latency_ms")),
        max(terms_all(NOOPT, "gen_dram_ms")))),
    Figure(README, "the 14 stages the term moves are the a26f7f6 forecast's within {:.1%}", lambda:
           math.ceil(head_vs_a26() * 1000) / 1000),
]

# The comparison.
CHECKS += [Figure(README, f"| {s} | {{}} of {{}} | {{}} of {{}} | {{:.2f}} … {{:.2f}} |", lambda s=s: (
    *summary(BEFORE_MVM, s)[:2], *summary(MVM, s)[:2], *summary(BEFORE_MVM, s)[2:])) for s in STAGES]
CHECKS += [
    Figure(README, "| all | {} of 104 | {} of 104 | |", lambda: (within_all(BEFORE_MVM), within_all(MVM))),
    Figure(README, "**The sweep's large tiles and large k now agree: {} of the {} stages the term moved are within "
           "±25%** (16×8 at every k, {:.2f}–{:.2f}; k = 64 on every tile, {:.2f}–{:.2f}; 16×16 at k = 8, {:.2f})",
           lambda: (*moved(), *band("gen", r"ours:tile=16x8,.*"), *band("gen", r"ours:tile=.*,k=64,.*"),
                    ratios("gen", re.escape(SWEEP.format("16x16", 8)))[0])),
    Figure(README, "The group kernel's misses fall from {} stages ({:.2f}–{:.2f}) to {} ({:.2f}–{:.2f})", lambda: (
        len(ratios("gen", GROUP_MISS, BEFORE_MVM, True)), *band("gen", GROUP_MISS, BEFORE_MVM, True),
        len(ratios("gen", GROUP_MISS, MVM, True)), *band("gen", GROUP_MISS, MVM, True))),
    Figure(README, "on 32×8 at k = 64 the model goes from {:.2f} to {:.2f} of the measured time", lambda: (
        ratios("gen", re.escape(SWEEP.format("32x8", 64)), BEFORE_MVM)[0],
        ratios("gen", re.escape(SWEEP.format("32x8", 64)))[0])),
    Figure(README, "**What stays missed in the group kernel does not grow with k** ({} stages, {:.2f}–{:.2f}): the "
           "default passes (8×8, k = 8: `ours`, `ours:order=group`, `contiguous` on sibenik and conference, "
           "{:.2f}–{:.2f})", lambda: (len(ratios("gen", GROUP_MISS, missed=True)), *band("gen", GROUP_MISS,
                                                                                          missed=True),
                                       min(ratios("gen", DEFAULT, scene="sibenik") +
                                           ratios("gen", DEFAULT, scene="conference")),
                                       max(ratios("gen", DEFAULT, scene="sibenik") +
                                           ratios("gen", DEFAULT, scene="conference")))),
    Figure(README, "At k = 8 the measured time exceeds the modeled one by {:.3f}, {:.3f}, {:.3f}, {:.3f} ms on 8×8, "
           "16×8, 16×16 and 32×8 tiles; at k = 64 by {:.3f}, {:.3f}, {:.3f}, {:.3f} ms", lambda: (
               *(gap(t, 8) for t in TILES), *(gap(t, 64) for t in TILES))),
    Figure(README, "(Nsight Compute has the group kernel's L1/TEX at {:.0f}%, noopt's at {:.0f}%)", lambda: (
        ncu(NCU, GROUP_LAUNCH, "L1/TEX Cache Throughput"), ncu(NCU, NOOPT_LAUNCH, "L1/TEX Cache Throughput"))),
    Figure(README, "noopt on the same 8×8 tiles misses by {:.3f} ms", lambda: (lambda x: x[0] - x[1])(
        compared(MVM, "gen", re.escape("noopt:order=tile,tile=8x8"))[0])),
    Figure(README, "8×8 is the exception ({:.3f} ms at k = 64): there the latency and issue terms are close ({:.3f} "
           "against {:.3f} ms at k = 64, {:.3f} against {:.3f} at k = 16", lambda: (
               gap("8x8", 64), terms(SWEEP.format("8x8", 64), "gen_latency_ms"),
               terms(SWEEP.format("8x8", 64), "gen_issue_ms"), terms(SWEEP.format("8x8", 16), "gen_latency_ms"),
               terms(SWEEP.format("8x8", 16), "gen_issue_ms"))),
    Figure(README, "**MLHCC's key on sibenik still misses ({:.2f})**: the walk's latency term is {:.3f} ms against a "
           "key stage of {:.3f} ms", lambda: (ratios("key", MLHCC, scene="sibenik")[0],
                                             terms("noopt+mlhcc", "key_latency_ms"),
                                             compared(MVM, "key", MLHCC, "sibenik")[0][1])),
    Figure(README, "(its time is {:.3f} ms measured)", lambda: compared(MVM, "key", MLHCC, "sibenik")[0][0]),
    Figure(README, "**noopt generation ({} stages, {:.2f}–{:.2f}) and costa's gather ({}, {:.2f}–{:.2f}) are "
           "unchanged**: noopt's latency term ({:.3f}–{:.3f} ms) is under its bytes ({:.3f} ms)", lambda: (
               len(ratios("gen", NOOPT)), *band("gen", NOOPT), len(ratios("permute", r"noopt\+costa")),
               *band("permute", r"noopt\+costa"), min(terms_all(NOOPT, "gen_latency_ms")),
               max(terms_all(NOOPT, "gen_latency_ms")), max(terms_all(NOOPT, "gen_dram_ms")))),
    Figure(README, "**country_kitchen's three group generations still agree ({:.2f}–{:.2f}), for the reason given "
           "before** (every warp counted with a lane off the all-diffuse path): their latency term ({:.3f} ms) is "
           "under their issue term ({:.3f} ms)", lambda: (
               *band("gen", GROUP_MISS, scene="country_kitchen"), terms("ours", "gen_latency_ms", "country_kitchen"),
               terms("ours", "gen_issue_ms", "country_kitchen"))),
    Figure(README, "(gen {} → {}, all {} → {} of 104)", lambda: (
        summary(BEFORE_MVM, "gen")[0], summary(MVM, "gen")[0], within_all(BEFORE_MVM), within_all(MVM))),
]
