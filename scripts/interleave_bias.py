#!/usr/bin/env python3
"""Node DRAM bytes of the functional tier and of the interleaved functional mode against the
cycle tier, at 1, 8, 32 and 128 rays in flight (wavefront order, one layout).

Writes interleave_bias.csv and prints a Markdown table: for each scene and rays-in-flight count,
the cycle tier's node DRAM bytes, and the relative error of the functional tier (which traces
one ray at a time whatever the count) and of functional.rays_in_flight = the same count.

Usage: scripts/interleave_bias.py CONFIG... [--size 512] [--layout dfl] [--out docs]
"""
import argparse
import csv
import json
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent


def stats(rtusim, config, sets):
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [str(rtusim), "run", str(config), "--out", tmp]
        for s in sets:
            cmd += ["--set", s]
        r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if r.returncode != 0:
            print(f"  failed: {' '.join(sets)}: {r.stderr.strip().splitlines()[0]}", flush=True)
            return None
        return json.loads((pathlib.Path(tmp) / "stats.json").read_text())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("configs", nargs="+", type=pathlib.Path)
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--layout", default="dfl")
    ap.add_argument("--in-flight", type=int, nargs="+", default=[1, 8, 32, 128])
    ap.add_argument("--out", type=pathlib.Path, default=ROOT / "docs")
    ap.add_argument("--csv", default="interleave_bias.csv")
    ap.add_argument("--rtusim", type=pathlib.Path, default=ROOT / "build" / "rtusim")
    args = ap.parse_args()
    common = [f"image.width={args.size}", f"image.height={args.size}", "tracer.ray_order=wavefront",
              f"layout.kind={args.layout}", "image.png=false", "image.heatmaps=false"]
    rows = []
    for config in args.configs:
        functional = stats(args.rtusim, config, common)
        for n in args.in_flight:
            cycle = stats(args.rtusim, config, common + ["sim.tier=cycle", f"sim.rays_in_flight={n}"])
            inter = stats(args.rtusim, config, common + [f"functional.rays_in_flight={n}"])
            if cycle is None:
                rows.append({"scene": config.stem, "rays_in_flight": n, "cycle_node_bytes": "failed",
                             "functional_node_bytes": functional["dram.bytes.nodes"],
                             "functional_error": "", "interleaved_node_bytes": inter["dram.bytes.nodes"],
                             "interleaved_error": "", "cycle_seconds": "",
                             "interleaved_seconds": inter["trace.seconds"],
                             "functional_seconds": functional["trace.seconds"]})
                continue
            ref = cycle["dram.bytes.nodes"]
            rows.append({"scene": config.stem, "rays_in_flight": n, "cycle_node_bytes": ref,
                         "functional_node_bytes": functional["dram.bytes.nodes"],
                         "functional_error": functional["dram.bytes.nodes"] / ref - 1,
                         "interleaved_node_bytes": inter["dram.bytes.nodes"],
                         "interleaved_error": inter["dram.bytes.nodes"] / ref - 1,
                         "cycle_seconds": cycle["trace.seconds"],
                         "interleaved_seconds": inter["trace.seconds"],
                         "functional_seconds": functional["trace.seconds"]})
            print(rows[-1], flush=True)
    args.out.mkdir(parents=True, exist_ok=True)
    with open(args.out / args.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print("| scene | rays in flight | cycle node MB | functional error | interleaved error |")
    print("|---|---:|---:|---:|---:|")
    for r in rows:
        if r["cycle_node_bytes"] == "failed":
            print(f"| {r['scene']} | {r['rays_in_flight']} | cycle tier failed | | |")
            continue
        print(f"| {r['scene']} | {r['rays_in_flight']} | {r['cycle_node_bytes'] / 1e6:.2f} | "
              f"{100 * r['functional_error']:+.2f}% | {100 * r['interleaved_error']:+.2f}% |")


if __name__ == "__main__":
    sys.exit(main())
