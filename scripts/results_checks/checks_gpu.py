"""results/gpu/*/README.md: the H100 runs (measured `cuda` beside MODELED `simt:preset=h100`)."""
from results_checks.core import Figure
from results_checks.logs import ncu
from results_checks.rows import lo_hi, load, method_of, pct, rate, speedup, total

ENCODERS = ("origin", "reis", "costa", "aila", "twopoint", "mlhcc")


def files(run):
    d = f"results/gpu/{run}/"
    return d + "README.md", d + "table-comparison.csv", d + "table-group.csv", d + "table-scenes.csv"


def sibenik_cells(run):
    """(file, method) of the 23 sibenik methods of a run: the group order from table-group.csv, the rest from
    table-comparison.csv (each ratio against the noopt of its own file)."""
    _, comparison, group, _ = files(run)
    methods = sorted({method_of(r) for r in load(comparison) if r["scene"] == "sibenik"})
    return [(comparison, m) for m in methods] + [(group, "ours:order=group")]


def trace_miss(path, scene, method):
    """MODELED ratio to noopt over the measured one, minus 1 (trace kernel)."""
    return pct(speedup(path, scene, method, "simt"), speedup(path, scene, method, "cuda"))


def too_fast(path, scene, method):
    """MODELED MRay/s over measured MRay/s (trace kernel)."""
    return rate(path, scene, method, "simt", "modeled_ms") / rate(path, scene, method, "cuda")


def e2e(path, method, scene="sibenik"):
    """Measured end-to-end speed (the device span gpu_e2e_ms) over noopt's, same file."""
    return speedup(path, scene, method, "cuda", "gpu_e2e_ms")


def stage(path, method, field, scene="sibenik", tracer="cuda"):
    return total(path, field, scene, method, tracer)


def run_41d9445():
    readme, comp, group, scenes = files("h100-41d9445")
    before = "results/gpu/h100-afc0353/table-comparison.csv"
    before_group = "results/gpu/h100-afc0353/table-group.csv"
    sweep = "results/gpu/h100-41d9445/sweep-sibenik.csv"
    cells = sibenik_cells("h100-41d9445")
    where = {"noopt": comp, "ours": comp, "ours:order=group": group, "contiguous": comp}
    then = {"noopt": before, "ours": before, "ours:order=group": before_group, "contiguous": before}
    sorted_after = [f"{g}+{e}" for g in ("noopt", "ours") for e in ENCODERS]
    after_contiguous = [f"contiguous+{e}" for e in ENCODERS]
    grouping = [m for m in {method_of(r) for r in load(sweep)} if m.startswith("ours:")]
    out = [
        Figure(readme, "Reproduced from afc0353 within {:.1%}–{:.1%}", lambda: lo_hi(
            pct(rate(where[m], "sibenik", m), rate(then[m], "sibenik", m)) for m in where)),
        Figure(readme, "noopt {:.1f} MRay/s ({:.1f} then), ours {:.1f} ({:.1f}), ours:order=group {:.1f} ({:.1f}), "
               "contiguous {:.1f} ({:.1f})", lambda: tuple(
                   v for m in where for v in (rate(where[m], "sibenik", m), rate(then[m], "sibenik", m)))),
        Figure(readme, "all 23 methods within {:+.1%} … {:+.1%} (camera rays the {:+.1%})", lambda: (
            *lo_hi(trace_miss(f, "sibenik", m) for f, m in cells), trace_miss(comp, "sibenik", "primary"))),
        Figure(readme, "the model is **{:.2f}–{:.2f}× too fast**", lambda: lo_hi(
            too_fast(f, "sibenik", m) for f, m in cells)),
        Figure(readme, "Conference and country_kitchen: ratios within {:+.1%} … {:+.1%} (camera rays the "
               "{:+.1%})", lambda: (*lo_hi(trace_miss(scenes, s, m) for s in ("conference", "country_kitchen")
                                           for m in ("primary", "ours", "ours:order=group", "contiguous")),
                                    trace_miss(scenes, "country_kitchen", "primary"))),
        Figure(readme, "(conference contiguous {:.3f} → {:.3f}, country_kitchen ours {:.3f} → {:.3f})", lambda: (
            speedup(scenes, "conference", "contiguous"), speedup(scenes, "conference", "contiguous", "simt"),
            speedup(scenes, "country_kitchen", "ours"), speedup(scenes, "country_kitchen", "ours", "simt"))),
        Figure(readme, "absolute {:.2f}–{:.2f}× too fast on conference and {:.2f}–{:.2f}× on country_kitchen",
               lambda: (*lo_hi(too_fast(scenes, "conference", m) for m in ("primary", *where)),
                        *lo_hi(too_fast(scenes, "country_kitchen", m) for m in ("primary", *where)))),
        Figure(readme, "so its group-order ratio is {:.3f}", lambda: (  # summary.md's cross-file figure, named
            rate(group, "sibenik", "ours:order=group", "cuda", "gpu_e2e_ms") / rate(comp, "sibenik", "noopt", "cuda",
                                                                                "gpu_e2e_ms"))),
        Figure(readme, "ours {:.2f}×, group order {:.2f}×, contiguous {:.2f}× noopt's end-to-end speed", lambda: (
            e2e(comp, "ours"), e2e(group, "ours:order=group"), e2e(comp, "contiguous"))),
        Figure(readme, "*slower* end to end than plain noopt ({:.2f}–{:.2f}×) although the sorts speed up the trace "
               "by up to {:.2f}×", lambda: (*lo_hi(e2e(comp, m) for m in sorted_after),
                                             max(speedup(comp, "sibenik", m) for m in sorted_after
                                                 if m.startswith("noopt")))),
        Figure(readme, "slower than contiguous alone ({:.2f}–{:.2f}× against {:.2f}×)", lambda: (
            *lo_hi(e2e(comp, m) for m in after_contiguous), e2e(comp, "contiguous"))),
        Figure(readme, "The model prices generation at {:.3f} ms for every generator; measured, noopt's kernel takes "
               "{:.3f} ms and the grouping generators' {:.2f} ms (tile 8×8) to {:.2f} ms (16×16 and 32×8 tiles",
               lambda: (stage(comp, "noopt", "modeled_gen_ms", tracer="simt"), stage(comp, "noopt", "gen_ms"),
                        min(stage(comp, m, "gen_ms") for m in ("ours", "contiguous")),
                        max(stage(sweep, m, "gen_ms") for m in grouping))),
        Figure(readme, "(measured trace-only {:.2f}×, end to end {:.2f}×)", lambda: (
            speedup(comp, "sibenik", "ours"), e2e(comp, "ours"))),
        Figure(readme, "CUB's sort takes {:.2f}–{:.2f} ms against {:.3f} modeled, the gather {:.2f}–{:.2f} ms "
               "against {:.2f}–{:.2f}, mlhcc's key kernel {:.2f}–{:.2f} ms against {:.3f}", lambda: (
                   *lo_hi(stage(comp, m, "sort_ms") for m in sorted_after + after_contiguous),
                   stage(comp, "noopt+twopoint", "modeled_sort_ms", tracer="simt"),
                   *lo_hi(stage(comp, m, "permute_ms") for m in sorted_after + after_contiguous),
                   *lo_hi(stage(comp, m, "modeled_permute_ms", tracer="simt") for m in sorted_after + after_contiguous),
                   *lo_hi(stage(comp, g + "+mlhcc", "key_ms") for g in ("noopt", "ours", "contiguous")),
                   stage(comp, "noopt+mlhcc", "modeled_key_ms", tracer="simt"))),
        Figure(readme, "Measured span − sum of stages: {:.3f}–{:.3f} ms (launch gaps), e.g. noopt {:.3f} − {:.3f}",
               lambda: (*lo_hi(gap(f, m) for f, m in cells), stage(comp, "noopt", "gpu_e2e_ms"),
                        stage(comp, "noopt", "e2e_ms"))),
        Figure(readme, "End to end (measured span) the same grid is {:.2f} … {:.2f} on (8,8) but below noopt for the "
               "16×16 and 32×8 tiles ({:.2f}–{:.2f}×): their group kernel costs {:.1f}–{:.1f} ms", lambda: (
                   *lo_hi(e2e(sweep, m) for m in grouping if "8x8" in m),
                   *lo_hi(e2e(sweep, m) for m in grouping if "16x16" in m or "32x8" in m),
                   *lo_hi(stage(sweep, m, "gen_ms") for m in grouping if "16x16" in m or "32x8" in m))),
    ]
    for method, path in (("noopt", comp), ("ours", comp), ("ours:order=group", group), ("contiguous", comp),
                         ("noopt+twopoint", comp), ("noopt+mlhcc", comp), ("ours+twopoint", comp)):
        out.append(e2e_row(readme, path, method))
    for tile in ("8,8", "16,8", "16,16", "32,8"):
        w, h = tile.split(",")
        out.append(Figure(readme, f"| ({tile}) | " + " | ".join("{:.2f}" for _ in range(4)) + " |",
                          lambda w=w, h=h: tuple(speedup(sweep, "sibenik", f"ours:tile={w}x{h},k={k}")
                                                 for k in (8, 16, 32, 64))))
    out += [Figure(readme, "Ratios to noopt, measured → modeled: ours {:.3f} → {:.3f} ({:+.1%}), group order {:.3f} → "
                   "{:.3f} ({:+.1%}), contiguous {:.3f} → {:.3f} ({:+.1%}), noopt+twopoint {:.3f} → {:.3f} ({:+.1%}), "
                   "ours+mlhcc {:.3f} → {:.3f}, contiguous+mlhcc {:.3f} → {:.3f}", lambda: ratios_41d9445(comp, group))]
    return out


def gap(path, method):
    return stage(path, method, "gpu_e2e_ms") - stage(path, method, "e2e_ms")


def ratios_41d9445(comp, group):
    out = []
    for path, m, miss in ((comp, "ours", 1), (group, "ours:order=group", 1), (comp, "contiguous", 1),
                          (comp, "noopt+twopoint", 1), (comp, "ours+mlhcc", 0), (comp, "contiguous+mlhcc", 0)):
        out += [speedup(path, "sibenik", m), speedup(path, "sibenik", m, "simt")]
        if miss:
            out.append(trace_miss(path, "sibenik", m))
    return tuple(out)


def e2e_row(readme, path, method):
    """A row of the end-to-end table: measured stages and span (ms), the measured and MODELED ratios to noopt."""
    def values():
        stages = [stage(path, method, f) for f in ("gen_ms", "key_ms", "sort_ms", "permute_ms", "trace_ms")]
        shown = ["{:.3f}".format(v) if v else "–" for v in stages]
        return (*shown, stage(path, method, "gpu_e2e_ms"), e2e(path, method),
                speedup(path, "sibenik", method, "simt", "gpu_e2e_ms"))
    bold = "**{:.3f}**" if "+" not in method else "{:.3f}"
    if method == "noopt":
        bold = "{:.3f}"
    return Figure(readme, f"| {method} | {{}} | {{}} | {{}} | {{}} | {{}} | {{:.3f}} | {bold} | {{:.3f}} |", values)


def span(values, spec):
    """A range 'a–b' of `values` formatted by `spec`, one figure where both ends round alike."""
    lo, hi = (format(v, spec) for v in lo_hi(values))
    return lo if lo == hi else f"{lo}–{hi}"


def ncu_41d9445():
    """What bounds the BVH2 kernel: ncu.log, launches 2–3 noopt, 4–5 ours; the README quotes the first launch of
    each batch (2 and 4), a range over the two where it names no batch."""
    readme, log = files("h100-41d9445")[0], "results/gpu/h100-41d9445/ncu.log"

    def both(metric):
        return ncu(log, 2, metric), ncu(log, 4, metric)

    def over(metric, spec=".0f"):
        return span(both(metric), spec)
    return [
        Figure(readme, "**L1/TEX throughput {:.1f}% (noopt) and {:.1f}% (ours) of peak**, SM issue {:.0f}% / {:.0f}%, "
               "IPC {:.2f} / {:.2f}, L1 hit rate {}%, L2 hit {}%, DRAM {}%, achieved occupancy {}% ({:.0f} registers: "
               "{:.0f} blocks of 128 per SM, {:.0f} warps)", lambda: (
                   *both("L1/TEX Cache Throughput"), *both("Issue Slots Busy"), *both("Executed Ipc Active"),
                   over("L1/TEX Hit Rate"), over("L2 Hit Rate"), over("DRAM Throughput"), over("Achieved Occupancy"),
                   ncu(log, 2, "Registers Per Thread"), ncu(log, 2, "Block Limit Registers"),
                   ncu(log, 2, "Theoretical Active Warps per SM"))),
        Figure(readme, "its durations, {:.2f} ms for noopt, are longer than the run's {:.2f} ms", lambda: (
            ncu(log, 2, "Duration") / 1e6, total(files("h100-41d9445")[1], "trace_ms", "sibenik", "noopt"))),
    ]


CHECKS = run_41d9445() + ncu_41d9445()


def run_c3eba59():
    readme, final = "results/gpu/h100-c3eba59/README.md", "results/gpu/h100-c3eba59/table-final.csv"
    before = {m: "results/gpu/h100-6f75752/table-comparison.csv" for m in ("noopt", "ours", "contiguous")}
    before["ours:order=group"] = "results/gpu/h100-6f75752/table-group.csv"
    order = ("noopt", "ours", "ours:order=group", "contiguous")
    kernels = ("cuda", "cuda:cwbvh")

    def ms(path, method, tracer):
        return total(path, "trace_ms", "sibenik", method, tracer)

    def diff(method, tracer):
        return abs(pct(ms(final, method, tracer), ms(before[method], method, tracer)))

    cells = [(m, t) for m in order for t in kernels]
    second_noopt = "results/gpu/h100-6f75752/table-group.csv"
    return [
        Figure(readme, "trace times (median of 5, ms) BVH2 / CWBVH — noopt {:.3f} / {:.3f}, ours {:.3f} / {:.3f}, group "
               "{:.3f} / {:.3f}, contiguous {:.3f} / {:.3f}, against", lambda: tuple(ms(final, m, t) for m, t in cells)),
        Figure(readme, "({:.3f} / {:.3f}, {:.3f} / {:.3f}, {:.3f} / {:.3f}, {:.3f} / {:.3f}; the group order from its",
               lambda: tuple(ms(before[m], m, t) for m, t in cells)),
        Figure(readme, "the group order's CWBVH time differs by {:.1%}, the other seven by at most {:.1%}", lambda: (
            diff("ours:order=group", "cuda:cwbvh"),
            max(diff(m, t) for m, t in cells if (m, t) != ("ours:order=group", "cuda:cwbvh")))),
        Figure(readme, "second noopt row ({:.3f} ms, `table-group.csv`) this run's noopt differs by {:.1%}, and that "
               "run's two noopt rows differ by {:.1%}", lambda: (
                   ms(second_noopt, "noopt", "cuda"), pct(ms(final, "noopt", "cuda"), ms(second_noopt, "noopt", "cuda")),
                   pct(ms(before["noopt"], "noopt", "cuda"), ms(second_noopt, "noopt", "cuda")))),
    ]


CHECKS += run_c3eba59()


def run_6f75752():
    readme, comp, group, scenes = files("h100-6f75752")
    cells = sibenik_cells("h100-6f75752")
    cwbvh_rows = [("sibenik", m, p) for m, p in (("primary", group), ("noopt", group), ("ours", comp),
                                                 ("ours:order=group", group), ("contiguous", comp))]
    cwbvh_rows += [(s, m, scenes) for s in ("conference", "country_kitchen") for m in ("noopt", "ours")]

    def row(scene, method, path):
        def values():
            b, c = (total(path, "trace_ms", scene, method, t) for t in ("cuda", "cuda:cwbvh"))
            b_r, c_r = (rate(path, scene, method, t) for t in ("cuda", "cuda:cwbvh"))
            return b, b_r, c, c_r, b / c
        bold = "**{:.2f}×**" if (scene, method) == ("sibenik", "noopt") else "{:.2f}×"
        return Figure(readme, f"| {scene} | {method} | {{:.3f}} ({{:.0f}}) | {{:.3f}} ({{:.0f}}) | {bold} |", values)
    return [row(*c) for c in cwbvh_rows] + [
        Figure(readme, "is {:.2f}–{:.2f}× the measured speed ({:.2f} the camera rays), ratios to noopt within {:+.1%} … "
               "{:+.1%} (camera rays the {:+.1%};", lambda: (
                   *lo_hi(too_fast(f, "sibenik", m) for f, m in cells), too_fast(comp, "sibenik", "primary"),
                   *lo_hi(trace_miss(f, "sibenik", m) for f, m in cells), trace_miss(comp, "sibenik", "primary"))),
        Figure(readme, "(sibenik camera rays and noopt BVH2 from `table-group.csv`, {:.3f} ms; `table-comparison.csv` has {:.3f} ms",
               lambda: (total(group, "trace_ms", "sibenik", "noopt"), total(comp, "trace_ms", "sibenik", "noopt"))),
    ]


CHECKS += run_6f75752()
