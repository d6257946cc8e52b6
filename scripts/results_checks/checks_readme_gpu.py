"""results/README.md, "What the committed results show": the summary lines of the measured GPU folders (gpu/h100-*,
model/h100-l1-rule) beside the figures their own READMEs quote (the same rows, logs and helpers), the built-in
table's console timings (Unrecorded), the scenes' triangle counts and the `stability.csv` rates reported only."""
from results_checks import checks_gpu as gpu
from results_checks import checks_ncu as ncu_n
from results_checks.checks_ncu import launch, per_ray
from results_checks.core import Figure, Unrecorded
from results_checks.logs import ncu
from results_checks.rows import lo_hi, load, method_of, pct, total

README = "results/README.md"
G = "results/gpu/"


def span(values, spec):
    """'a–b' of `values` formatted by spec, one figure when both ends print alike."""
    lo, hi = (format(v, spec) for v in lo_hi(values))
    return lo if lo == hi else f"{lo}–{hi}"


def stages_41d9445():
    """noopt's generation kernel, the grouping generators' (ours and contiguous at 8×8 to the sweep's largest
    tiles) and CUB's sort after every generator (the h100-41d9445 README's figures), measured ms."""
    _, comp, _, _ = gpu.files("h100-41d9445")
    sweep = G + "h100-41d9445/sweep-sibenik.csv"
    grouping = [m for m in {method_of(r) for r in load(sweep)} if m.startswith("ours:")]
    sorts = [f"{g}+{e}" for g in ("noopt", "ours", "contiguous") for e in gpu.ENCODERS]
    return (gpu.stage(comp, "noopt", "gen_ms"), min(gpu.stage(comp, m, "gen_ms") for m in ("ours", "contiguous")),
            max(gpu.stage(sweep, m, "gen_ms") for m in grouping),
            *lo_hi(gpu.stage(comp, m, "sort_ms") for m in sorts))


def cwbvh_over_bvh2(scene):
    """The CWBVH kernel's trace speed over the BVH2's on noopt (h100-6f75752; sibenik's rows in table-group.csv)."""
    _, comp, group, scenes = gpu.files("h100-6f75752")
    path = group if scene == "sibenik" else scenes
    return total(path, "trace_ms", scene, "noopt", "cuda") / total(path, "trace_ms", scene, "noopt", "cuda:cwbvh")


def c3eba59():
    """The largest trace-time difference of the c3eba59 table from 6f75752's, and 6f75752's two noopt rows."""
    final = G + "h100-c3eba59/table-final.csv"
    before = {m: G + "h100-6f75752/table-comparison.csv" for m in ("noopt", "ours", "contiguous")}
    before["ours:order=group"] = G + "h100-6f75752/table-group.csv"

    def ms(path, method, tracer):
        return total(path, "trace_ms", "sibenik", method, tracer)
    diff = max(abs(pct(ms(final, m, t), ms(p, m, t))) for m, p in before.items() for t in ("cuda", "cuda:cwbvh"))
    noopt = pct(ms(before["noopt"], "noopt", "cuda"), ms(G + "h100-6f75752/table-group.csv", "noopt", "cuda"))
    return diff, noopt


def l1_rule_ratio():
    """The h100-l1-rule model's L1 wavefronts per ray over Nsight Compute's, noopt and ours (sibenik BVH2)."""
    model = "results/model/h100-l1-rule/model-sibenik.csv"
    return span((total(model, "modeled_l1_wavefronts_per_ray", "sibenik", b, "simt")
                 / per_ray("bvh2", b, "l1tex__data_pipe_lsu_wavefronts.sum") for b in ("noopt", "ours")), ".2f")


def gpu_lines():
    log41, log9b = G + "h100-41d9445/ncu.log", G + "h100-9bc790a/ncu-cwbvh.log"
    return [
        Figure(README, "Our generation kernels ({:.2f} ms noopt, {:.2f}–{:.2f} ms grouping) and sort ({:.2f}–{:.2f} "
               "ms)", stages_41d9445),
        Figure(README, "kernel is L1-bound (L1/TEX {:.1f}% of peak)", lambda: ncu(
            log41, launch("noopt"), "L1/TEX Cache Throughput")),
        Figure(README, "the CWBVH kernel is issue-bound ({:.1f}% SM issue) on hardware", lambda: ncu(
            log9b, launch("noopt"), "Issue Slots Busy")),
        Figure(README, "{:.0f} M LSU wavefronts for noopt's batch, at least {:.2f}× the most the model's timeline can "
               "hold", lambda: (ncu_n.counted("noopt", "data") / 1e6,
                                ncu_n.counted("noopt", "data") / ncu_n.most_modeled("noopt"))),
        Figure(README, "the CWBVH kernel {:.2f}× (sibenik), {:.2f}× (conference), {:.2f}× (country_kitchen) the "
               "BVH2's speed on noopt, issue-bound ({:.0f}% issue)", lambda: (
                   *(cwbvh_over_bvh2(s) for s in ("sibenik", "conference", "country_kitchen")),
                   ncu(G + "h100-6f75752/ncu-cwbvh.log", launch("noopt"), "Issue Slots Busy"))),
        Figure(README, "within {:.1%} of `h100-6f75752`'s (measured; that run's own two noopt rows differ by {:.1%})",
               c3eba59),
        Figure(README, "L1 wavefronts per ray {}× the hardware's", l1_rule_ratio),
    ]


def triangles(scene):
    rows = {r["scene_triangles"] for r in load("results/table_sibenik_kitchen.csv") if r["scene"] == scene}
    if len(rows) != 1:
        raise LookupError(f"{scene}: triangle counts {sorted(rows)}")
    return int(rows.pop())


STABILITY = "results/stability.csv"


def rates(case, batch=None):
    """(rate, scene, batch) of every `stability.csv` row of `case` (and `batch`)."""
    return [(float(r["rate"]), r["scene"], r["batch"]) for r in load(STABILITY)
            if r["case"] == case and (batch is None or r["batch"] == batch)]


def edge_graze():
    """The one (count, of) of the edge_graze rows that are not 0 (conference and conference_lamps, direct)."""
    cells = {(r["count"], int(r["of"])) for r in load(STABILITY) if r["case"] == "edge_graze" and r["count"] != "0"}
    if len(cells) != 1:
        raise LookupError(f"edge_graze: {sorted(cells)}")
    return cells.pop()


def stability():
    below = "below_geometric_surface"
    return [
        Figure(README, "on conference and conference_lamps, {} of {:,} `direct` rays passes", edge_graze),
        Figure(README, "directions below the geometric surface {:.1f}–{:.0f}% for `direct` (at most {:.1%} for noopt and "
               "ours), shading/geometric disagreement up to {:.1%} (conference), reuse discontinuities up to {:.1%} of "
               "near-parallel pairs (country_kitchen), key degeneracy up to {:.0%} (twopoint on country_kitchen, {:.0%} "
               "on grazing", lambda: (
                   *(100 * r[0] for r in lo_hi(rates(below, "direct"))),
                   max(r for r, _, b in rates(below) if b != "direct"),
                   max(rates("shading_geometric_disagreement"))[0], max(rates("reuse_discontinuity"))[0],
                   max(rates("key_degeneracy:twopoint"))[0],
                   max(r for r, s, _ in rates("key_degeneracy:twopoint") if s == "grazing"))),
    ]


CHECKS = gpu_lines() + stability() + [
    Figure(README, "on sibenik ({:.0f}K triangles) and country_kitchen ({:.2f}M), 480×270", lambda: (
        triangles("sibenik") / 1e3, triangles("country_kitchen") / 1e6)),
    Figure(README, "on sibenik ({:.0f}K triangles) and country_kitchen ({:.2f}M, the largest shared scene)", lambda: (
        triangles("sibenik") / 1e3, triangles("country_kitchen") / 1e6)),
    Unrecorded(README, "9.5 s wall, 15.4 s user CPU on the 2-core machine, otherwise idle; an earlier run at the "
               "issue-13 revision took 12.9 s wall with other jobs running", "timed from the console, not recorded in any "
               "file"),
]
