"""results/model/stage-counters/README.md: the stage kernels' make-up, modeled beside Nsight Compute. The
diagnosis (diagnosis-6ebd003.md) is made again by scripts/stage_counters.py from the committed prediction and the
6ebd003 profile; the README's table must be its lines, and its prose figures are recomputed from the same files
(the prediction's chain and count, the profile's cycles per instruction and the stall its rule names, the latency
constants in simt/)."""
import re
import sys

from results_checks.checks_stage_latency import source_constant
from results_checks.core import Embedded, Figure, Generated
from results_checks.rows import ROOT, load

C = "results/model/stage-counters"
README = f"{C}/README.md"
DIAGNOSIS = f"{C}/diagnosis-6ebd003.md"
NCU = "../../stages/h200-6ebd003/ncu-stages.log.xz"


def modeled(method, column):
    (row,) = [r for r in load(f"{C}/prediction-a26f7f6.csv") if r["method"] == method and r["kernel"] == "gen"]
    return float(row[column])


def measured(first, last):
    """stage_counters.py's measured make-up of the last generator launch among launches first..last."""
    sys.path.insert(0, str(ROOT / "scripts"))
    import stage_counters
    launches = stage_counters.read_log(str(ROOT / C / NCU))[first:last + 1]
    (k,) = [k for k in launches if stage_counters.kernel_of(k["name"]) == "gen"][-1:]
    return stage_counters.measured(k)


def mio_stall():
    (v,) = [v for r, v in measured(0, 3)["stalls"].items() if re.search(r"\bMIO\b", r)]
    return v


CHECKS = [
    Generated(DIAGNOSIS, ["scripts/stage_counters.py", "compare", "prediction-a26f7f6.csv", f"{NCU}@0-3=noopt",
                          f"{NCU}@6-9=ours"], cwd=C),
    Embedded(README, DIAGNOSIS, "the timed pass (`diagnosis-6ebd003.md`)"),
    Figure(README, "A warp of noopt lives {:,.0f} cycles and the model's chain is {:,.0f}; the group kernel's warp "
                   "lives {:,.0f} and its chain is {:,.0f}",
           lambda: (measured(0, 3)["lifetime"], modeled("noopt", "chain_cycles"), measured(6, 9)["lifetime"],
                    modeled("ours", "chain_cycles"))),
    Figure(README, "the dependent ALU latency ({} cycles) and each load at its level's (a shared-memory load {})",
           lambda: (source_constant("simt/stage_model.cpp", "c.alu_latency"),
                    source_constant("simt/stage_model.cpp", "c.shared_latency"))),
    Figure(README, "which puts noopt's at {:.1f} cycles per instruction of its count, where the GPU spends {:.1f}",
           lambda: (modeled("noopt", "chain_cycles") / modeled("noopt", "cycles_per_warp"), measured(0, 3)["cpi"])),
    Figure(README, "noopt's largest stall: {:.1f} cycles per instruction waiting on the MIO", mio_stall),
    Figure(README, "a warp issuing once in {:.0f} to {:.0f} cycles",
           lambda: (measured(6, 9)["cpi"], measured(0, 3)["cpi"])),
]

# MLHCC's key kernel's L1 (mlhcc-key-l1.md, not a README: its tables are checked the same way).
MLHCC = f"{C}/mlhcc-key-l1.md"
MLHCC_TABLE = f"{C}/mlhcc-key-l1-table.md"
CHECKS += [
    Generated(MLHCC_TABLE, ["scripts/mlhcc_key_l1.py", "table", "mlhcc-key-l1.csv"], cwd=C),
    Embedded(MLHCC, MLHCC_TABLE, "The first three rows are the prediction"),
    Embedded(MLHCC, MLHCC_TABLE, "The first three rows are the prediction", prefix="- sibenik"),
    Embedded(MLHCC, MLHCC_TABLE, "Set beside sibenik's row"),
]
