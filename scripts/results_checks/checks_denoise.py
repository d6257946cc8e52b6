"""results/denoise/README.md: raw and OIDN-denoised relMSE of each method over noopt's, from the converge CSVs
(one per scene and seed) as scripts/denoise_table.py reads them, and the two quality CSVs of the crops.

Ratios are per seed (the method's error over noopt's at the same seed and frame count) on the reference-noise-
corrected columns, summarised as the table does: the geometric mean over seeds; a range quoted 'a–b' over cells
is the smallest and largest of those means."""
import importlib.util
import re
import statistics

from results_checks.core import Embedded, Figure, Unrecorded
from results_checks.logs import text_lines
from results_checks.rows import ROOT, USED, load

D = "results/denoise/"
README = D + "README.md"
FRAMES = (1, 4, 16, 128)
SHARED = ("sadeghi", "microjitter")
QUIET = ("sibenik_lamps", "conference_lamps")  # the scenes without hybrid groups
CK = "country_kitchen"

_spec = importlib.util.spec_from_file_location("denoise_table", ROOT / "scripts" / "denoise_table.py")
_table = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_table)
gmean = _table.gmean
_data = {}


def converge_files():
    return sorted(str(p.relative_to(ROOT)) for p in (ROOT / D).glob("converge_*_seed*.csv")
                  if not p.name.endswith("-summary.csv"))


def data(corrected=True):
    """(errors, methods, seeds) as denoise_table.py reads them: errors[(scene, method, seed, frame)] = (raw,
    denoised)."""
    if corrected not in _data:
        cols = ("rel_mse_corr", "denoised_rel_mse_corr") if corrected else ("rel_mse", "denoised_rel_mse")
        files = converge_files()
        USED.update(files)
        _data[corrected] = _table.read([str(ROOT / f) for f in files], *cols)
    return _data[corrected]


def rows():
    """Every converge row with a denoised error (the power-of-two frame counts)."""
    return [r for f in converge_files() for r in load(f) if r["denoised_rel_mse"]]


def per_seed(scene, method, frames, which, corrected=True):
    """The method's error over noopt's per seed; which: 0 raw, 1 denoised, 2 denoised ratio / raw ratio."""
    errors, _, seeds = data(corrected)
    out = []
    for s in sorted(seeds[scene]):
        if (scene, method, s, frames) not in errors:
            continue
        v, b = errors[(scene, method, s, frames)], errors[(scene, "noopt", s, frames)]
        out.append((v[1] / b[1]) / (v[0] / b[0]) if which == 2 else v[which] / b[which])
    return out


def mean_ratio(scene, method, frames, which, corrected=True):
    return gmean(per_seed(scene, method, frames, which, corrected))


def means(scenes, methods, which, frames=FRAMES):
    values = [mean_ratio(s, m, f, which) for s in scenes for m in methods for f in frames]
    return min(values), max(values)


def excess(scene, method, frames, which):
    """The method's error minus noopt's, mean over seeds (the table's last column)."""
    errors, _, seeds = data()
    ss = sorted(seeds[scene])
    return sum(errors[(scene, method, s, frames)][which] - errors[(scene, "noopt", s, frames)][which]
               for s in ss) / len(ss)


def noopt_falls():
    """noopt's denoised error over its raw one, every scene and seed: (1–16 frames, 128 frames) lists."""
    errors = data()[0]
    low = [d / r for (sc, m, s, f), (r, d) in errors.items() if m == "noopt" and f <= 16]
    high = [d / r for (sc, m, s, f), (r, d) in errors.items() if m == "noopt" and f == 128]
    return low, high


def noise(scene):
    return float(next(r for r in rows() if r["scene"] == scene)["ref_noise_rel_mse"])


def noise_share(frames, column, method=None, scene=None):
    """The reference's relMSE noise over `column`, every row of the given frame counts (and method, scene)."""
    return [float(r["ref_noise_rel_mse"]) / float(r[column]) for r in rows() if int(r["frame"]) in frames
            and (method is None or r["method"] == method) and (scene is None or r["scene"] == scene)]


def denoised_share(scene):
    """The reference's noise over noopt's denoised relMSE at 128 frames (mean over seeds)."""
    values = [float(r["denoised_rel_mse"]) for r in rows()
              if r["scene"] == scene and r["method"] == "noopt" and r["frame"] == "128"]
    return noise(scene) / (sum(values) / len(values))


def sig2(x):
    """A figure written to two significant digits, as a whole number where it is one (282.8 -> '280')."""
    return f"{float(f'{x:.2g}'):g}"


def quality(name, method, column, base="noopt"):
    rows_ = {r["method"]: r for r in load(D + f"quality_{name}.csv")}
    return float(rows_[method][column]) / float(rows_[base][column])


def logged(path, pattern):
    """The first group of `pattern` on the first line of the log that holds it."""
    for line in text_lines(path):
        m = re.search(pattern, line)
        if m:
            return m.group(1)
    raise LookupError(f"{path}: no line matches {pattern!r}")


def uncorrected_cell(scene, method, frames):
    """The denoised ratio of table_uncorrected.md's row, recomputed on the plain errors."""
    return mean_ratio(scene, method, frames, 1, corrected=False)


def verdict_band():
    """denoise_table.py's 'about the same' band: the denoised / raw change within ±this."""
    source = (ROOT / "scripts" / "denoise_table.py").read_text()
    return float(re.search(r"1 / ([\d.]+) <= g <=", source).group(1)) - 1


def walls():
    """{scene: [wall seconds of seeds 1..5]} from run.sh's lines in run.log (a resumed run's 0 s left out)."""
    out = {}
    for line in text_lines(D + "run.log"):
        m = re.match(r"run.sh: (\S+) seed (\d+): (\d+) s wall", line)
        if m and m.group(3) != "0":
            out.setdefault(m.group(1), {})[int(m.group(2))] = int(m.group(3))
    return {s: [v[k] for k in sorted(v)] for s, v in out.items()}


def wall_row(scene, methods):
    return Figure(README, f"| {scene} ({methods} methods) | " + " | ".join(["{} s"] * 5) + " |",
                  lambda: tuple(walls()[scene]))


def setup_checks():
    ms = [float(r["denoise_ms"]) / 1000 for r in rows() if r["denoise_ms"]]
    return [
        Figure(README, "Their own noise (relMSE, from the two half references): sibenik_lamps {:.3g}, country_kitchen "
               "{:.3g}, conference_lamps {:.3g}. That is at most {:.0%} of every raw error at 1–16 frames, but "
               "{:.0f}–{:.0%} of the raw errors at 128 frames (noopt's {:.0f}–{:.0%}) and {:.0f}–{:.0%} of noopt's "
               "**denoised** error at 128 frames (sibenik_lamps {:.0%}, country_kitchen {:.0%}, conference_lamps "
               "{:.0%})", lambda: (
                   noise("sibenik_lamps"), noise(CK), noise("conference_lamps"),
                   max(noise_share((1, 2, 4, 8, 16), "rel_mse")),
                   100 * min(noise_share((128,), "rel_mse")), max(noise_share((128,), "rel_mse")),
                   100 * min(noise_share((128,), "rel_mse", "noopt")), max(noise_share((128,), "rel_mse", "noopt")),
                   100 * min(map(denoised_share, SCENES)), max(map(denoised_share, SCENES)),
                   *map(denoised_share, ("sibenik_lamps", CK, "conference_lamps")))),
        Figure(README, "the same verdicts except three cells near the {:.0%} or the every-seed line", verdict_band),
        Figure(README, "(country_kitchen ours {:.2f}× instead of {:.2f}×)", lambda: (
            uncorrected_cell(CK, "ours", 128), mean_ratio(CK, "ours", 128, 1))),
        Figure(README, "**Metric**: relMSE (ε = {})", lambda: logged(D + "run.log", r"relMSE \(eps ([\d.]+)\)")),
        Figure(README, "conference_lamps {} s. Quality "
               "runs: sibenik_lamps {:.1f} s, country_kitchen {:.1f} s. Denoiser: {:.2f}–{:.2f} s per 480×270 image, "
               "median {:.2f} s", lambda: (
                   logged(D + "run.log", r"rendered 512 frames in ([\d.]+) s -> \S*conference_lamps"),
                   float(logged(D + "quality_sibenik_lamps_4frames.log", r"quality wall ([\d.]+) s")),
                   float(logged(D + "quality_country_kitchen_128frames.log", r"quality ck wall ([\d.]+) s")),
                   min(ms), max(ms), statistics.median(ms))),
        Figure(README, "a scene's slowest run took {:.0f}–{:.0f}× its fastest", lambda: (
            min(max(v) / min(v) for v in walls().values()), max(max(v) / min(v) for v in walls().values()))),
        wall_row("sibenik_lamps", 5), wall_row(CK, 6), wall_row("conference_lamps", 6),
        Unrecorded(README, "References: sibenik_lamps 610.9 s, country_kitchen 845.2 s",
                   "(the console's, in no committed log)"),
    ]


SCENES = ("sibenik_lamps", CK, "conference_lamps")


def answer_checks():
    low, high = noopt_falls()
    every = [(s, m, f) for s in SCENES for m in SHARED for f in FRAMES]
    agree = sum(min(per_seed(s, m, f, 2)) > 1 for s, m, f in every)
    single = max(v for s, m, f in every for v in per_seed(s, m, f, 1))
    falls = [1 / v for v in low + high]
    ds8 = [quality("sibenik_lamps_4frames", m, "denoised_rel_mse_ds8") for m in SHARED]
    ours_quiet = means(QUIET, ("ours",), 1)
    ours_early = max(mean_ratio("sibenik_lamps", "ours", f, 1) for f in (1, 4)) - 1
    donor = means((CK,), ("ours:hybrid=donor",), 1)
    return [
        Figure(README, "is {:.2g}–{:.2f} at 1–16 frames (every scene and seed) and {:.2f}–{:.2f} at 128 frames: the "
               "denoised error is {:.0f}–{}× below the raw one at 1–16 frames and {:.0f}–{:.0f}× at 128.", lambda: (
                   min(low), max(low), min(high), max(high), 1 / max(low), sig2(1 / min(low)),
                   1 / max(high), 1 / min(high))),
        Figure(README, "(every seed in {} of the {} scene × frame cells, the mean in all). Raw, they are {:.2f}–{:.2f}× "
               "noopt", lambda: (agree, len(every), *means(SCENES, SHARED, 0))),
        Figure(README, "denoised they are {:.2f}–{:.2f}× noopt (geometric means over seeds; single seeds up to {:.0f}×)",
               lambda: (*means(SCENES, SHARED, 1), single)),
        Figure(README, "while noopt's own error falls {:.0f}–{}×, and the {}× downsampled denoised relMSE "
               "(`denoised_rel_mse_ds8` in `quality_sibenik_lamps_4frames.csv`) is {:.0f}–{:.0f}× noopt's", lambda: (
                   min(falls), sig2(max(falls)), "8", min(ds8), max(ds8))),
        Figure(README, "ours is within about ±{:.0%} of noopt after denoising ({:.2f}–{:.2f}), as it was before "
               "({:.2f}–{:.2f} raw)", lambda: (
                   max(abs(v - 1) for v in ours_quiet), *ours_quiet, *means(QUIET, ("ours",), 0))),
        Figure(README, "except up to {:.0%} at 1–4 frames on sibenik_lamps", lambda: ours_early),
        Figure(README, "On country_kitchen ({:.0%} of its first-bounce rays are hybrid-diffuse in "
               "`quality_country_kitchen_128frames.csv`)", lambda: float(
                   load(D + "quality_country_kitchen_128frames.csv")[1]["hybrid_diffuse_share"])),
        Figure(README, "raw {:.2f}–{:.2f}×, denoised {:.2f}–{:.2f}× noopt ({:.2f}, {:.2f}, {:.2f}, {:.2f} at 1, 4, 16, "
               "128 frames)", lambda: (*means((CK,), ("ours",), 0), *means((CK,), ("ours",), 1),
                                       *(mean_ratio(CK, "ours", f, 1) for f in FRAMES))),
        Figure(README, "({:.3g} and {:.2g} relMSE at 128 frames)", lambda: (
            excess(CK, "ours", 128, 0), excess(CK, "ours", 128, 1))),
        Figure(README, "rule's bias ({:.1f}% bright on hybrid-diffuse pixels there", lambda: float(logged(
            "results/hybrid-reuse/hybrid_bias_country_kitchen.txt", r"^ours\s+\S+\s+\+([\d.]+)%"))),
        Figure(README, "country_kitchen {:.2f}–{:.2f}× raw and {:.2f}–{:.2f}× denoised: within {:.0%} of noopt",
               lambda: (*means((CK,), ("ours:hybrid=donor",), 0), *donor, max(abs(v - 1) for v in donor))),
        Figure(README, "(its excess over noopt at 128 frames below {:.1g} relMSE, raw and denoised)", lambda: max(
            abs(excess(CK, "ours:hybrid=donor", 128, i)) for i in (0, 1))),
        Figure(README, "About the same on sibenik_lamps and conference_lamps ({:.2f}–{:.2f}× denoised", lambda: means(
            QUIET, ("contiguous",), 1)),
        Figure(README, "(denoised {:.2f}–{:.2f}× from {:.2f}–{:.2f}× raw: the same bias as ours's, about half as much, "
               "excess {:.2g} raw and {:.2g} denoised at 128 frames)", lambda: (
                   *means((CK,), ("contiguous",), 1), *means((CK,), ("contiguous",), 0),
                   excess(CK, "contiguous", 128, 0), excess(CK, "contiguous", 128, 1))),
    ]


def crop_checks():
    sib, ck = "sibenik_lamps_4frames", "country_kitchen_128frames"
    means1 = [sum(v) / len(v) for v in ([data()[0][(s, "noopt", seed, 1)][0] for seed in data()[2][s]]
                                        for s in SCENES)]
    return [
        Figure(README, "denoised relMSE {:.2f}× and {:.2f}× noopt's, raw {:.2f}× and {:.2f}×; `ours` {:.2f}× / "
               "{:.2f}×, `contiguous` {:.2f}× / {:.2f}×", lambda: (
                   *(quality(sib, m, "denoised_rel_mse") for m in SHARED), *(quality(sib, m, "rel_mse") for m in SHARED),
                   *(quality(sib, m, c) for m in ("ours", "contiguous") for c in ("denoised_rel_mse", "rel_mse")))),
        Figure(README, "denoised relMSE ours {:.2f}×, contiguous {:.2f}×, ours:hybrid=donor {:.2f}× noopt's; its "
               "`denoised_rel_mse_ds8`, the error that survives {}× downsampling, is {:.1f}× noopt's for ours and "
               "{:.2f}× for ours:hybrid=donor", lambda: (
                   *(quality(ck, m, "denoised_rel_mse") for m in ("ours", "contiguous", "ours:hybrid=donor")), "8",
                   *(quality(ck, m, "denoised_rel_mse_ds8") for m in ("ours", "ours:hybrid=donor")))),
        Figure(README, "noopt's raw relMSE at 1 frame is {:.1f}–{:.0f})", lambda: (min(means1), max(means1))),
        Figure(README, "at 128 frames their noise is {:.0f}–{:.0%} of noopt's denoised error", lambda: (
            100 * min(map(denoised_share, SCENES)), max(map(denoised_share, SCENES)))),
    ]


def table_checks():
    return [Embedded(README, D + "table.md", f"### {s} (seeds") for s in ("conference_lamps", CK, "sibenik_lamps")]


CHECKS = setup_checks() + answer_checks() + crop_checks() + table_checks()
