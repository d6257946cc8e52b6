"""results/README.md, "What the committed results show": the summary lines of every results folder."""
from results_checks import checks_denoise as dn
from results_checks import checks_gpu as gpu
from results_checks.checks_model import SECONDARY, ratio_range, vs
from results_checks.core import Figure
from results_checks.rows import ROOT, lo_hi, load, word

README = "results/README.md"
V = "results/model/validate/"
DEVICES_NOT_MEASURED = ("cpu",)


def revision(name):
    revisions = {r["git_revision"] for r in load(V + name + ".csv")}
    if len(revisions) != 1:
        raise LookupError(f"{V}{name}.csv: revisions {sorted(revisions)}")
    return revisions.pop()


def validate_runs():
    return sorted(p.stem for p in (ROOT / V).glob("*.csv") if not p.name.endswith(".rows.csv"))


def measured_rows(pattern):
    """Rows of the CSVs under results/`pattern` that a GPU measured (device neither cpu nor simulated)."""
    n = 0
    for p in sorted((ROOT / "results").glob(pattern)):
        n += sum(1 for r in load(str(p.relative_to(ROOT)))
                 if r.get("device") and r["device"] not in DEVICES_NOT_MEASURED
                 and not r["device"].startswith(("simulated", "cpu only")))
    return n


def table1(name="tile"):
    return [r for r in load(V + name + ".csv") if r["table"] == "table1"]


def cells_within(name, bound=0.15):
    rows = [r for r in load(V + name + ".csv") if r["table"] in ("table1", "table3") and r["row"] != "noopt"]
    return sum(abs(float(r["ratio_error"])) <= bound for r in rows), len(rows)


def k_gain(name="tile"):
    cell = {r["row"]: float(r["modeled_mray_s"]) for r in load(V + name + ".csv") if r["table"] == "table3"}
    return cell["ours:tile=8x8,k=64"] / cell["ours:tile=8x8,k=32"] - 1


def checks():
    comp41 = "results/gpu/h100-41d9445/table-comparison.csv"
    group41 = "results/gpu/h100-41d9445/table-group.csv"
    afc = "results/gpu/h100-afc0353/table-comparison.csv"
    afc_cells = [(afc, m) for m in sorted({r["method"] if r["pass"] != "primary" else "primary"
                                           for r in load(afc) if r["scene"] == "sibenik"})]
    afc_cells.append(("results/gpu/h100-afc0353/table-group.csv", "ours:order=group"))
    cells41 = gpu.sibenik_cells("h100-41d9445")
    sorts = [f"{g}+{e}" for g in ("noopt", "ours") for e in gpu.ENCODERS]
    others = [r for r in validate_runs() if r not in ("tile", "group")]
    return [
        Figure(README, "under `gpu/h100-*` and `tune/h100-*` ({:,} measured H100 rows", lambda: measured_rows(
            "tune/h100-*/*.csv")),
        Figure(README, "ratios to NoOpt within {:+.0%} … {:+.0%} of the hardware, absolute speed modeled {:.2f}–{:.2f}× "
               "too fast", lambda: (*lo_hi(gpu.trace_miss(f, "sibenik", m) for f, m in afc_cells),
                                    *lo_hi(gpu.too_fast(f, "sibenik", m) for f, m in afc_cells))),
        Figure(README, "ours {:.2f}×, group order {:.2f}×, contiguous {:.2f}× noopt; every sort after noopt or ours "
               "{:.2f}–{:.2f}×", lambda: (gpu.e2e(comp41, "ours"), gpu.e2e(group41, "ours:order=group"),
                                          gpu.e2e(comp41, "contiguous"), *lo_hi(gpu.e2e(comp41, m) for m in sorts))),
        Figure(README, "the trace-only ratios within {:+.1%} … {:+.1%} of the model's (camera rays the {:+.1%})",
               lambda: (*lo_hi(gpu.trace_miss(f, "sibenik", m) for f, m in cells41),
                        gpu.trace_miss(comp41, "sibenik", "primary"))),
        Figure(README, "(revision `{}`; `l2_half` `{}`; `h100`, `l1_words` and `l1_words_group` `{}`)", lambda: (
            revision("tile"), revision("l2_half"), revision("h100"))),
        Figure(README, "what-if) and {} what-if variants", lambda: word(len(others))),
        Figure(README, "All {} reordering ratios of Table 1 are within {:.1%} of the paper's", lambda: (
            word(sum("+" in r["row"] for r in table1())),
            max(abs(float(r["ratio_error"])) for r in table1() if "+" in r["row"]))),
        Figure(README, "not ({} of {} cells within ±15%), modeled NoOpt is {:.1f} MRay/s against the paper's {:.1f}, "
               "and K = 32 → 64 still gains {:.0%}", lambda: (
                   *cells_within("tile"), float(table1()[0]["modeled_mray_s"]), float(table1()[0]["paper_mray_s"]),
                   k_gain())),
        Figure(README, "why group order matches ({} of {})", lambda: cells_within("group")),
        Figure(README, "BVH2 secondary {:.2f}–{:.2f} of the measured time ({:.2f}–{:.2f} before)", lambda: (
            *ratio_range(vs(methods=SECONDARY), 7), *ratio_range(vs(methods=SECONDARY), 5))),
        Figure(README, "ratios to noopt over-predicted by {:.0f}–{:.0%}", lambda: (
            100 * min(float(r[10]) / float(r[9]) - 1 for r in vs() if r[1] != "noopt"),
            max(float(r[10]) / float(r[9]) - 1 for r in vs() if r[1] != "noopt"))),
    ]


def denoise():
    """The denoise/ line: noopt's error over its denoised error, the shared-direction generators' denoised ratios
    to noopt (geometric means over seeds) and ours' on country_kitchen at 128 frames (checks_denoise's helpers)."""
    low, high = dn.noopt_falls()
    falls = [1 / v for v in low + high]
    return [
        Figure(README, "OIDN lowers noopt's error {:.0f}–{}×", lambda: (min(falls), dn.sig2(max(falls)))),
        Figure(README, "(denoised {:.2f}–{:.2f}× noopt; their image-wide shared directions", lambda: dn.means(
            dn.SCENES, dn.SHARED, 1)),
        Figure(README, "(country_kitchen, denoised up to ~{:.0f}× at {} frames", lambda: (
            max(dn.mean_ratio(dn.CK, "ours", f, 1) for f in dn.FRAMES), str(max(dn.FRAMES)))),
    ]


CHECKS = checks() + denoise()
