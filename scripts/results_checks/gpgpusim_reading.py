"""What the checks of results/model/stage-counters/gpgpusim/README.md read (checks_stage_gpgpusim.py): the stats
files' tables (made by scripts/gpgpusim_stage_stats.py), beside-model.md, the predictions, the H200 diagnosis,
commands.txt's wall times and the runs' gpgpusim.config; the bands and ratios the README's prose quotes."""
import re

from results_checks.rows import ROOT

D = "results/model/stage-counters/gpgpusim"


README = f"{D}/README.md"


BESIDE = f"{D}/beside-model.md"


DIAGNOSIS = "results/model/stage-counters/diagnosis-6ebd003.md"


# run folder -> (scene, prediction, every kernel or the two generators only)
RUNS = {"cornell-64x64": ("cornell", "prediction.csv", True), "sibenik-64x64": ("sibenik", "prediction.csv", True),
        "cornell-64x64-cta1": ("cornell", "prediction.csv", True),
        "cornell-32x32-cta1": ("cornell", "prediction-32x32.csv", True),
        "sibenik-32x32-cta1": ("sibenik", "prediction-32x32.csv", True),
        "cornell-64x64-l1banks16": ("cornell", "prediction.csv", False),
        "cornell-64x64-misslat20": ("cornell", "prediction.csv", False),
        "cornell-64x64-missq256": ("cornell", "prediction.csv", False),
        "cornell-64x64-alu2": ("cornell", "prediction.csv", False)}


# the G-buffer record's four 16-byte loads: their lines in the kernels' PTX (raycoh.6 and raycoh.7.sm_86.ptx)
RECORD = {"noopt_kernel": ("125", "129", "133", "137"), "group_kernel": ("111", "115", "119", "123")}


N, G = "noopt_kernel", "group_kernel"


def stats_command(name):
    scene, prediction, every = RUNS[name]
    kernels = [] if every else ["--kernels", "noopt_kernel,group_kernel"]
    return ["scripts/gpgpusim_stage_stats.py", *kernels, "--ptx-stats", f"{D}/runs/{name}/gpgpu_inst_stats.txt.xz",
            "--prediction", f"{D}/{prediction}", "--scene", scene, f"{D}/runs/{name}/gpgpusim.log.xz"]


def number(cell):
    cell = cell.strip().strip("*`")
    try:
        return float(cell.replace(",", ""))
    except ValueError:
        return cell


def tables(path):
    """Every markdown table of `path` as a list of rows, each a dict from its header's cells to the cell's value
    (a number where it reads as one)."""
    out, header = [], None
    for line in (ROOT / path).read_text().splitlines():
        if not line.startswith("|"):
            header = None
            continue
        cells = [c.strip() for c in line.strip()[1:-1].split("|")]
        if header is None:
            header, rows = [], []
            for h in cells:  # a repeated column name (the second 'ratio') gets ' 2'
                header.append(h + " 2" if h in header else h)
            out.append(rows)
        elif not set(line) <= set("|-: "):
            rows.append({h: number(c) if i else c for i, (h, c) in enumerate(zip(header, cells))})
    return out


def table(path, column):
    """The rows of the table of `path` that has the column `column`."""
    return next(t for t in tables(path) if t and column in t[0])


def launch(run, kernel, column, n=2):
    """A column of launch n of `kernel` in stats-RUN.md's launch tables."""
    rows = table(f"{D}/stats-{run}.md", column)
    return next(r[column] for r in rows if r["kernel"] == kernel and r["n"] == n)


def life(run, kernel):
    return launch(run, kernel, "block lifetime mean")


def latency(run, kernel, cls, column="mean latency"):
    rows = table(f"{D}/stats-{run}.md", "share %")
    return next(r[column] for r in rows if r["kernel"] == kernel and r["class"] == cls)


def record(run, kernel):
    """The G-buffer record's four loads: (least, most) mean latency."""
    rows = table(f"{D}/stats-{run}.md", "PTX line")
    lat = [r["mean latency"] for r in rows if r["kernel"] == kernel and f"{r['PTX line']:.0f}" in RECORD[kernel]]
    assert len(lat) == 4, (run, kernel, lat)
    return min(lat), max(lat)


def records(runs, kernels):
    r = [x for run in runs for k in kernels for x in record(run, k)]
    return min(r), max(r)


def down(run, kernel):
    """A what-if's change of the mean block lifetime against the RTX 3070 configuration, %."""
    return round(100 * (life(run, kernel) / life("cornell-64x64", kernel) - 1))


def beside(label, kernel, column):
    rows = table(BESIDE, "chain, MODELED")
    return next(r[column] for r in rows if r["scene"] == label and r["kernel"] == kernel)


def issue(label, kernel, column):
    rows = table(BESIDE, "issued %")
    return next(r[column] for r in rows if r["pass"] == label and r["kernel"] == kernel)


LOADED, ALONE = ("cornell", "sibenik"), ("cornell 64×64, one block per SM", "cornell 32×32, one block per SM",
                                         "sibenik 32×32, one block per SM")


LOADED_PASS = ("cornell 64×64", "sibenik 64×64")


ALONE_PASS = ("cornell 64×64, one block", "cornell 32×32, one block", "sibenik 32×32, one block")


def band(values, digits=None):
    values = [v if digits is None else round(v, digits) for v in values]
    return min(values), max(values)


def chain_ratio(label, kernel):
    return beside(label, kernel, "ratio 2")  # the second 'ratio' column: chain / block lifetime


def lifetime_ratio(label, kernel):
    """block lifetime / chain (the README's '0.79×': how long a block lives against the model's chain)."""
    return beside(label, kernel, "block lifetime, SIMULATED") / beside(label, kernel, "chain, MODELED")


def factor(loaded, alone, kernel):
    """How much longer a block lives loaded than alone."""
    return beside(loaded, kernel, "block lifetime, SIMULATED") / beside(alone, kernel, "block lifetime, SIMULATED")


def h200(method, column):
    rows = table(DIAGNOSIS, "block chain, modeled")
    return next(r[column] for r in rows if r["method"] == method and r["kernel"] == "gen")


def wall(name):
    """A command's wall time (s) in commands.txt (a run's NAME, or the output file a functional command wrote)."""
    for line in (ROOT / f"{D}/commands.txt").read_text().splitlines():
        if line.startswith(name + " ") or f"--out {name})" in line:
            return int(re.search(r"\s(\d+) s\s", line).group(1))
    raise KeyError(name)


def config(run, option):
    """The last value of `option` in runs/RUN/gpgpusim.config (options appended at its end override)."""
    found = re.findall(rf"^{re.escape(option)}\s+(\S+)", (ROOT / f"{D}/runs/{run}/gpgpusim.config").read_text(),
                       re.M)
    return found[-1]


def rng(values, digits=0, sep="–"):
    """'a–b' of the values rounded to `digits` (thousands separated), or 'a' where both ends round alike."""
    lo, hi = (f"{x:,.{digits}f}" for x in band(values))
    return lo if lo == hi else f"{lo}{sep}{hi}"


def preset(name):
    """A latency of simt/gpu_presets.cpp's gpgpusim-rtx3070 preset (a sum written a + b added up)."""
    text = (ROOT / "simt/gpu_presets.cpp").read_text().split("GpuModelConfig gpgpusim_rtx3070()")[1]
    return sum(int(x) for x in re.search(rf"g\.{name} = ([\d +]+);", text).group(1).split("+"))


def model(name):
    """The stage model's sm_86 constant (simt/stage_model.cpp, its second setting: the sm_86 constants)."""
    return int(re.findall(rf"c\.{name} = (\d+);", (ROOT / "simt/stage_model.cpp").read_text())[1])


def cub_scan(run="cornell-64x64", n=2):
    """CUB's scan kernel's block lifetime in launch n (one block): gpgpusim_stage_stats.py's reading of the log."""
    import sys
    sys.path.insert(0, str(ROOT / "scripts"))
    from gpgpusim_stage_stats import launches, lifetimes, read_log
    blocks = read_log(str(ROOT / f"{D}/runs/{run}/gpgpusim.log.xz"))
    ((b,),) = [[b for i, _, b in launches(blocks, ["cub scan"]) if i == n]]
    assert b["blocks"] == 1
    return lifetimes(b)[0]


def same_threads(kernel):
    """A thread's PTX instructions (all classes), loaded and alone on cornell 64×64: the same pass, so equal."""
    loaded, alone = (latency(r, kernel, "all", "executions / thread") for r in ("cornell-64x64", "cornell-64x64-cta1"))
    assert loaded == alone, (kernel, loaded, alone)
    return loaded


def icount_differs():
    """The largest relative difference of the warp-instruction counter, loaded against alone (cornell 64×64)."""
    return max(abs(launch("cornell-64x64-cta1", k, "warp insts") / launch("cornell-64x64", k, "warp insts") - 1)
               for k in (N, G))


def shares(run, kernel, classes):
    rows = table(f"{D}/stats-{run}.md", "share %")
    return sum(r["share %"] for r in rows if r["kernel"] == kernel and r["class"] in classes)


def lat_row(kernel, classes):
    """Executions a thread (loaded) and the mean latency loaded and alone of each class, cornell 64×64."""
    return (*(latency("cornell-64x64", kernel, c, "executions / thread") for c in classes),
            *(latency("cornell-64x64", kernel, c) for c in classes),
            *(latency("cornell-64x64-cta1", kernel, c) for c in classes))


SFU = ("SFU (rcp/sqrt/sin/cos/ex2/lg2)", "div/rem (SFU unit)", "barrier")


WHATIFS = ("cornell-64x64-l1banks16", "cornell-64x64-misslat20", "cornell-64x64-alu2", "cornell-64x64-missq256",
           "cornell-64x64-cta1")


L1D = "L1D accesses / misses / pending hits / reservation fails"


def reservation_fails(run, kernel=N):
    return float(launch(run, kernel, L1D).split(" / ")[3].replace(",", ""))


def record_band():
    """The G-buffer record's loads, loaded (cornell 64×64, both kernels), to the nearest 50 cycles."""
    return rng([round(x / 50) * 50 for x in records(["cornell-64x64"], (N, G))])


def loaded_band(kernel, column, digits=0):
    return rng([issue(p, kernel, column) for p in LOADED_PASS], digits)


SB, IDLE = "W0_Scoreboard % (no warp ready: all wait on a register)", \
    "W0_Idle % (no valid instruction: barrier, empty buffer, no warp)"


STALL, MEM = "Stall % (a warp ready, its unit or the memory stage full)", "memory stage stalled, % of cycles"


ALU = ("int/other ALU", "fp32 ALU")
