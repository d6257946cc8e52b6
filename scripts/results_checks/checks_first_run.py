"""results/gpu/h100-afc0353/README.md: the first H100 run, sibenik 1920×1080 trace kernel only, measured `cuda` and
`cuda:cwbvh` beside MODELED `simt:preset=h100`; ours:order=group from table-group.csv, every other method from
table-comparison.csv, each ratio against the noopt of its own file and tracer."""
import re

from results_checks.core import Figure, read_file
from results_checks.rows import lo_hi, pct, rate, speedup, total

R = "results/gpu/h100-afc0353/"
METHODS = ("primary", "noopt", "ours", "ours:order=group", "contiguous", "noopt+origin", "noopt+reis", "noopt+costa",
           "noopt+aila", "noopt+twopoint", "noopt+mlhcc", "noopt+window")


def where(method):
    return R + ("table-group.csv" if method == "ours:order=group" else "table-comparison.csv")


def mray(method, tracer):
    return rate(where(method), "sibenik", method, tracer, "modeled_ms" if tracer == "simt" else "trace_ms")


def ratio(method, tracer="cuda"):
    return speedup(where(method), "sibenik", method, tracer)


def miss(method):
    """The MODELED ratio to noopt over the measured one, minus 1."""
    return pct(ratio(method, "simt"), ratio(method))


def row(readme, method):
    def values():
        out = []
        for tracer in ("cuda", "cuda:cwbvh", "simt"):
            out += [mray(method, tracer), ratio(method, tracer)]
        return (*out, mray(method, "simt") / mray(method, "cuda"))
    return Figure(readme, f"| {method} | {{:.1f}} | {{:.3f}} | {{:.1f}} | {{:.3f}} | {{:.1f}} | {{:.3f}} | {{:.2f}} |",
                  values)


def run_afc0353():
    readme = R + "README.md"
    others = [m for m in METHODS if m != "noopt"]
    return [row(readme, m) for m in METHODS] + [
        Figure(readme, "the model is within {:.0%} … {:+.0%} of the hardware** on every method (ours {:+.1%}, group "
               "order {:+.1%}, contiguous {:+.1%}, primary {:+.1%}, twopoint {:+.1%}, costa {:+.1%})", lambda: (
                   *lo_hi(miss(m) for m in others), miss("ours"), miss("ours:order=group"), miss("contiguous"),
                   miss("primary"), miss("noopt+twopoint"), miss("noopt+costa"))),
        Figure(readme, "but for twopoint/mlhcc, which are {:.1%} apart on hardware and swap", lambda: (
            abs(pct(ratio("noopt+mlhcc"), ratio("noopt+twopoint"))))),
        Figure(readme, "the model is {:.2f}–{:.2f}× too fast** on this kernel", lambda: lo_hi(
            mray(m, "simt") / mray(m, "cuda") for m in METHODS)),
        Figure(readme, "{:.2f}× the BVH2 on NoOpt, {:.2f}× on primary rays, {:.2f}× on ours", lambda: tuple(
            mray(m, "cuda:cwbvh") / mray(m, "cuda") for m in ("noopt", "primary", "ours"))),
        Figure(readme, "divides it by `table-comparison.csv`'s noopt instead: {:.3f} measured, {:.3f} on the CWBVH "
               "kernel)", lambda: tuple(mray("ours:order=group", t) / rate(R + "table-comparison.csv", "sibenik",
                                                                            "noopt", t) for t in ("cuda", "cuda:cwbvh"))),
        Figure(readme, "The model's absolute miss against the paper's RTX 3060 figures was {}× (`docs/simt-model.md` §4)",
               lambda: re.search(r"absolute speed is ([\d.]+)× too high", read_file("docs/simt-model.md")).group(1)),
        Figure(readme, "generated NoOpt's batch in {:.0f} ms but ours in {:.0f} ms", lambda: tuple(
            total(where(m), "gen_ms", "sibenik", m) for m in ("noopt", "ours"))),
    ]


CHECKS = run_afc0353()
