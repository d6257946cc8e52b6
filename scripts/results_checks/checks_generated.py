"""Generated files: each is made again into a temporary folder by the script and from the rows that made it
(the command each folder's README names) and compared with the committed copy. File lists are written out, not
globbed, so that their order (which orders the rows) does not depend on the locale."""
from results_checks.core import Embedded, Generated
from results_checks.rows import ROOT

SUMMARY = "scripts/gpu_check_summary.py"


def gpu_summary(run, files, mode="equal"):
    d = f"results/gpu/{run}"
    return Generated(f"{d}/summary.md", [SUMMARY] + [f"{d}/{f}" for f in files], mode=mode)


def stages(run):
    d = f"results/stages/{run}"
    files = ("stages-conference-encoders.csv", "stages-conference.csv", "stages-country_kitchen-encoders.csv",
             "stages-country_kitchen.csv", "stages-sibenik-encoders.csv", "stages-sibenik.csv", "stages-sweep.csv")
    return Generated(f"{d}/stages.md", ["scripts/stage_bounds.py", "stage-bounds.csv", *files], cwd=d)


def l1_probe(run):
    d = f"results/gpu/{run}"
    args = ["scripts/l1_probe_summary.py", "l1-probe.csv", "l1-probe-ncu-order.csv", "l1-probe-ncu.log",
            "l1-probe-ncu2-order.csv", "l1-probe-ncu2.log"]
    return [Generated(f"{d}/l1-summary.txt", args + ["{tmp}/l1-measured.csv"], cwd=d),
            Generated(f"{d}/l1-measured.csv", args + ["{tmp}/l1-measured.csv"], cwd=d, produced="l1-measured.csv")]


SCENES = ("conference", "country_kitchen", "sibenik")
PREDICTION = [f"results/kernels/prediction-h100-{s}{e}.csv" for s in SCENES for e in ("-encoders", "")]
# results/kernels/h200-119b66c/kernels.md was written on the device, whose shell listed `kernels-*.csv` with each
# scene's main file before its -encoders file.
PREDICTION_DEVICE = [f"../prediction-h100-{s}{e}.csv" for s in SCENES for e in ("", "-encoders")]
MEASURED_DEVICE = [f"kernels-{s}{e}.csv" for s in SCENES for e in ("", "-encoders")]

V = "results/model/validate"
VALIDATE_RUNS = ("tile", "group", "l2_half", "l2_double", "dram_half", "l1_tags_2", "l1_tags_8", "l1_words",
                 "l1_words_group", "resident_16", "simple_kernel", "h100")  # scripts/validate-model's order
H = "results/gpu/h100-6f75752"
# The two commands of the READMEs that glob (`converge_*_seed*.csv`, `converge_*-summary.csv`), in the C locale's order.
DENOISE = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "results/denoise").glob("converge_*_seed*.csv"))
SEEDS = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "results/converge-480x270").glob("converge_*-summary.csv"))

CHECKS = [
    gpu_summary("h100-9bc790a", ["scaling-1920x1080.csv", "scaling-240x136.csv", "scaling-480x272.csv",
                                 "scaling-64x48.csv", "scaling-960x540.csv"]),
    gpu_summary("h100-41d9445", ["table-comparison.csv", "table-group.csv", "table-scenes.csv", "sweep-sibenik.csv"]),
    gpu_summary("h100-6f75752", ["table-comparison.csv", "table-group.csv", "table-scenes.csv", "sweep-sibenik.csv"]),
    gpu_summary("gpgpusim-dry-run-3bffdc3", ["table-comparison.csv", "table-group.csv", "table-scenes.csv",
                                             "sweep-sibenik.csv"]),
    # written on the device by the script as it was at afc0353: its rows are today's, its header and the end-to-end
    # table (which the script gained later) differ
    gpu_summary("h100-afc0353", ["table-comparison.csv", "table-group.csv"], mode="lines"),
    *l1_probe("h100-6f75752"),
    *l1_probe("h100-9566ba3"),
    *[stages(r) for r in ("h200-1a660a1", "h200-26a4674", "h200-6ebd003", "h200-a26f7f6", "h200-ab8957e",
                          "h200-d31e7d7", "h200-f400a3e")],
    Generated("results/model/hw-counters/prediction.md",
              ["scripts/hw_counters_check.py", "--modeled-table", "results/model/hw-counters/prediction.csv"]),
    Generated("results/intervals/cpu-79f5306/intervals.txt",
              ["scripts/speed_interval.py", "results/intervals/cpu-79f5306/table.csv"]),
    Generated("results/intervals/cpu-79f5306/intervals-e2e.txt",
              ["scripts/speed_interval.py", "results/intervals/cpu-79f5306/table.csv", "--e2e"]),
    Generated("results/kernels/prediction.md", ["scripts/kernel_gain.py", *PREDICTION]),
    Generated("results/kernels/h200-119b66c/kernels.md",
              ["scripts/kernel_gain.py", *PREDICTION_DEVICE, "--measured", *MEASURED_DEVICE],
              cwd="results/kernels/h200-119b66c"),
    Generated(f"{V}/summary.md", ["scripts/validate_summary.py", *[f"{V}/{r}.csv" for r in VALIDATE_RUNS],
                                  "--labels", ",".join(VALIDATE_RUNS), "--out", "{tmp}/summary.md"],
              produced="summary.md"),
    Generated("results/model/resolution.md",
              ["scripts/model_summary.py", *[f"results/model/resolution_{r}.csv" for r in ("640x360", "1280x720",
                                                                                          "1920x1080")],
               "--out", "{tmp}/resolution.md"], produced="resolution.md"),
    Generated("results/model/h100-l1-rule/model_vs_measured.md",
              ["scripts/model_vs_measured.py", "--measured", f"{H}/table-comparison.csv", f"{H}/table-group.csv",
               f"{H}/table-scenes.csv", "--modeled", *[f"results/model/h100-l1-rule/model-{s}.csv" for s in SCENES],
               "--before", f"{H}/table-comparison.csv", f"{H}/table-group.csv", f"{H}/table-scenes.csv"]),
    Generated("results/model/gpgpusim/table.md", ["scripts/model_vs_sim.py", "{tmp}", "{tmp}/model_vs_sim.png"],
              copy=("results/model/gpgpusim/runs",), produced="table.md"),
    Generated("results/model/gpgpusim/cells.csv", ["scripts/model_vs_sim.py", "{tmp}", "{tmp}/model_vs_sim.png"],
              copy=("results/model/gpgpusim/runs",), produced="cells.csv"),
    Generated("results/denoise/table.md", ["scripts/denoise_table.py", *DENOISE]),
    Generated("results/denoise/table_uncorrected.md", ["scripts/denoise_table.py", *DENOISE, "--uncorrected"]),
    Generated("results/converge-480x270/seeds.md",
              ["scripts/converge_seeds.py", *SEEDS]),
    Generated("results/model/device-path-tracer/prediction.md",
              ["scripts/reference_time_prediction.py",
               "results/model/device-path-tracer/converge_sibenik_lamps_1920x1080.csv"]),
]
CHECKS.append(Embedded("results/model/gpgpusim/README.md", "results/model/gpgpusim/table.md",
                       "`table.md` (generated by scripts/model_vs_sim.py), as of this commit:"))
