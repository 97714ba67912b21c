#!/usr/bin/env python3
"""Speed against accuracy for one scene: the ladder of rtusim's methods against the full cycle tier.

Runs, over the same frame (wavefront order, so the cycle tier's rays in flight matter, one
layout): the full cycle tier (the reference), the rtl tier (when built for the config's L1),
the functional tier, the interleaved functional mode (functional.rays_in_flight = the cycle
tier's sim.rays_in_flight), the same with functional.timed = true (its estimate.cycles is its
cycles point; once with one model, once in 16 runs on every thread), sampled runs of each at several rates and methods, and a naive
method expected to fail (the cycle tier at half resolution, its counts times four). Each point
is timed as the median of --repeats runs (trace.seconds: the simulation, without scene load and
tree build; --cycle-repeats for the sampled cycle-tier and naive points, the rtl tier once). Writes speed_accuracy_<name>.csv and .png: x = speed-up against the reference,
y = relative error of node DRAM bytes and of cycles, with 95% CI bars, the Pareto front marked.

Usage: scripts/speed_accuracy.py CONFIG [--name NAME] [--size N] [--repeats 3] [--cycle-repeats N]
                                 [--no-rtl] [--out out/charts]
(the committed charts are in docs/: --out docs redraws them)
"""
import argparse
import csv
import json
import math
import pathlib
import statistics
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent


def run(rtusim, config, sets, repeats):
    """Median trace.seconds over `repeats` runs, and the last run's stats."""
    seconds, stats = [], None
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(repeats):
            cmd = [str(rtusim), "run", str(config), "--out", tmp]
            for s in sets:
                cmd += ["--set", s]
            r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            if r.returncode != 0:
                return None, r.stderr.strip()
            stats = json.loads((pathlib.Path(tmp) / "stats.json").read_text())
            seconds.append(stats["trace.seconds"])
    return statistics.median(seconds), stats


def ladder(size, rif, rtl):
    """(label, family, extra --set values, scale of counts) of every point."""
    pts = [("cycle (reference)", "cycle", ["sim.tier=cycle"], 1.0)]
    if rtl:
        pts.append(("rtl", "rtl", ["sim.tier=rtl"], 1.0))
    pts += [("functional", "functional", [], 1.0),
            (f"interleaved {rif}", "interleaved", [f"functional.rays_in_flight={rif}"], 1.0),
            (f"timed {rif}", "timed interleaved",
             [f"functional.rays_in_flight={rif}", "functional.timed=true"], 1.0),
            (f"timed {rif}, 16 runs", "timed interleaved",
             [f"functional.rays_in_flight={rif}", "functional.timed=true",
              "functional.timed_segments=16"], 1.0)]
    for rate in (0.02, 0.05, 0.1, 0.25):
        pts.append((f"functional tiles {rate}", "sampled functional",
                    ["sample.method=tiles", f"sample.rate={rate}"], 1.0))
    for method in ("random", "stratified"):
        pts.append((f"functional {method} 0.1", "sampled functional",
                    [f"sample.method={method}", "sample.rate=0.1", "sample.warmup_pixels=16"], 1.0))
    for rate in (0.05, 0.1, 0.25):
        pts.append((f"interleaved tiles {rate}", "sampled interleaved",
                    [f"functional.rays_in_flight={rif}", "sample.method=tiles",
                     f"sample.rate={rate}"], 1.0))
    for rate in (0.05, 0.1, 0.25):
        pts.append((f"cycle tiles {rate}", "sampled cycle",
                    ["sim.tier=cycle", "sample.method=tiles", f"sample.rate={rate}",
                     "sample.unit_pixels=64"], 1.0))
    pts.append(("cycle tiles target 1%", "sampled cycle",
                ["sim.tier=cycle", "sample.method=tiles", "sample.unit_pixels=64",
                 "sample.target_ci=0.01", "sample.target_key=dram.bytes.nodes"], 1.0))
    half = max(1, size // 2)
    pts.append(("naive: half resolution x4", "naive",
                ["sim.tier=cycle", f"image.width={half}", f"image.height={half}"], 4.0))
    return pts


def worst_error(r):
    """|node error| at the far end of the CI when there is one (a lucky estimate earns nothing)."""
    ends = [r["nodes_err"]] + [r[k] for k in ("nodes_err_lo", "nodes_err_hi") if r[k] is not None]
    return max(abs(e) for e in ends)


def pareto(rows):
    """Marks rows not dominated in (speed-up up, worst |node error| within the CI down)."""
    for r in rows:
        r["pareto"] = not any(
            o is not r and o["speedup"] >= r["speedup"] and worst_error(o) <= worst_error(r) and
            (o["speedup"] > r["speedup"] or worst_error(o) < worst_error(r))
            for o in rows)


def read_csv(path):
    """The rows of an earlier run, numbers parsed."""
    rows = []
    with open(path) as f:
        for r in csv.DictReader(f):
            for k, v in r.items():
                if k in ("label", "family", "ci_valid", "units", "pareto"):
                    continue
                r[k] = None if v in ("", "None") else float(v)
            rows.append(r)
    return rows


def plot(rows, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(14, 6))
    colours = {"cycle": "black", "rtl": "grey", "functional": "tab:blue",
               "interleaved": "tab:green", "timed interleaved": "tab:orange",
               "sampled functional": "tab:cyan",
               "sampled interleaved": "tab:olive", "sampled cycle": "tab:red",
               "naive": "tab:purple"}
    panels = ((axes[0], "nodes", "node DRAM bytes"),
              (axes[1], "cycles", "sim.cycles (timed mode: estimate.cycles)"))
    for ax, key, name in panels:
        for r in rows:
            err = r[f"{key}_err"]
            if err is None or math.isnan(err):
                continue
            lo, hi = r[f"{key}_err_lo"], r[f"{key}_err_hi"]
            yerr = [[100 * (err - lo)], [100 * (hi - err)]] if lo is not None else None
            ax.errorbar(r["speedup"], 100 * err, yerr=yerr, fmt="o", capsize=3,
                        color=colours[r["family"]], mec="gold" if r["pareto"] and key == "nodes" else None,
                        mew=2 if r["pareto"] and key == "nodes" else 1)
            ax.annotate(r["label"], (r["speedup"], 100 * err), fontsize=7,
                        xytext=(4, 3), textcoords="offset points")
        if key == "nodes":
            front = sorted((r for r in rows if r["pareto"]), key=lambda r: r["speedup"])
            ax.plot([r["speedup"] for r in front], [100 * r["nodes_err"] for r in front],
                    "--", color="gold", label="Pareto front (speed-up, |error| at the CI's far end)")
            ax.legend(loc="best", fontsize=8)
        ax.axhline(0, color="k", lw=0.5)
        ax.axhspan(-1, 1, color="green", alpha=0.08)
        ax.set_xscale("log")
        ax.set_yscale("symlog", linthresh=2)  # linear within +-2%, logarithmic beyond
        ax.set_xlabel("speed-up against the full cycle tier (median trace seconds)")
        ax.set_ylabel(f"relative error of {name} (%)")
        ax.set_title(name)
        ax.grid(True, which="both", alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config", type=pathlib.Path)
    ap.add_argument("--name")
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--cycle-repeats", type=int, help="repeats of the sampled cycle-tier and "
                    "naive points (default: --repeats)")
    ap.add_argument("--rays-in-flight", type=int, default=32)
    ap.add_argument("--no-rtl", action="store_true")
    ap.add_argument("--replot", action="store_true", help="redraw from the CSV of an earlier run")
    ap.add_argument("--out", type=pathlib.Path, default=ROOT / "out" / "charts",
                    help="output directory (default out/charts; docs: the committed set)")
    ap.add_argument("--rtusim", type=pathlib.Path, default=ROOT / "build" / "rtusim")
    args = ap.parse_args()
    name = args.name or args.config.stem
    common = [f"image.width={args.size}", f"image.height={args.size}", "tracer.ray_order=wavefront",
              "layout.kind=dfl", f"sim.rays_in_flight={args.rays_in_flight}", "image.png=false",
              "image.heatmaps=false"]
    csv_path = args.out / f"speed_accuracy_{name}.csv"
    cycle_repeats = args.cycle_repeats or args.repeats
    title = (f"{name} {args.size}x{args.size}, Whitted depth 4, wavefront, dfl, "
             f"{args.rays_in_flight} rays in flight; medians of {args.repeats} runs" +
             (f" ({cycle_repeats} for sampled cycle and naive)" if cycle_repeats != args.repeats
              else ""))
    if args.replot:
        rows = read_csv(csv_path)
    else:
        rows = measure(args, common)
    pareto(rows)
    args.out.mkdir(parents=True, exist_ok=True)
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    plot(rows, args.out / f"speed_accuracy_{name}.png", title)
    print(f"wrote {csv_path} and its .png")


def measure(args, common):
    """Runs the ladder; one row per point that ran."""
    rows, ref = [], None
    for label, family, sets, scale in ladder(args.size, args.rays_in_flight, not args.no_rtl):
        sets = common + sets
        repeats = 1 if family in ("rtl",) else args.repeats
        if family in ("sampled cycle", "naive"):
            repeats = args.cycle_repeats or args.repeats
        print(f"+ {label}", flush=True)
        seconds, stats = run(args.rtusim, args.config, sets, repeats)
        if seconds is None:
            print(f"  skipped: {stats}", flush=True)
            continue
        if ref is None:
            ref = (seconds, stats)
        row = {"label": label, "family": family, "seconds": seconds,
               "speedup": ref[0] / seconds if seconds > 0 else float("inf"),
               "fraction": stats.get("sample.fraction", 1.0 / scale),
               "units": stats.get("sample.units", ""), "ci_valid": stats.get("sample.ci_valid", "")}
        for key, stat in (("nodes", "dram.bytes.nodes"), ("cycles", "sim.cycles")):
            truth = ref[1][stat]
            if stat == "sim.cycles" and "estimate.cycles" in stats:
                stat = "estimate.cycles"  # the timed mode's estimate of sim.cycles
            if stat not in stats:
                row.update({key: None, f"{key}_err": None, f"{key}_err_lo": None,
                            f"{key}_err_hi": None})
                continue
            v = stats[stat] * scale
            row[key] = v
            row[f"{key}_err"] = v / truth - 1
            lo, hi = stats.get(stat + ".ci95_low"), stats.get(stat + ".ci95_high")
            row[f"{key}_err_lo"] = None if lo is None else lo * scale / truth - 1
            row[f"{key}_err_hi"] = None if hi is None else hi * scale / truth - 1
        rows.append(row)
        print(f"  {seconds:.3f} s, x{row['speedup']:.1f}, node error {100 * row['nodes_err']:+.2f}%",
              flush=True)
    return rows


if __name__ == "__main__":
    sys.exit(main())
