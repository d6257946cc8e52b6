#!/usr/bin/env python3
"""The generation stage's kernels in a GPGPU-Sim performance-mode log: cycles, instructions, occupancy, block
lifetimes and the issue breakdown, per launch, as markdown (every figure SIMULATED: a second model, not hardware).

Usage:
  scripts/gpgpusim_stage_stats.py [--kernels tile_hits,noopt_kernel,group_kernel] [--prediction CSV --scene S]
      [--ptx-stats gpgpu_inst_stats.txt [--top N]] LOG
  LOG (.xz read too): the gpgpusim.log of `scripts/gpgpusim-run --timing --sms 1 --keep --option '-trace_enabled
  1' --option '-trace_components LIVENESS' --option '-trace_sampling_core 0'`: every CTA's start and finish cycle
  on the one SM (without them, no lifetimes). --prediction: stage_counters.py predict's CSV (MODELED), set beside
  the timed generator launches (noopt_kernel: method noopt, group_kernel: ours) of scene S.

What is read, per launch (the simulator prints its statistics when a kernel ends; the counters marked * are
cumulative over the process, so a launch's figure is the difference from the block before it):
  cycles           gpu_sim_cycle, from the launch (its -gpgpu_kernel_launch_latency, 5000 here, included)
  span             the first CTA's start to the last CTA's finish (LIVENESS lines)
  warp insts       gpgpu_n_tot_w_icount*; per warp: / (grid x warps per block)
  CTA/core         "CTA/core = N, limited by: X" at the kernel's bind: the theoretical resident blocks per SM
  block lifetime   per CTA, its finish cycle - its start cycle; mean, median, max (a block's warps all resident
                   until the last exits: the block's lifetime is what holds a resident slot)
  achieved warps   sum of block lifetimes x warps per block / span: the mean resident warps over the span (exact on
                   one SM; cycles x achieved warps x SMs / warps over the span is then the mean block lifetime)
  issue breakdown  "Stall:/W0_Idle:/W0_Scoreboard:/W1..W32"*, one count per scheduler per cycle
                   (gpgpu-sim shader.cc scheduler_unit::cycle): Wn an issue with n active threads; W0_Scoreboard no
                   warp's next instruction passed the scoreboard (waiting on a register an earlier instruction
                   writes: ALU, SFU, shared or global memory); W0_Idle no warp had a valid next instruction (waiting
                   at a barrier, instruction buffer empty, exited, or none resident; the schedulers are counted
                   from the first CTA's start: 4 x span);
                   Stall a warp was ready but its unit or the memory pipeline could not take it
  memory stalls    gpgpu_n_stall_shd_mem*, [s_mem][bk_conf]*, [gl_mem][resource_stall/coal_stall]*; shared-memory
                   and global/local load and store instructions gpgpu_n_shmem_insn*, gpgpu_n_load_insn*,
                   gpgpu_n_store_insn* (each counts an instruction's active threads); L1D_total_cache_*,
                   L2_total_cache_* (accesses, misses, ...)*
  latencies        --ptx-stats: per PTX line of the kernels, thread executions x issue-to-completion cycles
                   (warp_inst_t::completed), summed by instruction class; every launch of the process together
"""
import argparse
import csv
import glob
import lzma
import os
import re
import statistics
import sys

PUSH = re.compile(r"pushing kernel '([^']+)' to stream \d+, "
                  r"gridDim= \((\d+),(\d+),(\d+)\) blockDim = \((\d+),(\d+),(\d+)\)")
BIND = re.compile(r"bind to kernel (\d+) '")
LIMIT = re.compile(r"CTA/core = (\d+), limited by: (\w+)")
INIT = re.compile(r"cta:\s*(\d+), start_tid:.*initialized @\((\d+),(\d+)\), kernel_uid:(\d+)")
FINISH = re.compile(r"Finished CTA #(\d+) \((\d+),(\d+)\)")
DISTRO, DISTRO_RUN = re.compile(r"(Stall|W0_Idle|W0_Scoreboard|W\d+):(\d+)"), re.compile(r"(?:\s*\w+:\d+)*")
KV = re.compile(r"^\s*(gpu_sim_cycle|gpu_sim_insn|gpgpu_n_tot_w_icount|gpgpu_n_stall_shd_mem|gpgpu_n_shmem_insn|"
                r"gpgpu_n_load_insn|gpgpu_n_store_insn|gpgpu_n_shmem_bkconflict|kernel_launch_uid|"
                r"L1D_total_cache_\w+|L2_total_cache_\w+|gpgpu_stall_shd_mem\[\w+\]\[\w+\])\s*=\s*(\d+)\b")
CUMULATIVE = ("gpgpu_n_tot_w_icount", "gpgpu_n_stall_shd_mem", "gpgpu_n_shmem_insn", "gpgpu_n_load_insn",
              "gpgpu_n_store_insn", "gpgpu_n_shmem_bkconflict", "gpgpu_stall_shd_mem[s_mem][bk_conf]",
              "gpgpu_stall_shd_mem[gl_mem][resource_stall]", "gpgpu_stall_shd_mem[gl_mem][coal_stall]",
              "Stall", "W0_Idle", "W0_Scoreboard", "issued", "lanes", "L1D_total_cache_accesses",
              "L1D_total_cache_misses", "L1D_total_cache_pending_hits", "L1D_total_cache_reservation_fails",
              "L2_total_cache_accesses", "L2_total_cache_misses")
# Mangled names carry each identifier's length: "12group_kernel" is not "18fused_group_kernel".
SHORT = (("16tile_hits_kernel", "tile_hits"), ("12noopt_kernel", "noopt_kernel"), ("12group_kernel", "group_kernel"),
         ("DeviceScanInitKernel", "cub scan init"), ("DeviceScanKernel", "cub scan"), ("persistent_kernel", "trace"),
         ("primary_kernel", "primary"), ("gbuffer_kernel", "gbuffer"))


def open_text(path):  # plain or .xz
    return (lzma.open if path.endswith(".xz") else open)(path, "rt", errors="replace")


def short(name):
    return next((s for key, s in SHORT if key in name), name[:40])


def read_log(path):
    """Every kernel's statistics block, in the order the simulator printed them, with its CTAs."""
    pushes, limits, ctas, slots, blocks = {}, {}, {}, {}, []
    bound, block, distro = None, None, None
    with open_text(path) as f:
        for line in f:
            if m := PUSH.search(line):
                pushes.setdefault(m.group(1), []).append(([int(x) for x in m.groups()[1:4]],
                                                          [int(x) for x in m.groups()[4:7]]))
            elif m := BIND.search(line):
                bound = int(m.group(1))
            if (m := LIMIT.search(line)) and bound is not None and bound not in limits:
                limits[bound] = (int(m.group(1)), m.group(2))
            if m := INIT.search(line):
                slots[int(m.group(1))] = int(m.group(4)), int(m.group(2)) + int(m.group(3))
            elif (m := FINISH.search(line)) and int(m.group(1)) in slots:  # (a line cut by the host's: lost)
                uid, start = slots.pop(int(m.group(1)))
                ctas.setdefault(uid, []).append((start, int(m.group(2)) + int(m.group(3))))
            if line.startswith("kernel_name = "):
                block = {"name": line.split("=", 1)[1].strip()}
                blocks.append(block)
            elif block is not None:
                if m := KV.match(line):
                    block[m.group(1)] = int(m.group(2))
                elif line.startswith("Stall:") or (distro is not None and line.startswith("\tW")):
                    # the host thread's messages can cut this long line: its tail continues on a later line
                    distro = {} if line.startswith("Stall:") else distro
                    distro.update((k, int(v)) for k, v in DISTRO.findall(DISTRO_RUN.match(line).group(0)))
                    if "W32" in distro:
                        d, distro = distro, None
                        block.update(Stall=d["Stall"], W0_Idle=d["W0_Idle"], W0_Scoreboard=d["W0_Scoreboard"],
                                     issued=sum(d[f"W{i}"] for i in range(1, 33)),
                                     lanes=sum(i * d[f"W{i}"] for i in range(1, 33)))
    previous = {}
    for b in blocks:  # the launch's share of each cumulative counter (NaN where a cut line lost it)
        for k in CUMULATIVE:
            v = b.get(k)
            b[k] = float("nan") if v is None else v - previous.get(k, 0)
            previous[k] = previous.get(k, 0) if v is None else v
        uid = b.get("kernel_launch_uid", 0)
        # kernels run one after another: a block is its name's earliest launch not yet taken (uids count more)
        grid, dim = (pushes.get(b["name"]) or [([0, 0, 0], [0, 0, 0])]).pop(0)
        b["threads"], b["blocks"] = dim[0] * dim[1] * dim[2], grid[0] * grid[1] * grid[2]
        b["warps_per_block"] = -(-b["threads"] // 32)
        b["warps"] = b["blocks"] * b["warps_per_block"]
        b["limit"] = limits.get(uid, (0, ""))
        b["ctas"] = sorted(ctas.get(uid, []))
    return blocks


def lifetimes(b):
    """(mean, median, max block lifetime, span, achieved warps) from the CTAs' start and finish cycles."""
    if not b["ctas"]:
        return None
    life = [f - s for s, f in b["ctas"]]
    span = max(f for _, f in b["ctas"]) - min(s for s, _ in b["ctas"])
    return (statistics.mean(life), statistics.median(life), max(life), span,
            sum(life) * b["warps_per_block"] / span if span else float("nan"))


def fmt(v, digits=0):
    return "—" if v is None or v != v else f"{v:,.{digits}f}"


def pct(part, whole):
    return f"{100 * part / whole:.1f}" if whole else "—"


def launches(blocks, kernels):
    seen = {}
    for b in blocks:
        if (s := short(b["name"])) in kernels:
            seen[s] = seen.get(s, 0) + 1
            yield seen[s], s, b


def print_tables(blocks, kernels):
    print("SIMULATED (GPGPU-Sim performance mode, not hardware). n: the kernel's launch in the log (1 the untimed "
          "warm-up, 2 the timed pass). Cycles from the launch (launch latency included); span: first CTA start to "
          "last CTA finish; lifetimes per block (CTA), SM cycles.\n")
    print("| kernel | n | uid | blocks × warps | cycles | span | warp insts | insts / warp | CTA/core (limit) | "
          "resident warps, theoretical | achieved | block lifetime mean | median | max | cycles / inst of a warp | "
          "SIMT eff. % |")
    print("|---|---:|---:|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    for n, s, b in launches(blocks, kernels):
        lt = lifetimes(b) or (float("nan"),) * 5
        per_warp = b["gpgpu_n_tot_w_icount"] / b["warps"] if b["warps"] else float("nan")
        cta, why = b["limit"]
        print(f"| {s} | {n} | {b.get('kernel_launch_uid', '')} | {b['blocks']} × {b['warps_per_block']} | "
              f"{fmt(b.get('gpu_sim_cycle'))} | {fmt(lt[3])} | {fmt(b['gpgpu_n_tot_w_icount'])} | {fmt(per_warp, 1)} | "
              f"{cta} ({why}) | {cta * b['warps_per_block']} | {fmt(lt[4], 1)} | {fmt(lt[0])} | {fmt(lt[1])} | "
              f"{fmt(lt[2])} | {fmt(lt[0] / per_warp, 1)} | {pct(b['lanes'], 32 * b['issued'])} |")
    print("\nIssue breakdown: scheduler cycles (4 schedulers per SM cycle, counted from the first CTA's start: "
          "none during the launch latency) by what the scheduler did, % of the launch's scheduler cycles. "
          "Memory instructions: thread accesses (the simulator counts each instruction's active threads); "
          "shd_mem stalls: cycles the memory stage could not take its instruction, by cause; L1D and L2: "
          "the caches' totals (L2: every SM's requests, sectors).\n")
    print("| kernel | n | scheduler cycles | issued % | W0_Scoreboard % | W0_Idle % | Stall % | "
          "shared-memory insts | load insts | store insts | shd_mem stalls | s_mem bank conflicts | "
          "gl_mem resource / coal stalls | L1D accesses / misses / pending hits / reservation fails | "
          "L2 accesses / misses |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---|")
    for n, s, b in launches(blocks, kernels):
        total = b["issued"] + b["W0_Scoreboard"] + b["W0_Idle"] + b["Stall"]
        print(f"| {s} | {n} | {fmt(total)} | {pct(b['issued'], total)} | {pct(b['W0_Scoreboard'], total)} | "
              f"{pct(b['W0_Idle'], total)} | {pct(b['Stall'], total)} | {fmt(b['gpgpu_n_shmem_insn'])} | "
              f"{fmt(b['gpgpu_n_load_insn'])} | {fmt(b['gpgpu_n_store_insn'])} | {fmt(b['gpgpu_n_stall_shd_mem'])} | "
              f"{fmt(b['gpgpu_stall_shd_mem[s_mem][bk_conf]'])} | "
              f"{fmt(b['gpgpu_stall_shd_mem[gl_mem][resource_stall]'])} / "
              f"{fmt(b['gpgpu_stall_shd_mem[gl_mem][coal_stall]'])} | "
              + " / ".join(fmt(b[f"L1D_total_cache_{k}"]) for k in ("accesses", "misses", "pending_hits",
                                                                     "reservation_fails"))
              + f" | {fmt(b['L2_total_cache_accesses'])} / {fmt(b['L2_total_cache_misses'])} |")


def print_beside(blocks, prediction, scene):
    with open(prediction, newline="") as f:
        modeled = {(r["scene"], r["method"]): r for r in csv.DictReader(f) if r["kernel"] == "gen"}
    print(f"\n{scene}: the timed launch (n = 2) of each generator, SIMULATED beside the model's per-warp make-up "
          "(MODELED, scripts/stage_counters.py predict); ratio = MODELED / SIMULATED.\n")
    print("| method | kernel | insts / warp, SIMULATED (PTX) | cycles / warp, MODELED (SASS path) | ratio | "
          "block lifetime, SIMULATED | chain, MODELED | ratio | resident warps, SIMULATED (theoretical, achieved) | "
          "MODELED |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---|---:|")
    for n, s, b in launches(blocks, ("noopt_kernel", "group_kernel")):
        method = "noopt" if s == "noopt_kernel" else "ours"
        if n != 2 or not (m := modeled.get((scene, method))) or not b["ctas"]:
            continue
        per_warp, lt = b["gpgpu_n_tot_w_icount"] / b["warps"], lifetimes(b)
        cw, chain = float(m["cycles_per_warp"]), float(m["chain_cycles"])
        print(f"| {method} | {s} | {fmt(per_warp)} | {fmt(cw)} | {cw / per_warp:.2f} | {fmt(lt[0])} | "
              f"{fmt(chain)} | {chain / lt[0]:.2f} | {b['limit'][0] * b['warps_per_block']}, {fmt(lt[4], 1)} | "
              f"{fmt(float(m['resident_warps']))} |")


# PTX opcode -> class, first match wins (GPGPU-Sim, cuda-sim.cc: sqrt, rcp, rsqrt, sin, cos, ex2, lg2 on the SFU
# at -ptx_opcode_latency_sfu; div and rem on the SFU at the fp or int DIV latency; .f64 at the DP latencies).
CLASSES = (("global load", r"ld\.global|ldu\.global"), ("local load/store", r"(ld|st)\.local"),
           ("shared load", r"ld\.shared"), ("param/const load", r"ld\.(param|const)"),
           ("global store", r"st\.global"), ("shared store", r"st\.shared"),
           ("shared atomic", r"(atom|red)\.shared"), ("global atomic", r"(atom|red)(\.global)?\."),
           ("generic load/store", r"(ld|st)\."), ("barrier", r"bar\.|barrier\."), ("fence", r"membar|fence"),
           ("warp (shfl/vote/redux)", r"shfl|vote|redux|match"), ("fp64", r"\S*\.f64"),
           ("SFU (rcp/sqrt/sin/cos/ex2/lg2)", r"(rcp|sqrt|rsqrt|sin|cos|ex2|lg2|tanh)\."),
           ("div/rem (SFU unit)", r"(div|rem)\."), ("fp32 ALU", r"\S*\.f32"), ("control", r"(bra|ret|exit|call)\b"),
           ("int/other ALU", r"."))


def ptx_lines(folder, kernels):
    """(PTX file, line) -> (kernel, instruction) for the lines of the entries of the named kernels."""
    out = {}
    for path in sorted(glob.glob(os.path.join(folder, "*.ptx")) + glob.glob(os.path.join(folder, "*.ptx.xz"))):
        kernel = None
        with open_text(path) as f:
            for n, line in enumerate(f, 1):
                if line.startswith((".entry", ".visible .entry")):
                    kernel = k if (k := short(line.split()[-1])) in kernels else None
                elif line.rstrip() == "}":
                    kernel = None
                elif kernel and (text := line.strip()) and not text.startswith((".", "//", "{", "}", "$")):
                    out[(os.path.basename(path).removesuffix(".xz"), n)] = kernel, re.sub(r"^@!?%\w+\s+", "", text)
    return out


def print_latencies(blocks, kernels, stats, top):
    """gpgpu_inst_stats.txt per PTX line: thread executions, issue-to-completion latency x active threads."""
    lines = ptx_lines(os.path.dirname(os.path.abspath(stats)), kernels)
    threads = {}
    for _, s, b in launches(blocks, kernels):
        threads[s] = threads.get(s, 0) + b["blocks"] * b["threads"]
    sums, rows = {}, {}
    with open_text(stats) as f:
        for row in f:
            m = re.match(r"(\S+) (\d+) : (\d+) (\d+)", row)
            if m and (k := lines.get((m.group(1), int(m.group(2))))):
                cls = next(c for c, rx in CLASSES if re.match(rx, k[1]))
                e = sums.setdefault(k[0], {}).setdefault(cls, [0, 0])
                e[0], e[1] = e[0] + int(m.group(3)), e[1] + int(m.group(4))
                rows.setdefault(k[0], []).append((int(m.group(4)), int(m.group(3)), m.group(2), k[1]))
    print("\nInstruction latencies by class (gpgpu_inst_stats.txt, every launch of the kernel in the process summed, "
          "per thread of a launch): executions, mean issue-to-completion latency (cycles; the memory pipeline's and "
          "caches' queueing included, the wait before issue not), and their product, a thread's summed latencies "
          "(an upper bound of what its dependences could put on its chain).\n")
    print("| kernel | class | executions / thread | mean latency | summed latency / thread | share % |")
    print("|---|---|---:|---:|---:|---:|")
    for kernel, classes in sums.items():
        t = threads.get(kernel) or 1
        total = sum(lat for _, lat in classes.values())
        for cls, (count, lat) in sorted(classes.items(), key=lambda c: -c[1][1]):
            print(f"| {kernel} | {cls} | {count / t:.1f} | {lat / count if count else 0:.1f} | {lat / t:,.0f} | "
                  f"{pct(lat, total)} |")
        print(f"| {kernel} | all | {sum(c for c, _ in classes.values()) / t:.1f} | | {total / t:,.0f} | 100 |")
    print(f"\nThe {top} PTX lines of each kernel with the largest summed latency (same columns):\n")
    print("| kernel | PTX line | instruction | executions / thread | mean latency | summed latency / thread |")
    print("|---|---:|---|---:|---:|---:|")
    for kernel, found in rows.items():
        t = threads.get(kernel) or 1
        for lat, count, line, text in sorted(found, reverse=True)[:top]:
            print(f"| {kernel} | {line} | `{text[:70]}` | {count / t:.2f} | {lat / count:.0f} | {lat / t:,.0f} |")


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--kernels", default="tile_hits,noopt_kernel,group_kernel")
    p.add_argument("--prediction"), p.add_argument("--scene")
    p.add_argument("--ptx-stats", help="the run's gpgpu_inst_stats.txt(.xz), beside its NAME.N.sm_86.ptx(.xz)")
    p.add_argument("--top", type=int, default=8, help="PTX lines listed per kernel (with --ptx-stats)")
    p.add_argument("log")
    args = p.parse_args(argv)
    if bool(args.prediction) != bool(args.scene):
        p.error("--prediction and --scene go together")
    blocks = read_log(args.log)
    if not blocks:
        sys.exit(f"gpgpusim_stage_stats.py: {args.log}: no kernel statistics (a performance-mode log?)")
    print_tables(blocks, args.kernels.split(","))
    if args.ptx_stats:
        print_latencies(blocks, args.kernels.split(","), args.ptx_stats, args.top)
    if args.prediction:
        print_beside(blocks, args.prediction, args.scene)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
