#!/usr/bin/env python3
"""Plots of an `rtusim sweep` (run by the command itself; or by hand: sweep_plot.py DIR).

From DIR/results.csv and DIR/sweep.toml (which columns were swept):
  miss_ratio_curves[_<case>].png  node DRAM bytes per ray (log axis) against L1 size (log2 axis), one line
                                  per associativity, one panel per layout x line size; one file
                                  per combination of the other swept keys (a scene, ...)
  layout_comparison.png           node DRAM bytes per ray of each layout at the base config's
                                  node L1 (DIR/base.toml; the default cache, 8 KB, 4-way, 64 B,
                                  LRU, when the base's is not among the points), per combination
                                  of the other keys
Bad input (a file missing or not parsing, a column missing, a value not a number) is one line and
exit status 2, before any plot is written.
"""
import csv
import re
import sys
import tomllib
from collections import defaultdict
from pathlib import Path

from script_cli import ScriptError, guarded, parser, save_figure

plt = None  # matplotlib.pyplot, imported once the arguments are known to be good

Y_KEY = "report.node_dram_bytes_per_ray"
Y_LABEL = "node DRAM traffic (bytes per ray)"
CURVE_KEYS = ("layout.kind", "l1.line", "l1.assoc", "l1.size", "l1.policy")
DEFAULT_CACHE = {"l1.size": "8192", "l1.assoc": "4", "l1.line": "64", "l1.policy": "lru"}


def read_toml(path):
    """A TOML file's table; a ScriptError naming the file when it does not parse."""
    try:
        return tomllib.loads(path.read_text())
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
        raise ScriptError(f"{path}: {e}")


def base_cache(base_path):
    """The base config's node L1 as the CSV writes it (the default cache for keys it leaves out)."""
    l1 = read_toml(base_path).get("l1", {}) if base_path.is_file() else {}
    return {k: str(l1.get(k.split(".")[1], v)) for k, v in DEFAULT_CACHE.items()}


def check_rows(path, rows, swept):
    """Every row has the plotted column and numbers where the plots need them."""
    numeric = [Y_KEY] + [k for k in ("l1.size", "l1.line") if k in swept]
    for line, r in enumerate(rows, start=2):
        for k in numeric:
            try:
                float(r[k] or "")
            except KeyError:
                raise ScriptError(f"{path}: no column {k}")
            except ValueError:
                raise ScriptError(f"{path}:{line}: {k}: {r[k]!r} is not a number")
        if "l1.assoc" in swept and r["l1.assoc"] != "full" and not r["l1.assoc"].isdigit():
            raise ScriptError(f"{path}:{line}: l1.assoc: {r['l1.assoc']!r} is not a number or full")


def swept_keys(spec_path):
    """The swept keys of a spec, as the CSV names them."""
    sweep = read_toml(spec_path).get("sweep", {})
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
    ap = parser(__doc__)
    ap.add_argument("dir", type=Path, help="a finished sweep's directory (its results.csv, sweep.toml)")
    out = ap.parse_args().dir
    for name in ("results.csv", "sweep.toml"):
        if not (out / name).is_file():
            raise ScriptError(f"{out / name}: not found (DIR must be a finished `rtusim sweep` "
                              f"directory)")
    try:
        with open(out / "results.csv", newline="") as f:
            rows = list(csv.DictReader(f))
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise ScriptError(f"{out / 'results.csv'}: {e}")
    if not rows:
        raise ScriptError(f"{out / 'results.csv'}: no rows (the sweep has not finished)")
    header = list(rows[0].keys())
    swept = [k for k in swept_keys(out / "sweep.toml") if k in header]
    check_rows(out / "results.csv", rows, swept)
    base = base_cache(out / "base.toml")
    other = [k for k in swept if k not in CURVE_KEYS]
    global plt
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
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
            lines = sorted({r.get("l1.line", base["l1.line"]) for r in rs}, key=int)
            fig, axes = plt.subplots(len(layouts), len(lines), squeeze=False, sharex=True,
                                     sharey=True, figsize=(4.2 * len(lines), 3.2 * len(layouts)))
            for i, layout in enumerate(layouts):
                for j, line in enumerate(lines):
                    ax = axes[i][j]
                    panel = [r for r in rs if r.get("layout.kind", "") == layout
                             and r.get("l1.line", base["l1.line"]) == line]
                    curves = defaultdict(list)
                    for r in panel:
                        curves[(r.get("l1.policy", ""), r.get("l1.assoc", base["l1.assoc"]))].append(r)
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
                    ax.set_title(f"{layout or 'layout'}, {line} B lines", fontsize=10)
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
            if name in written:  # two cases with the same short name (scenes of one file stem)
                name = name[:-4] + f"_{len(written) + 1}.png"
            save_figure(fig, out / name, dpi=110)
            plt.close(fig)
            written.append(name)

    # Layout comparison at the base config's cache, else the default cache (keys not swept are
    # the base config's).
    if "layout.kind" in swept:
        at_default, cache = [], base
        for cache in (base, DEFAULT_CACHE):
            at_default = [r for r in rows
                          if all(r.get(k, v) == v for k, v in cache.items() if k in swept)]
            if at_default:
                break
        if at_default:
            cache = {k: (at_default[0][k] if k in swept else base[k]) for k in cache}
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
            ways = "fully associative" if cache["l1.assoc"] == "full" else f"{cache['l1.assoc']}-way"
            ax.set_title(f"Layouts at the node L1 of {size_label(cache['l1.size'])} KB, {ways}, "
                         f"{cache['l1.line']} B lines, {cache['l1.policy'].upper()}")
            ax.legend()
            fig.tight_layout()
            save_figure(fig, out / "layout_comparison.png", dpi=110)
            plt.close(fig)
            written.append("layout_comparison.png")

    print("wrote " + (", ".join(str(out / w) for w in written) if written else "no plot (no l1.size or layout.kind swept)"))
    return 0


if __name__ == "__main__":
    sys.exit(guarded(main))
