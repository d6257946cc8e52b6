"""Figures read from Nsight Compute logs (measured on the GPU): results/gpu/h100-9566ba3/README.md (what the two
trace kernels execute, `counts-*.log` per ray of the batch the `counts-*-table.csv` rows count) and the CWBVH
profile of results/gpu/h100-9bc790a/README.md (`ncu-cwbvh.log` beside the BVH2's `../h100-41d9445/ncu.log`).

Each batch is launched twice under ncu (launches 0-1 camera rays, 2-3 noopt, 4-5 ours); the READMEs quote the
first launch of each batch."""
from results_checks.core import Figure
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


CHECKS = run_9566ba3() + run_9bc790a()
