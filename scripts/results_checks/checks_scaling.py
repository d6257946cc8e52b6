"""results/gpu/h100-9bc790a/README.md: the trace kernel from 2 K to 2 M rays (`scaling-WxH.csv`), measured `cuda`
beside MODELED `simt:preset=h100`; each ratio to noopt from the same file and tracer."""
from results_checks.core import Figure
from results_checks.rows import lo_hi, median, pct, speedup, total

R = "results/gpu/h100-9bc790a/"
SIZES = ("64x48", "240x136", "480x272", "960x540", "1920x1080")
METHODS = ("primary", "noopt", "ours", "ours:order=group", "contiguous")
SECONDARY = METHODS[1:]


def path(size):
    return f"{R}scaling-{size}.csv"


def measured_ms(scene, size, method):
    return total(path(size), "trace_ms", scene, method)


def modeled_ms(scene, size, method):
    return total(path(size), "modeled_ms", scene, method, "simt")


def share(scene, size, method):
    """MODELED ms over measured ms."""
    return modeled_ms(scene, size, method) / measured_ms(scene, size, method)


def miss(scene, size, method):
    """The MODELED ratio to noopt over the measured one, minus 1."""
    return pct(speedup(path(size), scene, method, "simt"), speedup(path(size), scene, method))


def rays(scene, size, method):
    return total(path(size), "rays", scene, method)


def cells(scene, sizes, methods=METHODS):
    return [(scene, z, m) for z in sizes for m in methods]


def small_fixed_cost():
    """Measured − modeled trace time (µs) of cornell's secondary cells at 64×48 and 240×136."""
    return [1000 * (measured_ms(*c) - modeled_ms(*c)) for c in cells("cornell", SIZES[:2], SECONDARY)]


def few_rays(scene):
    return [c for c in cells(scene, SIZES) if rays(*c) < 100_000]


def findings(readme):
    small = cells("cornell", SIZES[:2], SECONDARY)
    big = cells("sibenik", SIZES[3:], ("primary", *SECONDARY[1:]))
    full = cells("sibenik", SIZES[3:]) + cells("cornell", SIZES[4:], SECONDARY)
    cornell_1080 = [measured_ms("cornell", "1920x1080", m) for m in METHODS]
    return [
        Figure(readme, "never takes less than {:.0f}–{:.0f} µs (cornell's secondary rays, {:.0f} K–{:.0f} K rays), the "
               "model {:.1f}–{:.1f} µs: launch and the CUDA-event pair cost {:.0f}–{:.0f} µs (measured − modeled, "
               "median {:.0f} µs)", lambda: (
                   *lo_hi(1000 * measured_ms(*c) for c in small), *lo_hi(rays(*c) / 1000 for c in small),
                   *lo_hi(1000 * modeled_ms(*c) for c in small), *lo_hi(small_fixed_cost()),
                   median(small_fixed_cost()))),
        Figure(readme, "Below about 100 K rays the modeled ÷ measured time is {:.2f}–{:.2f} on cornell and {:.2f}–{:.2f} "
               "on sibenik", lambda: (*lo_hi(share(*c) for c in few_rays("cornell")),
                                      *lo_hi(share(*c) for c in few_rays("sibenik")))),
        Figure(readme, "every ratio to noopt is within {:.0%} … {:+.1%} of the measured one", lambda: lo_hi(
            miss(*c) for c in big)),
        Figure(readme, "(960×540: ours {:.3f} measured, {:.3f} modeled; group {:.3f} / {:.3f}; contiguous {:.3f} / "
               "{:.3f})", lambda: tuple(speedup(path("960x540"), "sibenik", m, t) for m in SECONDARY[1:]
                                        for t in ("cuda", "simt"))),
        Figure(readme, "its whole 1080p trace takes {:.2f}–{:.2f} ms, so the fixed cost above is {:.0f}–{:.0%} of it) "
               "at 1080p: secondary ratios {:+.1f} … {:+.1%}, but primary {:.2f} modeled against {:.2f} measured; at "
               "960×540 {:+.0f} … {:+.0%}", lambda: (
                   *lo_hi(cornell_1080), 100 * median(small_fixed_cost()) / 1000 / max(cornell_1080),
                   median(small_fixed_cost()) / 1000 / min(cornell_1080),
                   100 * min(miss("cornell", "1920x1080", m) for m in SECONDARY[1:]),
                   max(miss("cornell", "1920x1080", m) for m in SECONDARY[1:]),
                   speedup(path("1920x1080"), "cornell", "primary", "simt"),
                   speedup(path("1920x1080"), "cornell", "primary"),
                   100 * min(miss("cornell", "960x540", m) for m in SECONDARY[1:]),
                   max(miss("cornell", "960x540", m) for m in SECONDARY[1:]))),
        Figure(readme, "At 240×136 on sibenik ({:.0f} K rays, a fraction of one wave of the persistent kernel) the model "
               "gives ours {:.3f}× and the hardware {:.3f}×; at 64×48 the hardware shows no gain at all ({:.2f}–{:.2f}×)",
               lambda: (rays("sibenik", "240x136", "noopt") / 1000, speedup(path("240x136"), "sibenik", "ours", "simt"),
                        speedup(path("240x136"), "sibenik", "ours"),
                        *lo_hi(speedup(path("64x48"), "sibenik", m) for m in SECONDARY[1:]))),
        Figure(readme, "modeled ÷ measured {:.2f}–{:.2f} on sibenik from 960×540 up, {:.2f}–{:.2f} on cornell at 1080p: "
               "the model is {:.1f}–{:.1f}× too fast", lambda: (
                   *lo_hi(share(*c) for c in cells("sibenik", SIZES[3:])),
                   *lo_hi(share(*c) for c in cells("cornell", SIZES[4:], SECONDARY)),
                   *lo_hi(1 / share(*c) for c in full))),
    ]


CHECKS = findings(R + "README.md")
