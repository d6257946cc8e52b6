"""results/model/*/README.md: the `simt` model (MODELED) beside measured and simulated runs."""
from results_checks.checks_ncu import launch, per_ray
from results_checks.core import Figure
from results_checks.logs import ncu
from results_checks.rows import ROOT, lo_hi, pct, rate, speedup, total

L1 = "results/model/h100-l1-rule/"
MEASURED = "results/gpu/h100-6f75752/"
SECONDARY = ("noopt", "ours", "ours:order=group", "contiguous")
SCENES = ("sibenik", "conference", "country_kitchen")


def md_rows(path):
    """The rows of a generated Markdown table (checked itself by regenerating it) as lists of cells."""
    rows = []
    for line in (ROOT / path).read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("|") and not set(line) <= set("|-: ") and cells[0] != "scene":
            rows.append(cells)
    return rows


def vs(scene=None, methods=SECONDARY, bvh="bvh2"):
    """model_vs_measured.md rows: scene, method, BVH, measured ms, before, ÷, now, ÷, limiter, ×noopt m, × now."""
    return [r for r in md_rows(L1 + "model_vs_measured.md")
            if (scene is None or r[0] == scene) and r[1] in methods and r[2] == bvh]


def ratio_range(rows, column):
    return lo_hi(float(r[column]) for r in rows if r[column] != "–")


def miss_now(rows):
    return lo_hi(float(r[10]) / float(r[9]) - 1 for r in rows if r[1] != "noopt")


def miss_before(scene):
    """The measured run's own simt rows (the earlier rule): MODELED ratio to noopt over the measured one, minus 1,
    first row of each method winning over the run's files as in model_vs_measured.py."""
    files = [MEASURED + f for f in ("table-comparison.csv", "table-group.csv", "table-scenes.csv")]

    def first(method, tracer, field):
        for f in files:
            try:
                return total(f, field, scene, method, tracer)
            except LookupError:
                continue
        raise LookupError(method)
    base_m, base_s = first("noopt", "cuda", "trace_ms"), first("noopt", "simt", "modeled_ms")
    return lo_hi((base_s / first(m, "simt", "modeled_ms")) / (base_m / first(m, "cuda", "trace_ms")) - 1
                 for m in SECONDARY[1:])


def l1_rule_row(readme, scene, label):
    return Figure(readme, f"| {label} | {{:.2f}}–{{:.2f}} | {{}}{{:.2f}}–{{:.2f}}{{}} | {{:+.0%}} … {{:+.0%}} | "
                  f"{{:+.0%}} … {{:+.0%}} |", lambda: (
                      *ratio_range(vs(scene), 5), "**" if scene == "sibenik" else "", *ratio_range(vs(scene), 7),
                      "**" if scene == "sibenik" else "", *miss_before(scene), *miss_now(vs(scene))))


def h100_l1_rule():
    readme = L1 + "README.md"
    scenes = MEASURED + "table-scenes.csv"
    group = MEASURED + "table-group.csv"
    model = L1 + "model-sibenik.csv"

    def wavefronts(method, tracer, field="modeled_l1_wavefronts_per_ray"):
        return total(model, field, "sibenik", method, tracer)

    def spread(method):
        return pct(total(scenes, "trace_ms", "country_kitchen", method), total(scenes, "trace_ms_min",
                                                                                "country_kitchen", method))

    def fastest(method):
        return (total(scenes, "trace_ms_min", "country_kitchen", "noopt") /
                total(scenes, "trace_ms_min", "country_kitchen", method))
    others = [float(r[10]) / float(r[9]) - 1 for r in vs() if r[1] != "noopt"
              and (r[0], r[1]) != ("country_kitchen", "ours:order=group")]
    return [
        l1_rule_row(readme, "sibenik", "sibenik (noopt, ours, group, contiguous)"),
        l1_rule_row(readme, "conference", "conference"),
        l1_rule_row(readme, "country_kitchen", "country_kitchen"),
        Figure(readme, "| camera rays | {:.2f}–{:.2f} | {:.2f}–{:.2f} |", lambda: (
            *ratio_range(vs(methods=("primary",)), 5), *ratio_range(vs(methods=("primary",)), 7))),
        Figure(readme, "on sibenik are now {:.1f} (noopt), {:.1f} (ours) and {:.1f} (camera rays)", lambda: (
            wavefronts("noopt", "simt"), wavefronts("ours", "simt"), wavefronts("primary", "simt"))),
        Figure(readme, "most of the missing time is found on sibenik ({:.2f}–{:.2f})", lambda: ratio_range(
            vs("sibenik"), 7)),
        Figure(readme, "(conference {:.2f}–{:.2f}, camera rays {:.2f}–{:.2f})", lambda: (
            *ratio_range(vs("conference"), 7), *ratio_range(vs(methods=("primary",)), 7))),
        Figure(readme, "over-predicts the coherence gains by {:.0f}–{:.0%} ({:.0%} for country_kitchen's group order)",
               lambda: (100 * lo_hi(others)[0], lo_hi(others)[1], *miss_now(vs("country_kitchen",
                                                                             ("ours:order=group",)))[1:])),
        Figure(readme, "where the old rule was within {:+.0%} … {:+.0%}", lambda: lo_hi(
            v for s in SCENES for v in miss_before(s))),
        Figure(readme, "country_kitchen's group order {:.3f}× noopt against tile order's {:.3f}× (medians of 5 traces",
               lambda: (speedup(scenes, "country_kitchen", "ours:order=group"),
                        speedup(scenes, "country_kitchen", "ours"))),
        Figure(readme, "whose median lies {:.1%} (group order) and {:.1%} (tile order) above their fastest trace; on the "
               "fastest traces the two are {:.3f}× and {:.3f}×", lambda: (
                   spread("ours:order=group"), spread("ours"), fastest("ours:order=group"), fastest("ours"))),
        Figure(readme, "**CWBVH** (`bvh=cwbvh`, issue-bound in the model and on hardware): {:.2f}–{:.2f} of the "
               "measured time", lambda: ratio_range(vs(methods=("primary",) + SECONDARY, bvh="cwbvh"), 7)),
        Figure(readme, "CWBVH ÷ BVH2 speed on sibenik noopt is {:.2f}× against the {:.2f}× measured", lambda: (
            total(model, "modeled_ms", "sibenik", "noopt", "simt") / total(model, "modeled_ms", "sibenik", "noopt",
                                                                           "simt:cwbvh"),
            rate(group, "sibenik", "noopt", "cuda:cwbvh") / rate(group, "sibenik", "noopt", "cuda"))),
        Figure(readme, "The model counts {:.1f} L1 wavefronts per ray ({:.1f} of them local)", lambda: (
            wavefronts("noopt", "simt:cwbvh"), wavefronts("noopt", "simt:cwbvh", "modeled_l1_local_wavefronts_per_ray"))),
    ]


def l1_work():
    """The L1 wavefronts per ray now and with the old rule (the model's columns of gpu/h100-9bc790a-ncu/model.csv)
    beside Nsight Compute's (gpu/h100-9566ba3/counts-*.log), and the CWBVH kernel's issue slots."""
    readme, model, old = L1 + "README.md", L1 + "model-sibenik.csv", "results/gpu/h100-9bc790a-ncu/model.csv"
    field, data = "modeled_l1_wavefronts_per_ray", "l1tex__data_pipe_lsu_wavefronts.sum"
    local = ("l1tex__t_requests_pipe_lsu_mem_local_op_ld.sum", "l1tex__t_requests_pipe_lsu_mem_local_op_st.sum")
    batches = ("noopt", "ours", "primary")

    def measured(batch, kernel="bvh2", *metrics):
        return per_ray(kernel, batch, *(metrics or (data,)))

    def modeled(path, batch):
        return total(path, field, "sibenik", batch, "simt")
    miss = [float(r[10]) / float(r[9]) - 1 for r in vs("country_kitchen", ("ours:order=group",))]
    return [
        Figure(readme, "against Nsight Compute's {:.1f}, {:.1f} and {:.1f} on the hardware", lambda: tuple(
            measured(b) for b in batches)),
        Figure(readme, "the same figures as in `../../gpu/h100-9bc790a-ncu/`): {:.2f}×, {:.2f}× and {:.2f}×, where the "
               "old rule gave {:.2f}×, {:.2f}× and {:.2f}×", lambda: (
                   *(modeled(model, b) / measured(b) for b in batches),
                   *(modeled(old, b) / measured(b) for b in batches))),
        Figure(readme, "Not tuned: a stated miss. The {:.0%} is measured against one run's medians", lambda: miss[0]),
        Figure(readme, "so the {:.0%} is not a property of group order", lambda: miss[0]),
        Figure(readme, "where the hardware does {:.1f} ({:.1f} local requests)", lambda: (
            measured("noopt", "cwbvh"), measured("noopt", "cwbvh", *local))),
        Figure(readme, "its issue slots are {:.0f}% busy on hardware", lambda: ncu(
            "results/gpu/h100-6f75752/ncu-cwbvh.log", launch("noopt"), "Issue Slots Busy")),
    ]


CHECKS = h100_l1_rule() + l1_work()
