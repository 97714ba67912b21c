#!/usr/bin/env python3
"""Plots of an `rtusim sweep` (run by the command itself; or by hand: sweep_plot.py DIR).

From DIR/results.csv and DIR/sweep.toml (which columns were swept):
  miss_ratio_curves[_<case>].png  node DRAM bytes per ray (log axis) against L1 size (log2 axis), one line
                                  per associativity, one panel per layout x line size; one file
                                  per combination of the other swept keys (a scene, ...)
  layout_comparison.png           node DRAM bytes per ray of each layout at the default cache
                                  (8 KB, 4-way, 64 B, LRU), per combination of the other keys
"""
import argparse
import csv
import re
import sys
import tomllib
from collections import defaultdict
from pathlib import Path

plt = None  # matplotlib.pyplot, imported once the arguments are known to be good

Y_KEY = "report.node_dram_bytes_per_ray"
Y_LABEL = "node DRAM traffic (bytes per ray)"
CURVE_KEYS = ("layout.kind", "l1.line", "l1.assoc", "l1.size", "l1.policy")
DEFAULT_CACHE = {"l1.size": "8192", "l1.assoc": "4", "l1.line": "64", "l1.policy": "lru"}


def swept_keys(spec_path):
    """The swept keys of a spec, as the CSV names them."""
    sweep = tomllib.loads(spec_path.read_text()).get("sweep", {})
    keys = []

    def flatten(table, prefix, out):
        for k, v in table.items():
            name = f"{prefix}.{k}" if prefix else k
            if isinstance(v, dict):
                flatten(v, name, out)
            else:
                out.append(name)

    for k, v in sweep.items():
        if k == "group":
            for entries in v.values():
                for entry in entries:
                    flatten(entry, "", keys)
        elif isinstance(v, dict):
            flatten(v, k, keys)
        else:
            keys.append(k)
    return list(dict.fromkeys(keys))


def short(value):
    """A file-name-friendly label of a value (a scene path becomes its file stem)."""
    value = Path(value).stem if "/" in value else value
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", value)


def assoc_order(a):
    return (1, 0) if a == "full" else (0, int(a))


def size_label(b):
    b = int(b)
    return f"{b // 1024}" if b % 1024 == 0 else f"{b / 1024:g}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir", type=Path, help="a finished sweep's directory (its results.csv, sweep.toml)")
    out = ap.parse_args().dir
    for name in ("results.csv", "sweep.toml"):
        if not (out / name).is_file():
            print(f"sweep_plot.py: {out / name}: not found (DIR must be a finished `rtusim sweep` "
                  f"directory)", file=sys.stderr)
            return 2
    global plt
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    with open(out / "results.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    header = list(rows[0].keys()) if rows else []
    swept = [k for k in swept_keys(out / "sweep.toml") if k in header]
    other = [k for k in swept if k not in CURVE_KEYS]
    written = []

    def case_of(row):
        return tuple(row[k] for k in other)

    def case_title(case, sep=", "):
        return sep.join(f"{k} = {short(v)}" for k, v in zip(other, case) if v != "")

    # Miss-ratio curves.
    if "l1.size" in swept:
        cases = defaultdict(list)
        for r in rows:
            cases[case_of(r)].append(r)
        for case, rs in cases.items():
            layouts = list(dict.fromkeys(r.get("layout.kind", "") for r in rs))
            lines = sorted({r.get("l1.line", "") for r in rs}, key=lambda v: int(v or 0))
            fig, axes = plt.subplots(len(layouts), len(lines), squeeze=False, sharex=True,
                                     sharey=True, figsize=(4.2 * len(lines), 3.2 * len(layouts)))
            for i, layout in enumerate(layouts):
                for j, line in enumerate(lines):
                    ax = axes[i][j]
                    panel = [r for r in rs if r.get("layout.kind", "") == layout
                             and r.get("l1.line", "") == line]
                    curves = defaultdict(list)
                    for r in panel:
                        curves[(r.get("l1.policy", ""), r.get("l1.assoc", ""))].append(r)
                    for (policy, assoc), pts in sorted(curves.items(),
                                                       key=lambda kv: (kv[0][0], assoc_order(kv[0][1] or "0"))):
                        pts.sort(key=lambda r: int(r["l1.size"]))
                        label = ("fully associative" if assoc == "full" else f"{assoc}-way") \
                            + (f" {policy}" if policy and len({p for p, _ in curves}) > 1 else "")
                        ax.plot([int(r["l1.size"]) / 1024 for r in pts],
                                [float(r[Y_KEY]) for r in pts], marker="o", ms=3, label=label)
                    ax.set_xscale("log", base=2)
                    ax.set_yscale("log")
                    sizes = sorted({int(r["l1.size"]) for r in panel})
                    ax.set_xticks([s / 1024 for s in sizes], [size_label(s) for s in sizes])
                    ax.set_title(f"{layout or 'layout'}, {line or '?'} B lines", fontsize=10)
                    ax.grid(True, which="both", alpha=0.3)
                    if i == len(layouts) - 1:
                        ax.set_xlabel("L1 size (KB)")
                    if j == 0:
                        ax.set_ylabel(Y_LABEL)
            axes[0][0].legend(fontsize=8)
            title = "Node L1 miss-ratio curves"
            if case_title(case):
                title += f" ({case_title(case)})"
            fig.suptitle(title)
            fig.tight_layout()
            name = "miss_ratio_curves" + "".join("_" + short(v) for v in case if v != "") + ".png"
            fig.savefig(out / name, dpi=110)
            plt.close(fig)
            written.append(name)

    # Layout comparison at the default cache (keys not swept are the base config's).
    if "layout.kind" in swept:
        at_default = [r for r in rows
                      if all(r.get(k, v) == v for k, v in DEFAULT_CACHE.items() if k in swept)]
        if at_default:
            cases = list(dict.fromkeys(case_of(r) for r in at_default))
            layouts = list(dict.fromkeys(r["layout.kind"] for r in at_default))
            fig, ax = plt.subplots(figsize=(max(6, 1.2 * len(cases) * len(layouts)), 4.5))
            width = 0.8 / len(layouts)
            for li, layout in enumerate(layouts):
                vals = []
                for case in cases:
                    match = [r for r in at_default if case_of(r) == case and r["layout.kind"] == layout]
                    vals.append(float(match[0][Y_KEY]) if match else 0.0)
                xs = [c + (li - (len(layouts) - 1) / 2) * width for c in range(len(cases))]
                bars = ax.bar(xs, vals, width, label=layout)
                ax.bar_label(bars, fmt="%.0f", fontsize=7)
            ax.set_xticks(range(len(cases)), [case_title(c, "\n") or "base config" for c in cases],
                          fontsize=8)
            ax.set_ylabel(Y_LABEL)
            ax.set_title("Layouts at the default node L1 (8 KB, 4-way, 64 B lines, LRU)")
            ax.legend()
            fig.tight_layout()
            fig.savefig(out / "layout_comparison.png", dpi=110)
            plt.close(fig)
            written.append("layout_comparison.png")

    print("wrote " + (", ".join(str(out / w) for w in written) if written else "no plot (no l1.size or layout.kind swept)"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
