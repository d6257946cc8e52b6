"""results/stages/h200-*/README.md: the counts their prose states about the rows (repeats per median, tiles per
frame). Their stage times are in `stages.md` beside them, which checks_generated.py makes again from the same rows;
the READMEs' comparisons of those times are words, not figures."""
from results_checks.core import Embedded, Figure, Generated
from results_checks.rows import load

S = "results/stages/"


def repeats(run):
    """The one repeat count of every row of the run's sibenik stages (raises when they differ)."""
    (n,) = {int(r["repeats"]) for r in load(f"{S}{run}/stages-sibenik.csv")}
    return n


def tiles(run):
    """8×8 tiles of the frame of the run's ours rows (1920×1080: 32400)."""
    rows = [r for r in load(f"{S}{run}/stages-sibenik.csv") if r["method"] == "ours" and "tile=8x8" in
            r["generator_params"]]
    (n,) = {int(r["width"]) * int(r["height"]) // 64 for r in rows}
    return n


M = "results/model/h200-stages"
MEASURED = [f"../../stages/h200-a26f7f6/stages-{f}.csv" for f in (
    "conference-encoders", "conference", "country_kitchen-encoders", "country_kitchen", "sibenik-encoders", "sibenik",
    "sweep")]
NCU_LOG = "../../stages/h200-6ebd003/ncu-stages.log.xz"

CHECKS = [
    # The stage model beside the measured stages: made again from the committed prediction and rows, and the
    # README's summary table copied from it.
    Generated(f"{M}/model-vs-measured.md", ["scripts/stage_model_check.py", "compare", "--ncu", NCU_LOG,
                                             "prediction.csv", *MEASURED], cwd=M),
    Embedded(f"{M}/README.md", f"{M}/model-vs-measured.md", "Summary of `model-vs-measured.md`"),
    Figure(S + "h200-6ebd003/README.md", "Each time is the median of {} repeats of one frame",
           lambda: repeats("h200-6ebd003")),
    Figure(S + "h200-a26f7f6/README.md", "of {} repeats of one frame", lambda: repeats("h200-a26f7f6")),
    Figure(S + "h200-d31e7d7/README.md", "1920×1080, one frame, {} repeats", lambda: repeats("h200-d31e7d7")),
    Figure(S + "h200-f400a3e/README.md", "`../h200-a26f7f6/` ({} repeats) within a few percent", lambda: (
        repeats("h200-a26f7f6"))),
    Figure(S + "h200-f400a3e/README.md", "Medians of {} repeats of one frame", lambda: repeats("h200-f400a3e")),
    Figure(S + "h200-1a660a1/README.md", "a single-pass look-back over {} tiles of 64 pixels", lambda: (
        tiles("h200-1a660a1"))),
]
