"""results/model/stage-counters/gpgpusim/README.md: the generation kernels under GPGPU-Sim (SIMULATED) beside the
stage model (MODELED). Each stats-*.md made again by scripts/gpgpusim_stage_stats.py from its committed run folder
(runs/NAME/gpgpusim.log.xz, gpgpu_inst_stats.txt.xz and the PTX beside it; the commands of commands.txt, section 4);
beside-model.md (the README's two tables that combine the runs with the prediction) by
scripts/gpgpusim_stage_summary.py; the README's tables checked against it, and every figure its prose and its
latency and what-if tables quote recomputed from the stats files (the tables of a generated file), the predictions,
../diagnosis-6ebd003.md (the H200 figures), commands.txt (wall times) and the runs' gpgpusim.config."""
from results_checks.core import Embedded, Figure, Generated
from results_checks.gpgpusim_reading import (
    D, README, BESIDE, RUNS, N, G, stats_command, launch, life, latency, record, records, down, beside, issue,
    LOADED, ALONE, ALONE_PASS, chain_ratio, lifetime_ratio, factor, h200, wall, config, rng, preset, model,
    cub_scan, same_threads, icount_differs, shares, lat_row, SFU, WHATIFS, reservation_fails, record_band,
    loaded_band, SB, IDLE, STALL, MEM, ALU)

CHECKS = [Generated(f"{D}/stats-{name}.md", stats_command(name)) for name in RUNS]
CHECKS += [
    Generated(BESIDE, ["scripts/gpgpusim_stage_summary.py", D]),
    Embedded(README, BESIDE, "Σ block lifetimes × 2 warps / span). Ratios are MODELED / SIMULATED."),
    Embedded(README, BESIDE, "blocks' span; launch 2):"),
]
CHECKS += [
    # the H200 figures, from the diagnosis's table
    Figure(README, "(noopt {:,.0f} against {:,.0f} cycles, the group kernel {:,.0f} against {:,.0f}), and could not "
           "say why", lambda: (h200("noopt", "block chain, modeled"), h200("noopt", "warp lifetime, measured"),
                                h200("ours", "block chain, modeled"), h200("ours", "warp lifetime, measured"))),
    Figure(README, "chain / warp lifetime {:.2f} (noopt), {:.2f} (group kernel), {} resident warps, {:.1f} and {:.1f} "
           "cycles per issued instruction", lambda: (
               h200("noopt", "ratio 2"), h200("ours", "ratio 2"),
               h200("noopt", "resident warps / SM, measured (theoretical, achieved)").split(",")[0],
               h200("noopt", "cycles / instruction, measured"), h200("ours", "cycles / instruction, measured"))),
    # the simulated GPU: the run's configuration
    Figure(README, "({} schedulers, {} warps and {} K registers per SM, {} KB L1, {} MHz)", lambda: (
        config("cornell-64x64", "-gpgpu_num_sched_per_core"),
        int(config("cornell-64x64", "-gpgpu_shader_core_pipeline").split(":")[0]) // 32,
        int(config("cornell-64x64", "-gpgpu_shader_registers")) // 1024,
        config("cornell-64x64", "-gpgpu_unified_l1d_size"),
        config("cornell-64x64", "-gpgpu_clock_domains").split(":")[0])),
    Figure(README, "the simulator fits {:.0f} blocks ({:.0f} warps) on the SM, \"limited by: regs\": **{:.0f} waves** "
           "of blocks", lambda: (float(launch("cornell-64x64", N, "CTA/core (limit)").split()[0]),
                                 launch("cornell-64x64", N, "resident warps, theoretical"),
                                 64 / float(launch("cornell-64x64", N, "CTA/core (limit)").split()[0]))),
    # wall times (commands.txt)
    Figure(README, "cornell {} s, sibenik {} s; the what-ifs below {} s (cornell 64×64), the one-block runs {} s "
           "(cornell 32×32), {} s (cornell 64×64), {} s (sibenik 32×32)", lambda: (
               wall("cornell-64x64"), wall("sibenik-64x64"),
               rng([wall(r) for r in WHATIFS[:4]]), wall("cornell-32x32-cta1"), wall("cornell-64x64-cta1"),
               wall("sibenik-32x32-cta1"))),
    # tile_hits and CUB's scan
    Figure(README, "{} blocks of {} warps, {:.0f} resident (\"limited by: threads\", {:.0f} warps), {:.1f} achieved; "
           "{:.1f} PTX instructions per warp; block lifetime {:,.0f} cycles (cornell launch 2). CUB's scan is one "
           "block ({:,.0f} cycles)", lambda: (
               *launch("cornell-64x64", "tile_hits", "blocks × warps").split(" × "),
               float(launch("cornell-64x64", "tile_hits", "CTA/core (limit)").split()[0]),
               launch("cornell-64x64", "tile_hits", "resident warps, theoretical"),
               launch("cornell-64x64", "tile_hits", "achieved"),
               launch("cornell-64x64", "tile_hits", "insts / warp"),
               life("cornell-64x64", "tile_hits"), cub_scan())),
    # the bullets under the first table
    Figure(README, "**Occupancy agrees**: {} resident warps in both, {} achieved", lambda: (
        rng([float(beside(s, k, "MODELED")) for s in LOADED for k in (N, G)]),
        rng([float(beside(s, k, "resident warps / SM, SIMULATED (theoretical, achieved)").split(", ")[1])
             for s in LOADED for k in (N, G)]))),
    Figure(README, "the PTX path is {}× shorter", lambda: rng(
        [beside(s, k, "ratio") for s in LOADED + ALONE for k in (N, G)], 1)),
    Figure(README, "as on the H200**: {} for noopt, {} for the group kernel (H200: {:.2f}, {:.2f})", lambda: (
        rng([chain_ratio(s, N) for s in LOADED], 2), rng([chain_ratio(s, G) for s in LOADED], 2),
        h200("noopt", "ratio 2"), h200("ours", "ratio 2"))),
    Figure(README, "(cornell 64×64) live {:,.0f} (noopt) and {:,.0f} cycles (group kernel), below the model's chains "
           "(ratios {:.2f}, {:.2f}; the 32×32 passes: {:.2f} and {:.2f} on cornell, {:.2f} and {:.2f} on sibenik)",
           lambda: (beside(ALONE[0], N, "block lifetime, SIMULATED"), beside(ALONE[0], G, "block lifetime, SIMULATED"),
                    *(chain_ratio(s, k) for s in ALONE for k in (N, G)))),
    Figure(README, "prices an unloaded block's path within {:+.0%} to {:+.0%} (the SASS count at {} cycles against "
           "the PTX count at the simulator's {}-cycle issue-to-completion ALU latency)", lambda: (
               min(lifetime_ratio(s, k) ** -1 - 1 for s in ALONE for k in (N, G)),
               max(lifetime_ratio(s, k) ** -1 - 1 for s in ALONE for k in (N, G)), model("alu_latency"),
               rng([latency("cornell-64x64-cta1", k, c) for k in (N, G) for c in ("int/other ALU", "fp32 ALU")])),
           minus="−"),
    Figure(README, "sharing the SM with {:.0f} other blocks adds to every block's life: **{:.1f} for noopt and {:.1f} "
           "for the group kernel** on cornell 64×64 (the same pass loaded and alone: the same thread instructions, "
           "{:.1f} and {:.1f} a thread; the simulator's warp-instruction counter differs by {:.1%}), {:.1f} and "
           "{:.1f} on sibenik (64×64 loaded against 32×32 alone)", lambda: (
               float(launch("cornell-64x64", N, "CTA/core (limit)").split()[0]) - 1,
               factor("cornell", ALONE[0], N), factor("cornell", ALONE[0], G), same_threads(N), same_threads(G),
               icount_differs(), factor("sibenik", ALONE[2], N), factor("sibenik", ALONE[2], G))),
    # the latency table (cornell 64×64, loaded and alone)
    Figure(README, "| noopt_kernel | the G-buffer record: 4 × `ld.global.nc.v4` (one 64-byte record a thread), each | "
           "{} | {} | {} (one DRAM load; L2 hits here) |", lambda: (
               rng(record("cornell-64x64", N)), rng(record("cornell-64x64-cta1", N)), preset("dram_latency"))),
    Figure(README, "| noopt_kernel | all global loads ({:.1f} a thread) | {:.0f} | {:.0f} | |",
           lambda: lat_row(N, ("global load",))),
    Figure(README, "| noopt_kernel | int / fp32 ALU ({:.0f} + {:.0f} a thread) | {:.1f} / {:.1f} | {:.1f} / {:.1f} | "
           "{} |", lambda: (*lat_row(N, ("int/other ALU", "fp32 ALU")), model("alu_latency"))),
    Figure(README, "| noopt_kernel | global stores ({:.1f} a thread: the ray's columns) | {:.0f} | {:.0f} | (not on "
           "the chain) |", lambda: lat_row(N, ("global store",))),
    Figure(README, "| noopt_kernel | shared loads ({:.1f}), SFU ({:.1f}), div ({:.1f}), barriers ({:.0f}) | {:.0f}, "
           "{:.0f}, {:.0f}, {:.0f} | {:.0f}, {:.0f}, {:.0f}, {:.0f} | {} (shared) |", lambda: (
               *lat_row(N, ("shared load", *SFU)), model("shared_latency"))),
    Figure(README, "| group_kernel | the G-buffer record, 4 × `ld.global.nc.v4` | {} | {} | |", lambda: (
        rng(record("cornell-64x64", G)), rng(record("cornell-64x64-cta1", G)))),
    Figure(README, "| group_kernel | all global loads ({:.1f} a thread) | {:.0f} | {:.0f} | |",
           lambda: lat_row(G, ("global load",))),
    Figure(README, "| group_kernel | int / fp32 ALU ({:.0f} + {:.0f}) | {:.1f} / {:.1f} | {:.1f} / {:.1f} | {} |",
           lambda: (*lat_row(G, ("int/other ALU", "fp32 ALU")), model("alu_latency"))),
    Figure(README, "| group_kernel | shared loads ({:.0f} a thread) | {:.0f} | {:.0f} | {} |",
           lambda: (*lat_row(G, ("shared load",)), model("shared_latency"))),
    Figure(README, "these latencies are {:,.0f} cycles (noopt) and {:,.0f} (group kernel) loaded, {:.0f}% and {:.0f}% "
           "of it global loads", lambda: (
               latency("cornell-64x64", N, "all", "summed latency / thread"),
               latency("cornell-64x64", G, "all", "summed latency / thread"),
               shares("cornell-64x64", N, ("global load",)), shares("cornell-64x64", G, ("global load",)))),
    # the what-ifs
    Figure(README, "| none (RTX 3070 configuration) | {:,.0f} | {:,.0f} | |", lambda: (
        life("cornell-64x64", N), life("cornell-64x64", G))),
    Figure(README, "| {} L1 banks instead of {} (`-gpgpu_l1_banks 16`) | {:,.0f} ({}%) | {:,.0f} ({}%) | G-buffer "
           "loads slower ({}): the queue moves to the L1's miss path (reservation fails {:,.0f} → {:,.0f} for "
           "noopt) |", lambda: (
               config(WHATIFS[0], "-gpgpu_l1_banks"), config("cornell-64x64", "-gpgpu_l1_banks"),
               life(WHATIFS[0], N), down(WHATIFS[0], N), life(WHATIFS[0], G), down(WHATIFS[0], G),
               rng(record(WHATIFS[0], N)), reservation_fails("cornell-64x64"), reservation_fails(WHATIFS[0])),
           minus="−"),
    Figure(README, "| L2 and DRAM latency {} + {} instead of {} + {} | {:,.0f} ({}%) | {:,.0f} ({}%) | G-buffer loads "
           "{}: still about twice their unloaded latency (~{:.0f} with the {}-cycle L2) |", lambda: (
               config(WHATIFS[1], "-gpgpu_l2_rop_latency"), config(WHATIFS[1], "-dram_latency"),
               config("cornell-64x64", "-gpgpu_l2_rop_latency"), config("cornell-64x64", "-dram_latency"),
               life(WHATIFS[1], N), down(WHATIFS[1], N), life(WHATIFS[1], G), down(WHATIFS[1], G),
               rng(record(WHATIFS[1], N)), round(min(record("cornell-64x64-cta1", N)), -2),
               config("cornell-64x64", "-gpgpu_l2_rop_latency"))),
    Figure(README, "| ALU latency {} instead of {} (int and fp add, max, mul, mad) | {:,.0f} ({}%) | {:,.0f} ({}%) | "
           "mean ALU issue-to-completion {:.1f} → {:.1f} only", lambda: (
               config(WHATIFS[2], "-ptx_opcode_latency_int").split(",")[0],
               config("cornell-64x64", "-ptx_opcode_latency_int").split(",")[0],
               life(WHATIFS[2], N), down(WHATIFS[2], N), life(WHATIFS[2], G), down(WHATIFS[2], G),
               latency("cornell-64x64", N, "int/other ALU"), latency(WHATIFS[2], N, "int/other ALU"))),
    Figure(README, "| L1 miss queue {} entries instead of {} (`-gpgpu_cache:dl1 ...,256:0,32`) | {:,.0f} ({}%) | "
           "{:,.0f} ({}%) | G-buffer loads {}: unchanged; fewer reservation fails ({:,.0f} → {:,.0f} for noopt) |",
           lambda: (config(WHATIFS[3], "-gpgpu_cache:dl1").split(",")[-2].split(":")[0],
                    config("cornell-64x64", "-gpgpu_cache:dl1").split(",")[-2].split(":")[0],
                    life(WHATIFS[3], N), down(WHATIFS[3], N), life(WHATIFS[3], G), down(WHATIFS[3], G),
                    rng(record(WHATIFS[3], N)), reservation_fails("cornell-64x64"), reservation_fails(WHATIFS[3]))),
    Figure(README, "| one block per SM (`-gpgpu_shader_cta 1`) | {:,.0f} ({}%) | {:,.0f} ({}%) | no contention: Stall "
           "{}%, G-buffer loads {} |", lambda: (
               life(WHATIFS[4], N), down(WHATIFS[4], N), life(WHATIFS[4], G), down(WHATIFS[4], G),
               rng([issue(ALONE_PASS[0], k, "Stall % (a warp ready, its unit or the memory stage full)")
                    for k in (N, G)], 1),
               rng(records([WHATIFS[4]], (N, G))))),
    # What it says
    Figure(README, "Alone on the SM, a block lives {:.2f}× (noopt) and {:.2f}× (group kernel) of the model's chain on "
           "cornell 64×64, {:.2f}× and {:.2f}× on sibenik 32×32. With {:.0f} blocks resident it lives {}× longer than "
           "alone", lambda: (
               lifetime_ratio(ALONE[0], N), lifetime_ratio(ALONE[0], G), lifetime_ratio(ALONE[2], N),
               lifetime_ratio(ALONE[2], G), float(launch("cornell-64x64", N, "CTA/core (limit)").split()[0]),
               rng([factor("cornell", ALONE[0], k) for k in (N, G)] + [factor("sibenik", ALONE[2], k)
                                                                        for k in (N, G)], 1))),
    Figure(README, "the simulator puts the model's chain at {} (noopt) and {} (group kernel) of the loaded lifetime, "
           "the same direction as the H200 ({:.2f}, {:.2f})", lambda: (
               rng([chain_ratio(s, N) for s in LOADED], 2), rng([chain_ratio(s, G) for s in LOADED], 2),
               h200("noopt", "ratio 2"), h200("ours", "ratio 2"))),
]
CHECKS += [
    Figure(README, "is {}% of noopt's scheduler cycles and {}% of the group kernel's; W0_Idle (barriers, empty "
           "instruction buffers) {}% and {}%", lambda: (
               loaded_band(N, SB), loaded_band(G, SB), loaded_band(N, IDLE), loaded_band(G, IDLE))),
    Figure(README, "cannot take its instruction ({}% for noopt, {}% for the group kernel; the memory stage is stalled "
           "on {}% and {}% of the cycles", lambda: (
               loaded_band(N, STALL), loaded_band(G, STALL), loaded_band(N, MEM), loaded_band(G, MEM))),
    Figure(README, "Alone, Stall is {}%. noopt issues {:.1f} global loads and {:.1f} global stores a thread", lambda: (
        rng([issue(p, k, STALL) for p in ALONE_PASS for k in (N, G)], 1),
        latency("cornell-64x64", N, "global load", "executions / thread"),
        latency("cornell-64x64", N, "global store", "executions / thread"))),
    Figure(README, "The G-buffer record's four loads take {} cycles from issue to completion loaded and ~{:.0f} alone, "
           "though every access hits in L2 (the stage model prices the record as one DRAM load, {}). Each what-if "
           "takes at most {}% off the lifetime: L2 and DRAM latency cut to {} cycles {}% / {}% (the record's loads "
           "still ~{:,.0f} cycles, about twice their unloaded latency at the normal L2 latency); four times the L1 "
           "banks {}% / {}% (the queue moves to the miss path: the record's loads get slower); a {:.0f}× larger miss "
           "queue {}% / {}%; half the ALU latency {}% / {}%", lambda: (
               record_band(),
               round(min(record("cornell-64x64-cta1", N)), -2), preset("dram_latency"),
               -min(down(r, k) for r in WHATIFS[:4] for k in (N, G)), config(WHATIFS[1], "-dram_latency"),
               down(WHATIFS[1], N), down(WHATIFS[1], G), round(min(record(WHATIFS[1], N)), -2),
               down(WHATIFS[0], N), down(WHATIFS[0], G),
               int(config(WHATIFS[3], "-gpgpu_cache:dl1").split(",")[-2].split(":")[0])
               / int(config("cornell-64x64", "-gpgpu_cache:dl1").split(",")[-2].split(":")[0]),
               down(WHATIFS[3], N), down(WHATIFS[3], G), down(WHATIFS[2], N), down(WHATIFS[2], G))),
    Figure(README, "(noopt {:.0f} shared loads a thread at {:.0f} cycles loaded; the group kernel {:.0f} at {:.0f}, "
           "{:.0f}% of its summed latency) and SFU, divide and barrier instructions are few (under {}% of the summed "
           "latency together)", lambda: (
               latency("cornell-64x64", N, "shared load", "executions / thread"),
               latency("cornell-64x64", N, "shared load"),
               latency("cornell-64x64", G, "shared load", "executions / thread"),
               latency("cornell-64x64", G, "shared load"), shares("cornell-64x64", G, ("shared load",)),
               1 + int(max(shares("cornell-64x64", k, SFU) for k in (N, G))))),
]
CHECKS += [
    Figure(README, "ALU {} (a dependent ALU instruction completes in {} cycles alone and ~{:.0f} loaded: "
           "operand-collector and pipeline stages that the configuration's latency of {} does not include; halving "
           "that latency changes the observed one by ~{:.0f} cycle), shared {} ({} alone, {} loaded), L1 {} / L2 {} / "
           "DRAM {} (the G-buffer record ~{:.0f} alone from L2, {} loaded)", lambda: (
               model("alu_latency"), rng([latency("cornell-64x64-cta1", k, c) for k in (N, G) for c in ALU]),
               sum(latency("cornell-64x64", k, c) for k in (N, G) for c in ALU) / 4,
               config("cornell-64x64", "-ptx_opcode_latency_int").split(",")[0],
               latency("cornell-64x64", N, ALU[0]) - latency(WHATIFS[2], N, ALU[0]), model("shared_latency"),
               rng([latency("cornell-64x64-cta1", k, "shared load") for k in (N, G)]),
               rng([latency("cornell-64x64", k, "shared load") for k in (N, G)]),
               preset("l1_latency"), preset("l2_latency"), preset("dram_latency"),
               round(min(record("cornell-64x64-cta1", N)), -2),
               record_band())),
]
