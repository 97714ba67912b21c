#!/usr/bin/env python3
"""Runs every benchmark of bench/ and writes one Markdown table of ratios against the reference
each measured in the same run (Embree for tracing, plain traversal for the tiers, the decode or
checksum loop for replay), with the machine it ran on.

Usage: bench/run_all.py [--build DIR] [--out FILE] [--quick]
  --build  the build directory holding bench/ (default: build beside this script's project)
  --out    the Markdown file to write (default: stdout only)
  --quick  fewer runs, Sponza only: a smoke test of the script, not figures to quote

Each benchmark prints `RATIO` lines (bench/bench_timing.h: print_ratio); a benchmark that fails
or prints none is reported in the table as failed and the script exits 1.
"""
import argparse
import os
import platform
import re
import subprocess
import sys
import time

PROJECT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def machine():
    """Model name, cores and AVX-512 flags from lscpu (Linux), else what platform knows."""
    model, cpus, flags = platform.processor() or platform.machine(), str(os.cpu_count()), []
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
        for line in out.splitlines():
            key, _, value = line.partition(":")
            if key.strip() == "Model name":
                model = value.strip()
            elif key.strip() == "CPU(s)":
                cpus = value.strip()
            elif key.strip() == "Flags":
                flags = sorted(f for f in value.split() if f.startswith("avx512"))
    except (OSError, subprocess.CalledProcessError):
        pass
    return model, cpus, flags


def build_flags(build):
    """Whether the build used -march=native (RTUSIM_NATIVE in CMakeCache.txt)."""
    try:
        with open(os.path.join(build, "CMakeCache.txt")) as f:
            m = re.search(r"^RTUSIM_NATIVE:BOOL=(\w+)", f.read(), re.M)
            return "RTUSIM_NATIVE=" + (m.group(1) if m else "?")
    except OSError:
        return "RTUSIM_NATIVE=?"


def run(cmd):
    """Runs one benchmark; returns (RATIO rows, other output lines, ok)."""
    print("$ " + " ".join(cmd), file=sys.stderr, flush=True)
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=PROJECT)
    rows, other = [], []
    for line in p.stdout.splitlines():
        if line.startswith("RATIO\t"):
            f = line.split("\t")[1:]
            rows.append({"bench": f[0], "case": f[1], "subject": f[2], "value": float(f[3]),
                         "reference": f[4], "reference_value": float(f[5]), "unit": f[6],
                         "ratio": float(f[7])})
        else:
            other.append(line)
    sys.stderr.write("\n".join(other) + "\n")
    return rows, other, p.returncode == 0 and (rows or "kdtree_build_bench" in cmd[0])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(PROJECT, "build"))
    ap.add_argument("--out")
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    b = os.path.join(os.path.abspath(args.build), "bench")
    scenes_dir = os.environ.get("RTUSIM_SCENES", os.path.join(os.path.dirname(PROJECT), "shared", "scenes"))
    scenes = ["sponza_dabrovic"] if args.quick else ["sponza_dabrovic", "kitchen"]
    # The cycle tier's reference (plain traversal of 65 K rays) takes 13-35 ms: 15 runs steady
    # its median, where 5 left the ratio spread over 11.7-17.6 on one VM.
    runs = "1" if args.quick else "15"
    benches = [[os.path.join(b, "traversal_bench")] + scenes,
               [os.path.join(b, "packet_kinds_bench")] + scenes]
    benches += [[os.path.join(b, "functional_tier_bench"), os.path.join(PROJECT, "configs", s + ".toml")]
                + (["--set", "image.width=128", "--set", "image.height=128"] if args.quick else [])
                for s in scenes]
    benches += [[os.path.join(b, "cycle_tier_bench"), runs],
                [os.path.join(b, "cache_replay_bench")],
                [os.path.join(b, "trace_replay_bench")]]
    builds = [[os.path.join(b, "kdtree_build_bench"), os.path.join(scenes_dir, s, s + ".gltf")]
              for s in scenes]

    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    rows, failed, build_rows = [], [], []
    for cmd in benches + builds:
        r, other, ok = run(cmd)
        if not ok:
            failed.append(os.path.basename(cmd[0]))
        rows += r
        for line in other:  # kdtree_build_bench: one line per scene, no reference
            m = re.match(r"(\S+)\s+tris\s+(\d+)\s+build_s\s+([\d.]+)", line)
            if m:
                build_rows.append((os.path.basename(m.group(1)), m.group(2), m.group(3)))

    model, cpus, avx512 = machine()
    md = [f"Benchmarks, {started}: {model}, {cpus} CPUs, AVX-512: "
          f"{' '.join(avx512) if avx512 else 'none'}; {build_flags(args.build)}. "
          "Medians of repeated runs, one thread, thread CPU time; ratio = subject / reference, "
          "both measured in the same run (for times in s, the slowdown).",
          "",
          "| benchmark | case | subject | value | reference | reference value | unit | ratio |",
          "|---|---|---|---:|---|---:|---|---:|"]
    for r in rows:
        md.append(f"| {r['bench']} | {r['case']} | {r['subject']} | {r['value']:.4g} | "
                  f"{r['reference']} | {r['reference_value']:.4g} | {r['unit']} | {r['ratio']:.3f} |")
    for name, tris, secs in build_rows:
        md.append(f"| kdtree_build_bench | {name} ({tris} tris) | SAH build | {secs} | — | — | s | — |")
    for name in failed:
        md.append(f"| {name} | FAILED | | | | | | |")
    text = "\n".join(md) + "\n"
    sys.stdout.write(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
