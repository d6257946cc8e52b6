"""results/model/stage-trip-counts/README.md: the stage model with trip-counted instructions (the group kernel per
path, MLHCC's cut walks). Its tables and every figure its prose quotes, recomputed from the committed predictions
(prediction-a26f7f6.csv, prediction.csv, and ../stage-l1-term/prediction-stages.csv for the model before), the
walk counts (mlhcc-walks.csv), the comparison the check makes again (model-vs-measured.md, from
prediction-a26f7f6.csv and the measured H200 rows) and the instruction counts."""
import re

from results_checks.checks_stages import MEASURED, NCU_LOG
from results_checks.core import Embedded, Figure, Generated
from results_checks.checks_stage_l1 import noopt_ncu
from results_checks.rows import ROOT, load, median

T = "results/model/stage-trip-counts"
README = f"{T}/README.md"
STATIC = "results/model/stage-l1-term/prediction-stages.csv"
SWEEP_8 = "ours:tile=8x8,k={},order=tile"
FILES = {"ours": "stages-{}.csv", "noopt": "stages-{}-encoders.csv", "noopt+mlhcc": "stages-{}-encoders.csv"}


def modeled(path, scene, method, stage):
    """The modeled ms of one stage in a prediction CSV (a sweep method from stages-sweep.csv)."""
    name = "stages-sweep.csv" if method.startswith("ours:") else FILES[method].format(scene)
    (row,) = [r for r in load(path) if r["file"] == name and r["scene"] == scene and r["method"] == method and
              r["stage"] == stage]
    return float(row["modeled_ms"])


def table_row(scene, method, stage):
    return tuple(modeled(p, scene, method, stage) for p in (STATIC, f"{T}/prediction-a26f7f6.csv",
                                                             f"{T}/prediction.csv"))


def walks(column):
    """(lowest, highest) of a column of mlhcc-walks.csv, and the dict scene -> value."""
    values = {r["scene"]: float(r[column]) for r in load(f"{T}/mlhcc-walks.csv")}
    return min(values.values()), max(values.values()), values


def count(path, kernel):
    """A kernel's instruction count in a count-stage-instructions / count-stage-paths output."""
    text = (ROOT / path).read_text()
    if "group_kernel SASS by region" in text:
        return int(re.search(r"by region, (\d+) instructions", text).group(1))
    return int(re.search(rf"^{kernel}\s+instructions\s+(\d+)", text, re.M).group(1))


def loop_bodies(kernel="key mlhcc"):
    text = (ROOT / "results/model/h200-stages/instructions-sm_90.txt").read_text()
    return tuple(int(x) for x in re.search(rf"^{kernel}\s.*loop bodies: ([\d, ]+)", text, re.M).group(1).split(", "))


def permute_mb(encoder, scene="conference"):
    (row,) = [r for r in load(f"results/stages/h200-a26f7f6/stages-{scene}-encoders.csv")
              if r["pass"] == "secondary" and r.get("pipeline") == "device" and r["encoder"] == encoder]
    return float(row["modeled_permute_bytes"]) / 1e6


def compared(path, stage, method, scene=None):
    """A model-vs-measured.md's rows of `stage` whose method matches `method`: (measured, modeled, ratio)."""
    out = []
    for line in (ROOT / path).read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 7 and cells[2] == stage and re.fullmatch(method, cells[1]) and scene in (None, cells[0]):
            out.append((float(cells[3]), float(cells[4]), float(cells[5])))
    return out


MVM = f"{T}/model-vs-measured.md"
BEFORE = "results/model/stage-l1-term/model-vs-measured.md"


def ratios(stage, method, scene=None, path=MVM, missed=None):
    r = [x[2] for x in compared(path, stage, method, scene)]
    return [x for x in r if missed is None or (abs(x - 1) > 0.25) == missed]


def band(stage, method, scene=None, path=MVM, missed=None):
    r = ratios(stage, method, scene, path, missed)
    return min(r), max(r)


def sweep(tile):
    return tuple(ratios("gen", re.escape(f"ours:tile={tile},k={k},order=tile"))[0] for k in (8, 16, 32, 64))


def summary(path, stage):
    """(count within, count, lowest, highest) of a stage in a model-vs-measured.md."""
    r = ratios(stage, r".*", path=path)
    return sum(abs(x - 1) <= 0.25 for x in r), len(r), min(r), max(r)


def within_all(path):
    return sum(abs(x - 1) <= 0.25 for s in ("gen", "key", "sort", "permute") for x in ratios(s, r".*", path=path))


GROUP = r"(ours|contiguous).*"
MLHCC = r"noopt\+mlhcc"

CHECKS = [Figure(README, f"| {s} | {m} | {st} | {{:.4f}} | {{:.4f}} | {{:.4f}} |", lambda s=s, m=m, st=st:
                 table_row(s, m, st))
          for s, m, st in (("sibenik", "ours", "gen"), ("conference", "ours", "gen"),
                           ("country_kitchen", "ours", "gen"), ("sibenik", SWEEP_8.format(64), "gen"),
                           ("sibenik", "ours:tile=32x8,k=8,order=tile", "gen"), ("sibenik", "noopt", "gen"),
                           ("conference", "noopt+mlhcc", "key"), ("country_kitchen", "noopt+mlhcc", "key"),
                           ("sibenik", "noopt+mlhcc", "key"))]

CHECKS += [
    Generated(MVM, ["scripts/stage_model_check.py", "compare", "--trip-counts", "--ncu", NCU_LOG,
                    "prediction-a26f7f6.csv", *MEASURED], cwd=T),
    Embedded(README, MVM, "Summary of `model-vs-measured.md`"),
    Figure(README, "({} instructions for the a26f7f6 kernels, {} since 63b5750)", lambda: (
        count(f"{T}/group-paths-before-sm_90.txt", "group"), count(f"{T}/group-paths-sm_90.txt", "group")),
           "-"),
    Figure(README, "At k = 64 the generation stage is {:.1f}× its k = 8 figure on 8×8 tiles", lambda:
           modeled(f"{T}/prediction-a26f7f6.csv", "sibenik", SWEEP_8.format(64), "gen") /
           modeled(f"{T}/prediction-a26f7f6.csv", "sibenik", SWEEP_8.format(8), "gen")),
    Figure(README, "MLHCC's walks run {:.1f}–{:.1f} (origin) and {:.1f}–{:.1f} (end point) iterations per warp",
           lambda: (*walks("origin_trips")[:2], *walks("end_trips")[:2])),
    Figure(README, "key stage is priced {:.1f}–{:.1f}× the static count's", lambda: (
        min(table_row(s, "noopt+mlhcc", "key")[1] / table_row(s, "noopt+mlhcc", "key")[0]
            for s in ("conference", "country_kitchen", "sibenik")),
        max(table_row(s, "noopt+mlhcc", "key")[1] / table_row(s, "noopt+mlhcc", "key")[0]
            for s in ("conference", "country_kitchen", "sibenik")))),
    Figure(README, "Elsewhere the forecast is the a26f7f6 one less at most {:.1%}", lambda: max(
        1 - table_row(s, m, "gen")[2] / table_row(s, m, "gen")[1]
        for s, m in (("sibenik", "ours"), ("conference", "ours"), ("country_kitchen", "ours"),
                     ("sibenik", SWEEP_8.format(64))))),
    Figure(README, "costa's ({:.0f} MB on conference) equal twopoint's ({:.0f} MB)", lambda: (
        permute_mb("costa"), permute_mb("twopoint"))),
    Figure(README, "each cut walk's loop body once ({} and {} instructions,", loop_bodies, "-"),
    Figure(README, "A warp runs {} + (origin − 1) × {} + (end − 1) × {} instructions", lambda: (
        count("results/model/h200-stages/instructions-sm_90.txt", "key mlhcc"), *loop_bodies()), "-"),
    Figure(README, "gen {} of {} ({:.2f} … {:.2f}), key {} of {} ({:.2f} … {:.2f}), {} of 104", lambda: (
        *summary(BEFORE, "gen"), *summary(BEFORE, "key"), within_all(BEFORE))),
    Figure(README, "**MLHCC's key: {} of 3 now agree (conference {:.2f}, country_kitchen {:.2f}; {:.2f}–{:.2f} "
           "before).**", lambda: (
               len(ratios("key", MLHCC, missed=False)), ratios("key", MLHCC, "conference")[0],
               ratios("key", MLHCC, "country_kitchen")[0], *band("key", MLHCC, path=BEFORE))),
    Figure(README, "the kernel moves from {:.3f} ms to {:.2f}–{:.2f} ms (MODELED), the measured {:.2f}–{:.2f} ms (GPU)",
           lambda: (table_row("sibenik", "noopt+mlhcc", "key")[0],
                    min(x[1] for x in compared(MVM, "key", MLHCC)), max(x[1] for x in compared(MVM, "key", MLHCC)),
                    min(x[0] for x in compared(MVM, "key", MLHCC)),
                    max(x[0] for x in compared(MVM, "key", MLHCC)))),
    Figure(README, "**sibenik ({:.2f}) still misses**: its walks are the deepest ({:.1f} origin iterations a warp "
           "against {:.1f}–{:.1f}) and its measured time the longest by far ({:.2f} ms against {:.2f}–{:.2f} ms)",
           lambda: (ratios("key", MLHCC, "sibenik")[0], walks("origin_trips")[2]["sibenik"],
                    walks("origin_trips")[2]["conference"], walks("origin_trips")[2]["country_kitchen"],
                    compared(MVM, "key", MLHCC, "sibenik")[0][0], compared(MVM, "key", MLHCC, "conference")[0][0],
                    compared(MVM, "key", MLHCC, "country_kitchen")[0][0])),
    Figure(README, "**The group kernel is now under-priced everywhere but on country_kitchen ({} stages, "
           "{:.2f}–{:.2f}; {:.2f}–{:.2f} before).**", lambda: (
               len(ratios("gen", GROUP, missed=True)), *band("gen", GROUP, missed=True),
               *band("gen", GROUP, path=BEFORE, missed=True))),
    Figure(README, "(k = 8, 16, 32, 64 on 8×8: {:.2f}, {:.2f}, {:.2f}, {:.2f}; on 16×8: {:.2f}, {:.2f}, {:.2f}, "
           "{:.2f}; on 32×8: {:.2f}, {:.2f}, {:.2f}, {:.2f}, and 16×16 within {:.2f} of 32×8)", lambda: (
               *sweep("8x8"), *sweep("16x8"), *sweep("32x8"),
               max(abs(a - b) for a, b in zip(sweep("16x16"), sweep("32x8"))))),
    Figure(README, "**country_kitchen's three group generations agree ({:.2f}–{:.2f}), but not for a reason to "
           "trust.**", lambda: band("gen", GROUP, "country_kitchen")),
    Figure(README, "show the form's real error ({:.2f}–{:.2f} at k = 8)", lambda: (
        min(ratios("gen", r"ours|ours:order=group|contiguous", s)[i] for s in ("sibenik", "conference")
            for i in range(3)),
        max(ratios("gen", r"ours|ours:order=group|contiguous", s)[i] for s in ("sibenik", "conference")
            for i in range(3)))),
    Figure(README, "**noopt generation (25 stages, {:.2f}–{:.2f}) and costa's gather (3, {:.2f}–{:.2f}) are "
           "unchanged**", lambda: (*band("gen", r"noopt.*"), *band("permute", r"noopt\+costa"))),
    Figure(README, "The count of stages within ±25% barely moves ({} → {})", lambda: (
        within_all(BEFORE), within_all(MVM))),
]

# The second step: noopt per path (noopt-path/).
NP = f"{T}/noopt-path"
NP_MVM = f"{NP}/model-vs-measured.md"


def noopt_row(scene):
    name = f"stages-{scene}.csv"
    out = []
    for path in (f"{T}/prediction-a26f7f6.csv", f"{NP}/prediction-a26f7f6.csv", f"{NP}/prediction.csv"):
        (row,) = [r for r in load(path) if r["file"] == name and r["method"] == "noopt" and r["stage"] == "gen"]
        out.append(float(row["modeled_ms"]))
    return tuple(out)


def unrolled(forms, trips):
    """simt/stage_paths.cpp unrolled_loop_instructions: forms {unroll: body}, 16x then 4x then 1x."""
    n, left = 0, trips
    for u in (16, 4):
        if forms.get(u):
            n, left = n + (left // u) * forms[u], left % u
    if forms.get(1):
        return n + left * forms[1]
    return n + left * (forms[4] / 4 if forms.get(4) else forms.get(16, 0) / 16)


def diffuse_warp(path=f"{T}/noopt-paths-before-sm_90.txt", warps=2):
    """A warp's path on an all-diffuse scene (8x8 tiles: 2 warps): common (the scan's loop run once per warp of the
    block, the atomic retry loops once each) and the diffuse case; and the static count."""
    text = (ROOT / path).read_text()
    common = re.search(r"^common\s+straight=(\d+) loops=(\S+)", text, re.M)
    families = [{int(u): int(b) for b, u in (form.split("/") for form in fam.split("+"))}
                for fam in common.group(2).split(",")]
    n = int(common.group(1)) + unrolled(families[0], warps) + sum(sum(f.values()) for f in families[1:])
    n += int(re.search(r"^lobe_diffuse\s+straight=(\d+)", text, re.M).group(1))
    return n, int(re.search(r"by region, (\d+) instructions", text).group(1))


NOOPT = r"noopt.*"
CHECKS += [Figure(README, f"| {s} | {{:.4f}} | {{:.4f}} | {{:.4f}} |", lambda s=s: noopt_row(s))
           for s in ("sibenik", "conference", "country_kitchen")]
CHECKS += [
    Generated(NP_MVM, ["scripts/stage_model_check.py", "compare", "--trip-counts", "--noopt-path", "--ncu",
                       "../" + NCU_LOG, "prediction-a26f7f6.csv", *("../" + m for m in MEASURED)], cwd=NP),
    Embedded(README, NP_MVM, "Summary of `noopt-path/model-vs-measured.md`"),
    Figure(README, "diffuse case: {:.0f} of {} instructions a warp on conference with the a26f7f6 kernels",
           diffuse_warp),
    Figure(README, "**noopt generation still misses, further ({} stages, {:.2f}–{:.2f}; {:.2f}–{:.2f} with its "
           "static count).**", lambda: (len(ratios("gen", NOOPT, path=NP_MVM)), *band("gen", NOOPT, path=NP_MVM),
                                        *band("gen", NOOPT))),
    Figure(README, "bytes-bound on sibenik and conference ({:.3f} ms, MODELED) against ~{:.2f} ms measured (GPU)",
           lambda: (noopt_row("sibenik")[1], median([x[0] for x in compared(NP_MVM, "gen", NOOPT)]))),
    Figure(README, "Compute has the kernel at {:.0f}% of its L1/TEX throughput and {:.0f}% of its SM's", lambda: (
        noopt_ncu("L1/TEX Cache Throughput"), noopt_ncu("Compute (SM) Throughput"))),
    Figure(README, "The static count's agreement-looking {:.2f}–{:.2f} was", lambda: band("gen", NOOPT)),
]
