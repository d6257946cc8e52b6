"""The L1 probe (bench/l1_probe.cu): results/gpu/h100-6f75752/README.md (measured on the H100: the rule table from
`l1-summary.txt`, which a Generated check makes again, the rule that holds recomputed here from each pattern's
lane offsets in `l1-measured.csv`, and the CWBVH kernel's Nsight Compute figures) and
results/gpu/gpgpusim-l1-probe/README.md (SIMULATED: `l1-probe-sim.csv`)."""
import csv
import math

from results_checks.checks_ncu import launch, per_ray
from results_checks.core import Figure, Unrecorded
from results_checks.logs import ncu, text_lines
from results_checks.rows import ROOT, USED, total

H = "results/gpu/h100-6f75752/"
SIM = "results/gpu/gpgpusim-l1-probe/"


def parity(x):
    return bin(x).count("1") & 1


def hopper_rule(width, offsets):
    """(data-stage, tag-stage) wavefronts of one warp load as the README states the rule: passes of 128 / width
    lanes, each as many wavefronts as the most distinct 4-byte words in one of 32 banks; the most distinct 128-byte
    lines in one of 4 tag banks, line k's bank (parity(k & 0b01111), parity(k & 0b10101)) of address bits 7-11."""
    lanes, data = 128 // width, 0
    for first in range(0, len(offsets), lanes):
        banks = {}
        for off in offsets[first:first + lanes]:
            for word in range(off // 4, (off + width) // 4):
                banks.setdefault(word % 32, set()).add(word)
        data += max(len(v) for v in banks.values())
    tags = {}
    for off in offsets:
        k = (off >> 7) & 31
        tags.setdefault((parity(k & 0b01111), parity(k & 0b10101)), set()).add(off >> 7)
    return data, max(len(v) for v in tags.values())


def measured():
    USED.add(H + "l1-measured.csv")
    with open(ROOT / H / "l1-measured.csv", newline="") as f:
        return list(csv.DictReader(f))


def rule_fit():
    """(patterns whose ncu counts the rule gives exactly, patterns, mean and largest |cycles - rule|)."""
    exact, errors = 0, []
    for r in measured():
        data, tag = hopper_rule(int(r["width"]), [int(x) for x in r["offsets"].split()])
        exact += round(float(r["data_wavefronts"])) == data and (
            not r["tag_wavefronts"] or round(float(r["tag_wavefronts"])) == tag)
        errors.append(abs(float(r["cycles_per_load"]) - max(data, tag)))
    return exact, len(errors), sum(errors) / len(errors), max(errors)


def summary_rule(rule):
    """(exact, of, mean |err| cycles) of a rule's line in l1-summary.txt."""
    for line in text_lines(H + "l1-summary.txt"):
        words = line.split()
        if words and words[0] == rule:
            exact, of = words[1].split("/")
            return int(exact), int(of), float(words[3])
    raise LookupError(f"{H}l1-summary.txt: no line for {rule}")


def pattern(name):
    return next(r for r in measured() if r["pattern"] == name)


def example(name):
    r = pattern(name)
    return (*hopper_rule(int(r["width"]), [int(x) for x in r["offsets"].split()]), float(r["cycles_per_load"]))


def sim_rows():
    USED.add(SIM + "l1-probe-sim.csv")
    with open(ROOT / SIM / "l1-probe-sim.csv", newline="") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def sim_floor():
    return min(float(r["cycles_per_load"]) for r in sim_rows())


def sim_over_rule():
    """Measured cycles minus the simulator's rule, on the patterns whose rule exceeds the issue floor."""
    return [float(r["cycles_per_load"]) - int(r["gpgpusim"]) for r in sim_rows() if int(r["gpgpusim"]) > sim_floor()]


def sim_error(rule):
    return sum(abs(float(r["cycles_per_load"]) - int(r[rule])) for r in sim_rows()) / len(sim_rows())


def sim_pattern(name):
    return next(r for r in sim_rows() if r["pattern"] == name)


def rule_row(label, rule):
    return Figure(H + "README.md", f"| {label} | {{}} / {{}} | {{:.2f}} |", lambda: summary_rule(rule))


def run_6f75752():
    readme = H + "README.md"
    cw, bvh2, before = H + "ncu-cwbvh.log", H + "ncu.log", "results/gpu/h100-9bc790a/ncu-cwbvh.log"
    before_bvh2, noopt = "results/gpu/h100-41d9445/ncu.log", launch("noopt")
    wf = "l1tex__data_pipe_lsu_wavefronts.sum"
    over = sim_over_rule()
    return [
        Figure(readme, "(e.g. 4-byte lanes on 6 lines 5 lines apart: data {}, tag {}, measured {:.2f} cycles)",
               lambda: example("w4-lines6-rotated")),
        rule_row("the model's hardware rule until now: max(1, ⌈distinct lines / 4⌉)", "lines4"),
        rule_row("one per distinct line", "lines"),
        rule_row("⌈distinct sectors / 4⌉", "sectors4"),
        rule_row("most distinct sectors at one sector position", "bank_max"),
        rule_row("GPGPU-Sim's rule (`l1_banks=4`)", "gpgpusim"),
        Figure(readme, "| **4-byte banks per pass, and hashed tag banks** | **{} / {}** | **{:.0f}** (all within {:.1f}) |",
               lambda: (*rule_fit()[:3], math.ceil(rule_fit()[3] * 10) / 10)),
        Figure(readme, "there its cycles follow the simulator's own rule (`gpgpusim`) plus {:.1f}–{:.1f}, where that "
               "rule exceeds the simulator's issue floor of ≈ {:.1f}", lambda: (min(over), max(over), sim_floor())),
        Figure(readme, "That is the {:.1f}× gap of", lambda: per_ray("bvh2", "noopt", wf) / total(
            "results/gpu/h100-9bc790a-ncu/model.csv", "modeled_l1_wavefronts_per_ray", "sibenik", "noopt", "simt")),
        Figure(readme, "ran sibenik noopt in {:.2f} ms against the BVH2's {:.2f} ms ({:.2f}×); the exact "
               "one-FMA-per-plane step runs it in {:.2f} ms under the same conditions (`ncu-cwbvh.log`, launch {}), "
               "{:.2f}× the BVH2", lambda: (
                   ncu(before, noopt, "Duration") / 1e6, ncu(before_bvh2, noopt, "Duration") / 1e6,
                   ncu(before_bvh2, noopt, "Duration") / ncu(before, noopt, "Duration"),
                   ncu(cw, noopt, "Duration") / 1e6, noopt,
                   ncu(before_bvh2, noopt, "Duration") / ncu(cw, noopt, "Duration"))),
        Figure(readme, "issue-bound ({:.0f}% of issue slots, IPC {:.2f}, L1/TEX {:.0f}%; {:.0f} registers, {:.0f}% "
               "theoretical occupancy), the BVH2 kernel L1-bound (L1/TEX {:.1f}%, issue {:.0f}%; {:.0f} registers)",
               lambda: (ncu(cw, noopt, "Issue Slots Busy"), ncu(cw, noopt, "Executed Ipc Active"),
                        ncu(cw, noopt, "L1/TEX Cache Throughput"), ncu(cw, noopt, "Registers Per Thread"),
                        ncu(cw, noopt, "Theoretical Occupancy"), ncu(bvh2, noopt, "L1/TEX Cache Throughput"),
                        ncu(bvh2, noopt, "Issue Slots Busy"), ncu(bvh2, noopt, "Registers Per Thread"))),
        Unrecorded(readme, "Ylitie et al.'s 1.9–2.1×", "Ylitie et al.'s"),
    ]


def run_sim():
    readme = SIM + "README.md"
    over = sim_over_rule()
    rules = ("lines4", "lines", "sectors4", "bank_max", "bytes128")
    return [
        Figure(readme, "issue floor of about {:.1f} cycles per load (its in-order issue of the probe's PTX), the "
               "measured cycles per load are that rule plus {:.2f}–{:.2f} ({} patterns)", lambda: (
                   sim_floor(), min(over), max(over), len(over))),
        Figure(readme, "one sector position: rule {}, measured {:.2f}; a random node pattern: rule {}, measured {:.2f}, "
               "where the sector-position count would say {}", lambda: (
                   sim_pattern("w4-lines32-samesector")["gpgpusim"],
                   float(sim_pattern("w4-lines32-samesector")["cycles_per_load"]),
                   sim_pattern("w4-node27-2")["gpgpusim"], float(sim_pattern("w4-node27-2")["cycles_per_load"]),
                   sim_pattern("w4-node27-2")["bank_max"])),
        Figure(readme, "Mean absolute error over the {} patterns: {:.2f} cycles for the simulator's rule, {:.2f} for "
               "the next best", lambda: (len(sim_rows()), sim_error("gpgpusim"), min(map(sim_error, rules)))),
    ]


CHECKS = run_6f75752() + run_sim()
