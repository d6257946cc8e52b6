#!/usr/bin/env python3
"""Where a stage kernel's instructions and stalls go, region by region: Nsight Compute's per-instruction counts beside
the regions the stage model's trip counts are made of (scripts/count-stage-paths; simt/stage_paths.h).

Usage:
  scripts/stage_regions.py SOURCE.csv LISTING.txt --warps-from LOG
      SOURCE.csv: Nsight Compute's source page of one launch profiled with the SourceCounters section (`ncu --import
      REPORT --page source --csv --print-source sass`): each SASS instruction's executions and stall samples.
      LISTING.txt: `scripts/count-stage-paths [--noopt] --listing sm_90` of the revision that built the profiled binary
      (the same kernel's SASS compiled here, each instruction's offset, opcode and region); the instructions are
      matched by offset from the kernel's first one and their opcodes checked.
      LOG: an ncu log of the same pass (scripts/stage_counters.py reads it) with the kernel's launch: its warps.
Prints per region (MEASURED; the static size is the listing's): executions per warp, the share of stall samples and
the largest stall reasons. The model runs each region for the warps and trip counts its pass gives it, so a region
executed more per warp than its static size, or one the model leaves out of the pass's path, is where its count
misses.
"""
import argparse
import collections
import csv
import math
import os
import sys

import stage_counters as sc


def fail(message):
    """Bad input: one line naming it, exit 2."""
    print(f"stage_regions.py: {message}", file=sys.stderr)
    sys.exit(2)


def hex_address(text, path):
    try:
        return int(text, 16)
    except ValueError:
        fail(f"{path}: address {text!r} is not hexadecimal (the source page's Address column)")


def read_listing(path):
    """[(offset, opcode, region)] of `count-stage-paths --listing`."""
    out = []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                fields = line.split()
                if len(fields) != 3:
                    fail(f"{path}: {line.strip()!r} is not 'offset opcode region' (count-stage-paths --listing)")
                out.append((hex_address(fields[0], path), fields[1], fields[2]))
    return out


def read_source_page(path):
    """The SASS rows of an ncu --page source --csv export: [{column: text}] in address order."""
    header, rows = None, []
    with open(path, newline="", errors="replace") as f:
        for row in csv.reader(f):
            if row and row[0] == "Address":
                header = row
            elif header and len(row) == len(header):
                rows.append(dict(zip(header, row)))
    if header is None or "Instructions Executed" not in header:
        fail(f"{path}: no SASS rows with 'Instructions Executed' (an ncu --page source --csv "
                 "--print-source sass export of a launch profiled with --section SourceCounters)")
    return rows


def opcode_of(source):
    words = [w for w in source.split() if not w.startswith("@")]
    return words[0].split(".")[0] if words else ""


def match_regions(rows, listing, path):
    """Each source-page row's region: by offset from the kernel's first instruction; the opcodes must agree."""
    base = hex_address(rows[0]["Address"], path)
    by_offset = {o: (op, r) for o, op, r in listing}
    out, wrong = [], 0
    for row in rows:
        op, region = by_offset.get(hex_address(row["Address"], path) - base, (None, None))
        code = opcode_of(row.get("Source", ""))
        if code in ("NOP", "") or region is None:
            continue  # NOPs and the code after the last EXIT are not in the listing
        wrong += op.split(".")[0] != code
        out.append((region, row))
    if wrong > len(out) // 50:
        fail(f"{path}: {wrong} of {len(out)} instructions differ from the listing's opcodes at the "
                 "same offsets: the profiled binary is not the listing's compile (count-stage-paths --listing of the "
                 "revision that built it)")
    return out


def regions(args):
    launches = [k for k in sc.read_log(args.warps_from) if sc.kernel_of(k["name"]) == "gen"]
    if not launches:
        fail(f"{args.warps_from}: no generator launch (noopt_kernel, group_kernel) to read "
                 "the warps from")
    warps = sc.measured(launches[-1])["warps"]
    listing = read_listing(args.listing)
    matched = match_regions(read_source_page(args.source), listing, args.source)
    samples = [c for c in matched[0][1] if c.startswith("stall_")] if matched else []
    executed, stalls, sampled = collections.Counter(), collections.defaultdict(collections.Counter), collections.Counter()
    for region, row in matched:
        executed[region] += sc.number(row["Instructions Executed"])
        sampled[region] += sc.number(row.get("Warp Stall Sampling (All Samples)", row.get("# Samples", "0")))
        for c in samples:
            stalls[region][c[len("stall_"):]] += sc.number(row[c]) if not math.isnan(sc.number(row[c])) else 0
    static = collections.Counter(r for _, _, r in listing)
    all_samples = sum(sampled.values()) or math.nan
    print(f"## Where the instructions and stalls go, by region (measured; {sc.fmt(warps)} warps)\n")
    print("| region | static instructions | executed per warp | stall samples % | largest stall reasons |")
    print("|---|---:|---:|---:|---|")
    for region in sorted(static, key=lambda r: -executed[r]):
        top = ", ".join(f"{r} {v / sampled[region] * 100:.0f}%" for r, v in stalls[region].most_common(3)
                        if sampled[region] and v)
        print(f"| {region} | {static[region]} | {sc.fmt(executed[region] / warps, 1)} | "
              f"{sc.fmt(sampled[region] / all_samples * 100, 1)} | {top or '—'} |")
    print(f"| all | {sum(static.values())} | {sc.fmt(sum(executed.values()) / warps, 1)} | 100.0 | |")


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("source")
    p.add_argument("listing")
    p.add_argument("--warps-from", required=True)
    args = p.parse_args(argv)
    for path in (args.source, args.listing, args.warps_from):
        if not os.path.isfile(path):
            p.error(f"{path}: no such file")
    regions(args)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
