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

from script_cli import (ScriptError, existing_file, guarded, output_dir, parser, positive_int,
                        save_figure, write_atomically)

ROOT = pathlib.Path(__file__).resolve().parent.parent


def run(rtusim, config, sets, repeats):
    """Median trace.seconds over `repeats` runs, and the last run's stats."""
    seconds, stats = [], None
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(repeats):
            cmd = [str(rtusim), "run", str(config), "--out", tmp]
            for s in sets:
                cmd += ["--set", s]
            try:
                r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            except OSError as e:
                raise ScriptError(f"--rtusim {rtusim}: cannot run ({e.strerror})")
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
    """|node error| at the far end of the CI when there is one (a lucky estimate earns nothing;
    an open-ended CI, from too few units, is an infinite error)."""
    ends = [r["nodes_err"]] + [r[k] for k in ("nodes_err_lo", "nodes_err_hi") if r[k] is not None]
    return max(abs(e) for e in ends)


def pareto(rows):
    """Marks rows not dominated in (speed-up up, worst |node error| within the CI down)."""
    for r in rows:
        r["pareto"] = not any(
            o is not r and o["speedup"] >= r["speedup"] and worst_error(o) <= worst_error(r) and
            (o["speedup"] > r["speedup"] or worst_error(o) < worst_error(r))
            for o in rows)


# The run's settings, in every row of the CSV (the chart's title is drawn from them).
SETTINGS = ("size", "repeats", "cycle_repeats", "rays_in_flight")
TEXT_COLUMNS = ("label", "family", "ci_valid", "units", "pareto")


def read_csv(path):
    """The rows of an earlier run, numbers parsed; a ScriptError when it is not such a CSV."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        raise ScriptError(f"--replot: {path}: cannot read ({e.strerror})")
    need = ("label", "family", "speedup", "nodes_err", "nodes_err_lo", "nodes_err_hi",
            "cycles_err", "cycles_err_lo", "cycles_err_hi") + SETTINGS
    missing = [k for k in need if not rows or k not in rows[0]]
    if missing:
        raise ScriptError(f"--replot: {path}: not a speed_accuracy CSV of this version "
                          f"(no rows, or no column {missing[0]})")
    for line, r in enumerate(rows, start=2):
        for k, v in r.items():
            if k in TEXT_COLUMNS:
                continue
            try:
                r[k] = None if v in ("", "None") else float(v)
            except (TypeError, ValueError):
                raise ScriptError(f"--replot: {path}:{line}: column {k}: {v!r} is not a number")
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
            yerr = None
            if lo is not None and hi is not None and math.isfinite(hi):
                yerr = [[100 * (err - lo)], [100 * (hi - err)]]
            elif lo is not None:  # an open-ended CI (too few units): its low end and an arrow up
                yerr = [[100 * (err - lo)], [0]]
                ax.annotate("", xy=(r["speedup"], 100 * err + 50), xytext=(r["speedup"], 100 * err),
                            arrowprops={"arrowstyle": "->", "color": colours[r["family"]]})
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
    save_figure(fig, path, dpi=110)


def main():
    ap = parser(__doc__)
    ap.add_argument("config", type=pathlib.Path)
    ap.add_argument("--name", help="the scene's name in the output files (default: the config's stem)")
    ap.add_argument("--size", type=positive_int, default=512, help="image width and height (default 512)")
    ap.add_argument("--repeats", type=positive_int, default=3, help="runs per point (default 3)")
    ap.add_argument("--cycle-repeats", type=positive_int, help="repeats of the sampled cycle-tier and "
                    "naive points (default: --repeats)")
    ap.add_argument("--rays-in-flight", type=positive_int, default=32,
                    help="the cycle tier's sim.rays_in_flight and the interleaved modes' (default 32)")
    ap.add_argument("--no-rtl", action="store_true", help="leave out the rtl tier")
    ap.add_argument("--replot", action="store_true", help="redraw from the CSV of an earlier run "
                    "(its settings, not these options', title the chart)")
    ap.add_argument("--out", type=pathlib.Path, default=ROOT / "out" / "charts",
                    help="output directory (default out/charts; docs: the committed set)")
    ap.add_argument("--rtusim", type=pathlib.Path, default=ROOT / "build" / "rtusim")
    args = ap.parse_args()
    name = args.name or args.config.stem
    csv_path = args.out / f"speed_accuracy_{name}.csv"
    if args.replot:
        rows = read_csv(csv_path)
        settings = {}
        for k in SETTINGS:
            if rows[0][k] is None:
                raise ScriptError(f"--replot: {csv_path}: column {k} is empty")
            settings[k] = int(rows[0][k])
        for r in rows:  # written back as the integers they are
            r.update(settings)
    else:
        existing_file(args.config, "CONFIG")
        existing_file(args.rtusim, "--rtusim")
        output_dir(args.out)
        settings = {"size": args.size, "repeats": args.repeats,
                    "cycle_repeats": args.cycle_repeats or args.repeats,
                    "rays_in_flight": args.rays_in_flight}
        common = [f"image.width={args.size}", f"image.height={args.size}",
                  "tracer.ray_order=wavefront", "layout.kind=dfl",
                  f"sim.rays_in_flight={args.rays_in_flight}", "image.png=false",
                  "image.heatmaps=false"]
        rows = measure(args, common)
        for r in rows:
            r.update(settings)
    output_dir(args.out)
    pareto(rows)
    size, repeats, cycle_repeats = settings["size"], settings["repeats"], settings["cycle_repeats"]
    title = (f"{name} {size}x{size}, wavefront, dfl, {settings['rays_in_flight']} rays in flight; "
             f"medians of {repeats} runs" +
             (f" ({cycle_repeats} for sampled cycle and naive)" if cycle_repeats != repeats else ""))

    def write(f):
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)

    write_atomically(csv_path, write)
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
            first = (stats.splitlines() or [""])[0]
            if ref is None:  # every error is measured against it: nothing to chart without it
                raise ScriptError(f"{args.config}: the reference ({label}) failed: {first}")
            print(f"  skipped: {first}", flush=True)
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
            # A CI key present but null is an open-ended interval (too few units): infinite.
            lo = stats.get(stat + ".ci95_low", None)
            hi = stats.get(stat + ".ci95_high", None)
            open_ended = stat + ".ci95_high" in stats and hi is None
            row[f"{key}_err_lo"] = None if lo is None else lo * scale / truth - 1
            row[f"{key}_err_hi"] = (math.inf if open_ended else
                                    None if hi is None else hi * scale / truth - 1)
        rows.append(row)
        print(f"  {seconds:.3f} s, x{row['speedup']:.1f}, node error {100 * row['nodes_err']:+.2f}%",
              flush=True)
    return rows


if __name__ == "__main__":
    sys.exit(guarded(main))
