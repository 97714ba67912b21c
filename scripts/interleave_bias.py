#!/usr/bin/env python3
"""Node DRAM bytes and cycles of the functional tier, the interleaved functional mode and the
timed interleaved mode against the cycle tier, at 1, 8, 32 and 128 rays in flight (wavefront
order, one layout).

Writes interleave_bias_<name>.csv per scene and prints a Markdown table: for each scene and
rays-in-flight count, the cycle tier's node DRAM bytes and sim.cycles, the relative error of the
functional tier (which traces one ray at a time whatever the count), of
functional.rays_in_flight = the same count (round-robin) and of the same with
functional.timed = true (node bytes, and its estimate.cycles against sim.cycles), and the
seconds of each (trace.seconds, the median of --repeats runs; each run with the config's
sim.threads: the cycle tier's unit and the interleaved modes' timing run on one thread).

Usage: scripts/interleave_bias.py CONFIG... [--names NAME...] [--size 512] [--layout dfl]
                                  [--repeats 1] [--out out/charts]
(the committed tables are in docs/: --names kitchen sponza --out docs redraws them)
"""
import argparse
import csv
import pathlib
import sys

from script_cli import (ScriptError, existing_file, guarded, output_dir, parser, positive_int,
                        write_atomically)
from speed_accuracy import ROOT, run


def stats(rtusim, config, sets, repeats, may_fail=False):
    """The last run's stats, with trace.seconds the median of `repeats` runs. A failed run is a
    ScriptError, or with may_fail (the cycle tier's runs: their row says so) None."""
    seconds, last = run(rtusim, config, sets, repeats)
    if seconds is None:
        first = (last.splitlines() or [""])[0]
        if not may_fail:
            raise ScriptError(f"{config}: {first}")
        print(f"  failed: {' '.join(sets)}: {first}", flush=True)
        return None
    last["trace.seconds"] = seconds
    return last


def main():
    ap = parser(__doc__)
    ap.add_argument("configs", nargs="+", type=pathlib.Path)
    ap.add_argument("--size", type=positive_int, default=512, help="image width and height (default 512)")
    ap.add_argument("--layout", default="dfl", help="layout.kind (default dfl)")
    ap.add_argument("--in-flight", type=positive_int, nargs="+", default=[1, 8, 32, 128],
                    help="rays in flight (default 1 8 32 128)")
    ap.add_argument("--repeats", type=positive_int, default=1, help="runs per point (default 1)")
    ap.add_argument("--names", nargs="+", help="one name per config for the CSVs' names "
                    "(default: each config's file stem)")
    ap.add_argument("--out", type=pathlib.Path, default=ROOT / "out" / "charts",
                    help="output directory (default out/charts; docs: the committed set)")
    ap.add_argument("--rtusim", type=pathlib.Path, default=ROOT / "build" / "rtusim")
    args = ap.parse_args()
    names = args.names or [c.stem for c in args.configs]
    if len(names) != len(args.configs):
        ap.error(f"--names gives {len(names)} names for {len(args.configs)} configs")
    if len(set(names)) != len(names):
        ap.error(f"two configs have the same name ({' '.join(names)}): give --names")
    for config in args.configs:
        existing_file(config, "CONFIG")
    existing_file(args.rtusim, "--rtusim")
    output_dir(args.out)
    common = [f"image.width={args.size}", f"image.height={args.size}", "tracer.ray_order=wavefront",
              f"layout.kind={args.layout}", "image.png=false", "image.heatmaps=false"]
    rows = []
    for config, name in zip(args.configs, names):
        functional = stats(args.rtusim, config, common, args.repeats)
        for n in args.in_flight:
            cycle = stats(args.rtusim, config, common + ["sim.tier=cycle", f"sim.rays_in_flight={n}"],
                          args.repeats, may_fail=True)
            inter = stats(args.rtusim, config, common + [f"functional.rays_in_flight={n}"],
                          args.repeats)
            timed = stats(args.rtusim, config, common + [f"functional.rays_in_flight={n}",
                                                          "functional.timed=true"], args.repeats)
            row = {"scene": name, "rays_in_flight": n,
                   "cycle_node_bytes": cycle["dram.bytes.nodes"] if cycle else "failed",
                   "cycle_cycles": cycle["sim.cycles"] if cycle else "",
                   "functional_node_bytes": functional["dram.bytes.nodes"],
                   "interleaved_node_bytes": inter["dram.bytes.nodes"],
                   "timed_node_bytes": timed["dram.bytes.nodes"],
                   "timed_estimate_cycles": timed["estimate.cycles"],
                   "functional_error": "", "interleaved_error": "", "timed_error": "",
                   "timed_cycles_error": "",
                   "cycle_seconds": cycle["trace.seconds"] if cycle else "",
                   "functional_seconds": functional["trace.seconds"],
                   "interleaved_seconds": inter["trace.seconds"],
                   "timed_seconds": timed["trace.seconds"]}
            if cycle:
                ref = cycle["dram.bytes.nodes"]
                row["functional_error"] = functional["dram.bytes.nodes"] / ref - 1
                row["interleaved_error"] = inter["dram.bytes.nodes"] / ref - 1
                row["timed_error"] = timed["dram.bytes.nodes"] / ref - 1
                row["timed_cycles_error"] = timed["estimate.cycles"] / cycle["sim.cycles"] - 1
            rows.append(row)
            print(rows[-1], flush=True)
    for name in names:
        def write(f):
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            w.writeheader()
            w.writerows(r for r in rows if r["scene"] == name)
        write_atomically(args.out / f"interleave_bias_{name}.csv", write)
    print("| scene | rays in flight | cycle node MB | functional | round-robin | timed | "
          "timed cycles | cycle s / round-robin s / timed s |")
    print("|---|---:|---:|---:|---:|---:|---:|---|")
    for r in rows:
        if r["cycle_node_bytes"] == "failed":
            print(f"| {r['scene']} | {r['rays_in_flight']} | cycle tier failed | | | | | |")
            continue
        print(f"| {r['scene']} | {r['rays_in_flight']} | {r['cycle_node_bytes'] / 1e6:.2f} | "
              f"{100 * r['functional_error']:+.2f}% | {100 * r['interleaved_error']:+.2f}% | "
              f"{100 * r['timed_error']:+.2f}% | {100 * r['timed_cycles_error']:+.2f}% | "
              f"{r['cycle_seconds']:.1f} / {r['interleaved_seconds']:.1f} / "
              f"{r['timed_seconds']:.1f} |")


if __name__ == "__main__":
    sys.exit(guarded(main))
