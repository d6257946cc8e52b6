"""Figures read from Nsight Compute logs (measured on the GPU): results/gpu/h100-9566ba3/README.md (what the two
trace kernels execute, `counts-*.log` per ray of the batch the `counts-*-table.csv` rows count) and the CWBVH
profile of results/gpu/h100-9bc790a/README.md (`ncu-cwbvh.log` beside the BVH2's `../h100-41d9445/ncu.log`).

Each batch is launched twice under ncu (launches 0-1 camera rays, 2-3 noopt, 4-5 ours); the READMEs quote the
first launch of each batch."""
from results_checks.checks_gpu import too_fast
from results_checks.core import Figure, Unrecorded
from results_checks.logs import ncu
from results_checks.rows import select, total

R = "results/gpu/h100-9566ba3/"
BATCHES = ("primary", "noopt", "ours")
KERNELS = {"BVH2": "bvh2", "CWBVH": "cwbvh"}


def launch(batch):
    return 2 * BATCHES.index(batch)


def per_ray(kernel, batch, *metrics):
    """The sum of `metrics` of the batch's first launch over the batch's rays (its row of counts-*-table.csv)."""
    tracer = "cuda:cwbvh" if kernel == "cwbvh" else "cuda"
    rays = float(select(f"{R}counts-{kernel}-table.csv", "sibenik", batch, tracer)[0]["rays"])
    return sum(ncu(f"{R}counts-{kernel}.log", launch(batch), m) for m in metrics) / rays


def counts_row(name, batch):
    """A row of the table: instructions, data-stage and tag-stage wavefronts, global load requests, local
    requests (ld + st), L1-missing sectors per ray, and the SM cycles (the busiest SM, millions)."""
    kernel = KERNELS[name]

    def values():
        return (per_ray(kernel, batch, "smsp__inst_executed.sum"),
                per_ray(kernel, batch, "l1tex__data_pipe_lsu_wavefronts.sum"),
                per_ray(kernel, batch, "l1tex__t_output_wavefronts_pipe_lsu_mem_global_op_ld.sum"),
                per_ray(kernel, batch, "l1tex__t_requests_pipe_lsu_mem_global_op_ld.sum"),
                per_ray(kernel, batch, "l1tex__t_requests_pipe_lsu_mem_local_op_ld.sum",
                        "l1tex__t_requests_pipe_lsu_mem_local_op_st.sum"),
                per_ray(kernel, batch, "l1tex__t_sectors_pipe_lsu_mem_global_op_ld_lookup_miss.sum"),
                ncu(f"{R}counts-{kernel}.log", launch(batch), "sm__cycles_elapsed.max") / 1e6)
    return Figure(R + "README.md", f"| {name} {batch} | {{:.1f}} | {{:.1f}} | {{:.1f}} | {{:.2f}} | {{:.2f}} | "
                  "{:.2f} | {:.2f} M |", values)


def run_9566ba3():
    readme = R + "README.md"
    data = "l1tex__data_pipe_lsu_wavefronts.sum"
    inst = "smsp__inst_executed.sum"
    local = ("l1tex__t_requests_pipe_lsu_mem_local_op_ld.sum", "l1tex__t_requests_pipe_lsu_mem_local_op_st.sum")
    group = "results/gpu/h100-6f75752/table-group.csv"
    return [counts_row(n, b) for n in KERNELS for b in BATCHES] + [
        Figure(readme, "to the digit ({:.1f}, {:.1f}, {:.1f} wavefronts per ray)", lambda: (
            per_ray("bvh2", "noopt", data), per_ray("bvh2", "ours", data), per_ray("bvh2", "primary", data))),
        Figure(readme, "executes {:.2f}× the BVH2's instructions on noopt ({:.1f} / {:.1f}) and moves {:.2f}× its L1 "
               "data ({:.1f} / {:.1f})", lambda: (
                   per_ray("cwbvh", "noopt", inst) / per_ray("bvh2", "noopt", inst), per_ray("cwbvh", "noopt", inst),
                   per_ray("bvh2", "noopt", inst), per_ray("cwbvh", "noopt", data) / per_ray("bvh2", "noopt", data),
                   per_ray("cwbvh", "noopt", data), per_ray("bvh2", "noopt", data))),
        Figure(readme, "issue-bound ({:.0f}% of issue slots, `../h100-6f75752/ncu-cwbvh.log`), so its {:.2f}× speed-up",
               lambda: (ncu("results/gpu/h100-6f75752/ncu-cwbvh.log", launch("noopt"), "Issue Slots Busy"),
                        total(group, "trace_ms", "sibenik", "noopt", "cuda")
                        / total(group, "trace_ms", "sibenik", "noopt", "cuda:cwbvh"))),
        Figure(readme, "Its local memory traffic ({:.1f} requests per ray)", lambda: per_ray("cwbvh", "noopt", *local)),
    ]


def run_9bc790a():
    readme, log = "results/gpu/h100-9bc790a/README.md", "results/gpu/h100-9bc790a/ncu-cwbvh.log"
    bvh2 = "results/gpu/h100-41d9445/ncu.log"
    noopt = launch("noopt")
    return [
        Figure(readme, "issue-bound — SM issue {:.1f}% of peak, L1/TEX {:.0f}%, IPC {:.2f}, {:.0f} registers ({:.0f} "
               "blocks of 128 per SM, {:.0f}% achieved occupancy); the BVH2 kernel on the same rays is L1-bound ({:.1f}% "
               "L1, {:.0f}% issue)", lambda: (
                   ncu(log, noopt, "Issue Slots Busy"), ncu(log, noopt, "L1/TEX Cache Throughput"),
                   ncu(log, noopt, "Executed Ipc Active"), ncu(log, noopt, "Registers Per Thread"),
                   ncu(log, noopt, "Block Limit Registers"), ncu(log, noopt, "Achieved Occupancy"),
                   ncu(bvh2, noopt, "L1/TEX Cache Throughput"), ncu(bvh2, noopt, "Issue Slots Busy"))),
        Figure(readme, "no faster (noopt {:.2f} ms against {:.2f} ms under ncu's locked clock)", lambda: (
            ncu(log, noopt, "Duration") / 1e6, ncu(bvh2, noopt, "Duration") / 1e6)),
    ]


N = "results/gpu/h100-9bc790a-ncu/"
METRICS = {"data": "l1tex__data_pipe_lsu_wavefronts.sum", "global": "l1tex__t_requests_pipe_lsu_mem_global_op_ld.sum",
           "sectors": "l1tex__t_sectors_pipe_lsu_mem_global_op_ld.sum",
           "local_ld": "l1tex__t_requests_pipe_lsu_mem_local_op_ld.sum",
           "local_st": "l1tex__t_requests_pipe_lsu_mem_local_op_st.sum", "inst": "smsp__inst_executed.sum",
           "cycles": "sm__cycles_elapsed.avg"}
H100_MHZ = 1980  # simt/gpu_presets.cpp, the h100 preset's clock


def counted(batch, *names):
    """The sum of the named metrics of the batch's first launch in ncu-metrics.log."""
    return sum(ncu(N + "ncu-metrics.log", launch(batch), METRICS[n]) for n in names)


def rays(batch):
    return float(select(N + "model.csv", "sibenik", batch, "simt")[0]["rays"])


def ray_count(batch, *names):
    return counted(batch, *names) / rays(batch)


def warp_count(batch, *names):
    return counted(batch, *names) / (rays(batch) / 32)


def modeled(batch, field):
    return total(N + "model.csv", field, "sibenik", batch, "simt")


def most_modeled(batch):
    """The most L1 wavefronts the model's timeline can hold: one per SM and cycle over its modeled time."""
    sms = int(dict(p.split("=") for p in select(N + "model.csv", "sibenik", batch, "simt")[0]["tracer_params"]
                   .split(","))["sms"])
    return modeled(batch, "modeled_ms") * 1e-3 * H100_MHZ * 1e6 * sms


def per_ray_row(batch):
    def values():
        wf, local = "modeled_l1_wavefronts_per_ray", "modeled_l1_local_wavefronts_per_ray"
        return (modeled(batch, wf), ray_count(batch, "data"), ray_count(batch, "data") / modeled(batch, wf),
                modeled(batch, local), ray_count(batch, "local_ld", "local_st"), ray_count(batch, "global"))
    return Figure(N + "README.md", f"| {batch} | {{:.1f}} | {{:.1f}} | {{:.2f}} | {{:.1f}} | {{:.1f}} | {{:.1f}} |", values)


def run_9bc790a_ncu():
    readme = N + "README.md"
    cols = ("data", "global", "sectors", "local_ld", "local_st", "inst", "cycles")
    gap = {b: ray_count(b, "data") / modeled(b, "modeled_l1_wavefronts_per_ray") for b in ("noopt", "ours")}
    too_fast = {b: gpu_too_fast(b) for b in ("noopt", "ours")}
    hw_global, model_global = global_wavefronts()
    return [
        Unrecorded(readme, "20.5 s on the device", "`gpu-carry` from `scripts/gpu-check prepare` at 9bc790a"),
        *(Figure(readme, f"| {b} | " + " | ".join(["{:.1f} M"] * 6 + ["{:.2f} M"]) + " |",
                 lambda b=b: tuple(counted(b, c) / 1e6 for c in cols)) for b in ("noopt", "ours")),
        Figure(readme, "Per warp of 32 rays (noopt): {:,.0f} wavefronts, {:,.0f} global and {:,.0f} local ({:,.0f} load + "
               "{:,.0f} store) memory instructions, {:,.0f} instructions", lambda: (
                   warp_count("noopt", "data"), warp_count("noopt", "global"),
                   warp_count("noopt", "local_ld", "local_st"), warp_count("noopt", "local_ld"),
                   warp_count("noopt", "local_st"), warp_count("noopt", "inst"))),
        Figure(readme, "over its modeled {:.3f} ms (noopt) at its {} MHz on 132 SMs it can have counted at most {:.0f} M "
               "wavefronts; the hardware needed **{:.0f} M, at least {:.2f}× that** (ours: at most {:.0f} M modeled in "
               "{:.3f} ms, {:.0f} M measured, at least {:.2f}×)", lambda: (
                   modeled("noopt", "modeled_ms"), H100_MHZ, most_modeled("noopt") / 1e6, counted("noopt", "data") / 1e6,
                   counted("noopt", "data") / most_modeled("noopt"), most_modeled("ours") / 1e6,
                   modeled("ours", "modeled_ms"), counted("ours", "data") / 1e6,
                   counted("ours", "data") / most_modeled("ours"))),
        Figure(readme, "({:.2f}× and {:.2f}× on these batches)",
               lambda: (too_fast["noopt"], too_fast["ours"])),
        Figure(readme, "half of the kernel's memory instructions ({:,.0f} of {:,.0f} per warp)", lambda: (
            warp_count("noopt", "local_ld", "local_st"), warp_count("noopt", "global", "local_ld", "local_st"))),
        *(per_ray_row(b) for b in ("primary", "noopt", "ours")),
        Figure(readme, "For coherent rays (primary) the model's L1 work is the hardware's within {:.0%}; the incoherent "
               "batches need {:.2f}–{:.2f}× the model's wavefronts, the same factor as their time ({:.2f}–{:.2f}×)",
               lambda: (abs(ray_count("primary", "data") / modeled("primary", "modeled_l1_wavefronts_per_ray") - 1),
                        min(gap.values()), max(gap.values()), min(too_fast.values()), max(too_fast.values()))),
        Figure(readme, "{:.1f} local requests per ray on hardware against {:.1f} modeled local wavefronts (noopt)",
               lambda: (ray_count("noopt", "local_ld", "local_st"), modeled("noopt",
                                                                            "modeled_l1_local_wavefronts_per_ray"))),
        Figure(readme, "noopt's global loads take {:.0f} wavefronts per ray on the H100 ({:.1f} per request, {:.1f} "
               "sectors per request) against about {:.0f} in the model", lambda: (
                   hw_global, hw_global / ray_count("noopt", "global"),
                   counted("noopt", "sectors") / counted("noopt", "global"), model_global)),
        Figure(readme, "undercounts divergent loads by about {:.2f}×", undercount),
    ]


def global_wavefronts():
    """noopt's global-load wavefronts per ray on the H100 (all wavefronts less one per local request) and in the
    model (all less its local ones)."""
    return (ray_count("noopt", "data") - ray_count("noopt", "local_ld", "local_st"),
            modeled("noopt", "modeled_l1_wavefronts_per_ray") - modeled("noopt", "modeled_l1_local_wavefronts_per_ray"))


def undercount():
    hw, model = global_wavefronts()
    return hw / model


def gpu_too_fast(batch):
    """The MODELED trace speed over the measured one on the same batch (../h100-41d9445/table-comparison.csv)."""
    return too_fast("results/gpu/h100-41d9445/table-comparison.csv", "sibenik", batch)


CHECKS = run_9566ba3() + run_9bc790a() + run_9bc790a_ncu()
