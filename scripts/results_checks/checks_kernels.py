"""results/kernels/README.md: the SASS counts of the trace kernels' steps, read from the counting script's output
committed beside it (`sass-counts-sm_86.txt`, `sass-counts-sm_90.txt`); the CWBVH kernel's counts before its
stack moved out of its state are quoted from docs/simt-model.md (no committed output holds them).

A step's local accesses are the script's difference against the step's frame; the classic triangle step's -2 is
shown as 0 (no access), never as a negative count."""
import math
import re

from results_checks.core import Figure, Unrecorded, read_file
from results_checks.logs import sass_step, text_lines

K = "results/kernels/"
SM86, SM90 = K + "sass-counts-sm_86.txt", K + "sass-counts-sm_90.txt"
FIELDS = ("instructions", "issue cycles", "global loads", "local accesses")
TABLE = {"node": ("bvh2 node_step", "tuned node_step", "cwbvh node_step"),
         "triangle": ("bvh2 triangle", "tuned triangle", "cwbvh triangle_step")}


def widths(path, step):
    """(32-bit, 64-bit, 128-bit) LDG counts of a step."""
    for line in text_lines(path):
        if line.startswith(step + " "):
            return tuple(int(v) for v in re.search(r"bits: (\d+)/(\d+)/(\d+)", line).groups())
    raise LookupError(f"{path}: no {step!r} line")


def counts(step, path=SM86):
    inst, cycles, _, local = (sass_step(path, step, f) for f in FIELDS)
    return inst, cycles, max(local, 0.0)


def loads(step):
    w32, w64, w128 = widths(SM86, step)
    parts = [f"{n} × LDG.E{suffix}" for n, suffix in ((w32, ""), (w128, ".128"), (w64, ".64")) if n]
    return " + ".join(parts)


def before():
    """The CWBVH node and triangle steps before 2026-11, as docs/simt-model.md quotes them."""
    m = re.search(r"node\s+(\d+) = (\d+) with (\d+) local accesses, triangle (\d+) with (\d+) loads",
                  read_file("docs/simt-model.md"))
    return tuple(int(v) for v in m.groups())


def row(name):
    classic, tuned, cwbvh = TABLE[name]

    def values():
        c, t, w = counts(classic), counts(tuned), counts(cwbvh)
        out = [c[0], c[1], loads(classic), c[2], t[0], t[1], loads(tuned), t[2]]
        b = before()
        if name == "node":
            return (*out, b[0], b[1], loads(cwbvh), b[2], w[0], w[1], loads(cwbvh), w[2])
        return (*out, b[3], b[3], f"{b[4]} × LDG.E", w[0], w[1], loads(cwbvh))
    f = "{:.0f} / {:.0f} / {} / {:.0f}"
    last = f"{f} → {f}" if name == "node" else "{:.0f} / {:.0f} / {} → {:.0f} / {:.0f} / {}"
    return Figure(K + "README.md", f"| {name} | {f} | {f} | {last} |", values)


def sm90_spread():
    """The largest difference of an sm_90 count from its sm_86 count over the table's steps, as the smallest whole
    percent that bounds it ('within 4%')."""
    worst = max(abs(sass_step(SM90, s, f) / sass_step(SM86, s, f) - 1)
                for steps in TABLE.values() for s in steps for f in FIELDS[:2])
    return str(math.ceil(100 * worst))


def run_kernels():
    readme = K + "README.md"
    return [row("node"), row("triangle"),
            Figure(readme, "`scripts/count-cwbvh-step-instructions sm_86`, sm_90 within {}%)", sm90_spread),
            Figure(readme, "The tuned node step issues fewer instructions ({:.0f} against {:.0f}:", lambda: (
                sass_step(SM86, "tuned node_step", "instructions"), sass_step(SM86, "bvh2 node_step", "instructions"))),
            Figure(readme, "needs {:.0f} loads instead of {:.0f} and {:.0f} local accesses instead of {:.0f}", lambda: (
                sass_step(SM86, "tuned node_step", "global loads"), sass_step(SM86, "bvh2 node_step", "global loads"),
                sass_step(SM86, "tuned node_step", "local accesses"),
                sass_step(SM86, "bvh2 node_step", "local accesses"))),
            Figure(readme, "a divergent node step goes from about {:.0f} × 16 + {:.0f} to {:.0f} × 16 + {:.0f} wavefronts",
                   lambda: tuple(sass_step(SM86, s, f) for s in ("bvh2 node_step", "tuned node_step")
                                 for f in ("global loads", "local accesses"))),
            Figure(readme, "ALU-bound at {:.0f} partition cycles against the BVH2's {:.0f}", lambda: (
                sass_step(SM86, "cwbvh node_step", "issue cycles"), sass_step(SM86, "tuned node_step", "issue cycles")))]


CHECKS = run_kernels()
CHECKS += [
    Unrecorded(K + "README.md", "the issue's goal of CWBVH ≥ 1.3× the new BVH2", "the issue's goal"),
    Unrecorded(K + "h200-119b66c/README.md", "(4.8 against 3.35 TB/s by the two datasheets; not measured here)",
               "by the two datasheets"),
]
