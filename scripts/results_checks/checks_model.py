"""results/model/*/README.md: the `simt` model (MODELED) beside measured and simulated runs."""
from results_checks import checks_gpu as gpu
from results_checks import checks_ncu as ncu_n
from results_checks.checks_ncu import launch, per_ray
from results_checks.core import Embedded, Figure, Unrecorded, render
from results_checks.logs import ncu, text_lines
from results_checks.rows import ROOT, lo_hi, load, method_of, pct, rate, speedup, total

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


GS = "results/model/gpgpusim/"
H41 = "results/gpu/h100-41d9445/"
H9B = "results/gpu/h100-9bc790a/"


def cells(waves=None, size=None, method=None):
    """cells.csv rows (secondary rays unless `method` names one): waves (lo, hi) bounds, a size or a method."""
    out = [r for r in load(GS + "cells.csv") if (r["method"] != "primary" if method is None else r["method"] == method)]
    if waves:
        out = [r for r in out if waves[0] <= float(r["waves"]) < waves[1]]
    if size:
        out = [r for r in out if r["size"] == size]
    return out


def error_cell(rows, within=None, bold=False):
    """'a … b' of error_now over `rows`, with how many lie within ±`within`."""
    lo, hi = lo_hi(float(r["error_now"]) for r in rows)
    text = f"{render('{:+.0%} … {:+.0%}', (lo, hi))}"
    if within is not None:
        text += f", {sum(abs(float(r['error_now'])) <= within for r in rows)}"
    return text


def h100_full():
    """(file, scene, method) of every measured trace beside the MODELED one once the H100 is full: the three scenes
    at 1080p (../gpu/h100-41d9445) and sibenik from 960x540 up (../gpu/h100-9bc790a)."""
    out = [(f, "sibenik", m) for f, m in gpu.sibenik_cells("h100-41d9445")]
    scenes = H41 + "table-scenes.csv"
    out += [(scenes, s, m) for s in ("conference", "country_kitchen")
            for m in ("primary", "noopt", "ours", "ours:order=group", "contiguous")]
    for res in ("960x540", "1920x1080"):
        f = H9B + f"scaling-{res}.csv"
        out += [(f, "sibenik", m) for m in sorted({method_of(r) for r in load(f) if r["scene"] == "sibenik"})]
    return out


HISTORY = "the earlier rows were computed on the cells of their time"
STEP_ROWS = ("| step | commit | ≥ 4 waves (28 cells; 36 in the last row) | 1.3–3.7 waves (12) | 32×24 (24) |",
             "| as designed | df6083a | −54% … −44%, 0 within ±20% | −61% … −50% | −85% … −66% | 23/23 within ±10% |",
             "| + launch latency (cfg:11) | cb8922b | −54% … −42%, 0 | −58% … −47% | −77% … −60% | 23/23 |",
             "| + L1 bank rule (`l1_banks=4`) | 02e2544 | −46% … −11%, 22 | −51% … −32% | −76% … −54% | 23/23 |",
             "| + PTX step costs | 130c525 | −37% … −5%, 22 | −43% … −27% | −75% … −52% | 23/23 |")


def l1_model(batch):
    return ncu_n.modeled(batch, "modeled_l1_wavefronts_per_ray")


def gpgpusim():
    readme = GS + "README.md"
    full, mid, small = cells((4, 1e9)), cells((1, 4)), cells(size="32x24")
    others = [r for r in full if r["method"] != "noopt"]
    below = [r for r in cells((0, 1)) if r["method"] != "noopt"]
    cornell = [r for r in cells() if (r["scene"], r["size"]) == ("cornell", "224x128")]
    noopt_small = {r["scene"]: float(r["error_now"]) for r in cells(size="32x24", method="noopt")}
    ncu41 = H41 + "ncu.log"
    return [
        Embedded(readme, GS + "table.md", "Repeatability (the same batch traced again", prefix="- "),
        Figure(readme, "| + in-order PTX issue | 5e7e66b | **{} of {}** | {} | **{}** | {}/{} ({}) |", lambda: (
            error_cell(full, 0.2), len(full), error_cell(mid, 0.2), error_cell(small, 0.2),
            sum(abs(float(r["ratio_error_now"])) <= 0.1 for r in others), len(others),
            render("{:+.0%} … {:+.0%}", lo_hi(float(r["ratio_error_now"]) for r in others)))),
        Figure(readme, "cornell 224×128 ({:.1f} waves, the one issue-bound scene): {}", lambda: (
            float(cornell[0]["waves"]), error_cell(cornell))),
        Figure(readme, "Below one wave, sibenik's and country_kitchen's noopt ({:+.0%}, {:+.0%})", lambda: (
            noopt_small["sibenik"], noopt_small["country_kitchen"])),
        Figure(readme, "Ratios below one wave differ by up to {:+.0%}", lambda: min(
            float(r["ratio_error_now"]) for r in below)),
        Figure(readme, "Once the GPU is full the hardware takes {:.1f}–{:.1f}× the model's time", lambda: lo_hi(
            gpu.too_fast(f, s, m) for f, s, m in h100_full())),
        Figure(readme, "keeps the model's ratios to noopt ({:+.0%} … {:+.0%})", lambda: lo_hi(
            gpu.trace_miss(f, s, m) for f, s, m in h100_full() if m != "noopt")),
        Figure(readme, "the hardware's L1 wavefronts per ray are about {:.1f}–{:.1f}× the model's count", lambda: lo_hi(
            gpu.too_fast(f, "sibenik", m) for f, m in gpu.sibenik_cells("h100-41d9445"))),
        Figure(readme, "{:.0f} M L1 LSU wavefronts for sibenik noopt's 1080p batch, at least {:.2f}× the {:.0f} M the model's "
               "timeline can hold (one per SM and cycle over its modeled {:.3f} ms)", lambda: (
                   ncu_n.counted("noopt", "data") / 1e6, ncu_n.counted("noopt", "data") / ncu_n.most_modeled("noopt"),
                   ncu_n.most_modeled("noopt") / 1e6, ncu_n.modeled("noopt", "modeled_ms"))),
        Figure(readme, "{:.1f} per ray against the hardware's {:.1f} for noopt ({:.2f}×), {:.1f} against {:.1f} for ours "
               "({:.2f}×), but {:.1f} against {:.1f} for the coherent camera rays; local memory differs little ({:.1f} "
               "modeled, {:.1f} requests measured)", lambda: (
                   *(v for b in ("noopt", "ours") for v in (l1_model(b), ncu_n.ray_count(b, "data"),
                                                             ncu_n.ray_count(b, "data") / l1_model(b))),
                   l1_model("primary"), ncu_n.ray_count("primary", "data"),
                   ncu_n.modeled("noopt", "modeled_l1_local_wavefronts_per_ray"),
                   ncu_n.ray_count("noopt", "local_ld", "local_st"))),
        Figure(readme, "rule undercounts by about {:.2f}×", lambda: ncu_n.undercount()),
        Figure(readme, "(the H100 needs {:.1f}× the model's wavefronts for divergent loads)", lambda: ncu_n.ray_count(
            "noopt", "data") / l1_model("noopt")),
        Unrecorded(readme, "the model then was 1.7–2.2× faster than the simulator once the GPU was full and 2.5–4.3× "
                   "below one wave, with ratios to noopt already within ±3% at ≥ 4 waves", HISTORY),
        Unrecorded(readme, "whose gap (1.7–2.2×)", HISTORY),
        *(Unrecorded(readme, row, HISTORY) for row in STEP_ROWS),
        Figure(readme, "puts the BVH2 kernel at {:.1f}% of L1/TEX throughput (noopt, sibenik) with the SM issue at {:.0f}%",
               lambda: (ncu(ncu41, 2, "L1/TEX Cache Throughput"), ncu(ncu41, 2, "Issue Slots Busy"))),
    ]


def kernel_counters(path):
    """Per kernel of a GPGPU-Sim log (launch order): its gpu_sim_cycle and the cumulative counters that follow it
    (L1D_total_cache_accesses, the issue breakdown's Stall / W0_Idle / W0_Scoreboard / W1..W32 line)."""
    out = []
    for line in text_lines(path):
        line = line.strip()
        if line.startswith("gpu_sim_cycle = "):
            out.append({"cycles": int(line.split("=")[1])})
        elif line.startswith("L1D_total_cache_accesses = ") and out:
            out[-1]["l1_accesses"] = int(line.split("=")[1])
        elif line.startswith("Stall:") and out:
            out[-1]["issue"] = {k: int(v) for k, v in (cell.split(":") for cell in line.split())}
    return out


def l1_rate(cell):
    """noopt's L1 accesses per SM and cycle in a cell's `gen` run: its kernel is the third (primary warm-up,
    primary, noopt), the counter cumulative."""
    kernels = kernel_counters(GS + f"runs/{cell['scene']}_{cell['size']}_sms{cell['sms']}_gen.kernels.txt")
    return (kernels[2]["l1_accesses"] - kernels[1]["l1_accesses"]) / (int(cell["sms"]) * kernels[2]["cycles"])


def memory_stall_share():
    """The share of noopt's scheduler cycles (every slot of the issue breakdown) that stalled with an instruction
    ready (`Stall`: the memory pipeline full), cornell 224×128: its kernel is the third, the counters cumulative."""
    k = kernel_counters(GS + "issue_breakdown_cornell_224x128_noopt.txt")
    delta = {name: k[2]["issue"][name] - k[1]["issue"][name] for name in k[2]["issue"]}
    return delta["Stall"] / sum(delta.values())


def gpgpusim_counters():
    readme = GS + "README.md"
    return [
        Figure(readme, "The simulator's own counters agree: {:.2f}–{:.2f} L1 accesses per SM and cycle in every ≥ 4-wave "
               "noopt kernel", lambda: lo_hi(l1_rate(c) for c in cells((4, 1e9), method="noopt"))),
        Figure(readme, "show {:.0%} of cycles waiting on the memory pipeline", memory_stall_share),
    ]


CHECKS += gpgpusim() + gpgpusim_counters()
