#!/usr/bin/env python3
"""The layout table: every layout x the shared scenes at three node-L1 sizes.

Whitted depth 4, 512x512, recursive order, node L1 4-way / 64 B / LRU at 8 KB (the study's
setting), 4 KB and 32 KB; all layouts over the same rays, the tree built once per run. For each
scene and layout: node memory, node DRAM bytes per L1 size, and the reduction against DFL and
ODFL. Optionally (--cycle) the cycle tier with 32 rays in flight on the given scenes.
Writes layouts.csv and layouts.md under --out; --readme replaces the table in README.md between
its <!-- layout-table --> markers.

Usage: scripts/layout_table.py [--scenes kitchen sponza_dabrovic ...] [--size 512]
                               [--l1 8192 4096 32768] [--cycle kitchen sponza_dabrovic]
                               [--cycle-size 512] [--out out/layouts] [--rtusim build/rtusim]
                               [--readme]
"""
import csv
import json
import pathlib
import re
import sys

from script_cli import (ScriptError, guarded, output_dir, parser, positive_int, run_rtusim,
                        write_atomically)

ROOT = pathlib.Path(__file__).resolve().parent.parent
LAYOUTS = ["dfl", "odfl", "subtree", "subtree-bfs", "veb", "cluster", "profile"]
SCENES = ["kitchen", "sponza_dabrovic", "cornell_whitted", "iridescent_dish",
          "metal_rough_spheres", "box"]
MARK_BEGIN, MARK_END = "<!-- layout-table -->", "<!-- /layout-table -->"


def run(rtusim, scene, size, l1_bytes, out_dir, extra=(), reuse=False, layouts=LAYOUTS):
    """One rtusim run of every layout; returns its stats (with reuse, an earlier run's)."""
    if reuse and (out_dir / "stats.json").exists():
        return json.loads((out_dir / "stats.json").read_text())
    kinds = ",".join(f'"{k}"' for k in layouts)
    cmd = [str(rtusim), "run", str(ROOT / "configs" / f"{scene}.toml"),
           "--set", f"layout.kind=[{kinds}]",
           "--set", f"image.width={size}", "--set", f"image.height={size}",
           "--set", "tracer.max_depth=4", "--set", "tracer.ray_order=recursive",
           "--set", f"l1.size={l1_bytes}", "--set", "l1.assoc=4", "--set", "l1.line=64",
           "--set", "l1.policy=lru", "--set", "image.png=false", "--set", "image.heatmaps=false",
           *extra, "--out", str(out_dir)]
    print("+", " ".join(cmd), flush=True)
    run_rtusim(cmd, f"{scene}, {size}x{size}, l1.size {l1_bytes}")
    return json.loads((out_dir / "stats.json").read_text())


def pct(x, base):
    return f"{100 * (x / base - 1):+.1f}%"


def main():
    ap = parser(__doc__)
    ap.add_argument("--scenes", nargs="*", default=SCENES)
    ap.add_argument("--size", type=positive_int, default=512)
    ap.add_argument("--l1", nargs="+", type=positive_int, default=[8192, 4096, 32768])
    ap.add_argument("--cycle", nargs="*", default=[], help="scenes for the cycle-tier table")
    ap.add_argument("--cycle-size", type=positive_int, default=512)
    ap.add_argument("--out", type=pathlib.Path, default=ROOT / "out" / "layouts")
    ap.add_argument("--rtusim", type=pathlib.Path, default=ROOT / "build" / "rtusim")
    ap.add_argument("--readme", action="store_true", help="put the table into README.md")
    ap.add_argument("--reuse", action="store_true",
                    help="take the stats of runs already in --out (same settings) instead of rerunning")
    args = ap.parse_args()
    if not args.scenes and not args.cycle:
        ap.error("nothing to tabulate: give --scenes or --cycle")
    for scene in args.scenes + args.cycle:
        if not (ROOT / "configs" / f"{scene}.toml").is_file():
            ap.error(f"--scenes/--cycle {scene}: no configs/{scene}.toml")
    if not args.rtusim.is_file():
        ap.error(f"--rtusim {args.rtusim}: not found (build first)")
    readme = ROOT / "README.md"
    pattern = re.compile(re.escape(MARK_BEGIN) + ".*?" + re.escape(MARK_END), re.S)
    if args.readme and not (readme.is_file() and pattern.search(readme.read_text())):
        raise ScriptError(f"--readme: {readme}: missing, or no {MARK_BEGIN} ... {MARK_END} markers")
    output_dir(args.out)

    # Functional tier: node memory and node DRAM bytes per scene, layout and L1 size.
    rows, stats = [], {}
    for scene in args.scenes:
        for l1 in args.l1:
            s = run(args.rtusim, scene, args.size, l1, args.out / f"{scene}_{args.size}_l1_{l1}",
                    reuse=args.reuse)
            stats[(scene, l1)] = s
            for kind in LAYOUTS:
                p = f"layout.{kind}."
                rows.append({"tier": "functional", "scene": scene, "l1_bytes": l1,
                             "layout": kind, "rays": s["rays.total"],
                             "node_memory_bytes": s[p + "tree.bytes"],
                             "node_fetches": s[p + "traversal.node_fetches"],
                             "node_dram_bytes": s[p + "dram.bytes.nodes"], "cycles": ""})
    # Cycle tier: 32 rays in flight at the study's L1.
    for scene in args.cycle:
        s = run(args.rtusim, scene, args.cycle_size, 8192,
                args.out / f"{scene}_cycle_{args.cycle_size}",
                ["--set", 'sim.tier="cycle"', "--set", "sim.rays_in_flight=32"], args.reuse)
        stats[(scene, "cycle")] = s
        for kind in LAYOUTS:
            p = f"layout.{kind}."
            rows.append({"tier": "cycle", "scene": scene, "l1_bytes": 8192, "layout": kind,
                         "rays": s["rays.total"], "node_memory_bytes": s[p + "tree.bytes"],
                         "node_fetches": s[p + "traversal.node_fetches"],
                         "node_dram_bytes": s[p + "dram.bytes.nodes"],
                         "cycles": s[p + "sim.cycles"]})

    if not rows:
        raise ScriptError("nothing to tabulate: give --scenes or --cycle")

    def write_csv(f):
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)

    write_atomically(args.out / "layouts.csv", write_csv)

    def node(scene, key, kind, what):
        return stats[(scene, key)][f"layout.{kind}.{what}"]

    head = "| scene | layout | node memory KB | × ODFL |"
    rule = "|---|---|---:|---:|"
    for l1 in args.l1:
        head += f" {l1 // 1024} KB: node DRAM MB | vs DFL | vs ODFL |"
        rule += "---:|---:|---:|"
    lines = [] if not args.scenes else [f"Node DRAM traffic per layout (functional tier; Whitted depth 4, {args.size}x"
             f"{args.size}, recursive order, node L1 4-way / 64 B / LRU; vs = change of node "
             "DRAM bytes, negative = fewer). Written by `scripts/layout_table.py`.", "",
             head, rule]
    for scene in args.scenes:
        for kind in LAYOUTS:
            mem = node(scene, args.l1[0], kind, "tree.bytes")
            omem = node(scene, args.l1[0], "odfl", "tree.bytes")
            line = f"| {scene} | {kind} | {mem / 1024:,.1f} | {mem / omem:.2f} |"
            for l1 in args.l1:
                b = node(scene, l1, kind, "dram.bytes.nodes")
                line += (f" {b / 1e6:.2f} | {pct(b, node(scene, l1, 'dfl', 'dram.bytes.nodes'))} | "
                         f"{pct(b, node(scene, l1, 'odfl', 'dram.bytes.nodes'))} |")
            lines.append(line)
    if args.cycle:
        lines += [] if not lines else [""]
        lines += [f"Cycle tier, 32 rays in flight, {args.cycle_size}x{args.cycle_size}, "
                  "node L1 8 KB / 4-way / 64 B / LRU, DDR4-2400:", "",
                  "| scene | layout | cycles | vs ODFL | node DRAM MB | vs ODFL |",
                  "|---|---|---:|---:|---:|---:|"]
        for scene in args.cycle:
            for kind in LAYOUTS:
                c, b = node(scene, "cycle", kind, "sim.cycles"), node(scene, "cycle", kind,
                                                                     "dram.bytes.nodes")
                lines.append(
                    f"| {scene} | {kind} | {c:,} | {pct(c, node(scene, 'cycle', 'odfl', 'sim.cycles'))} | "
                    f"{b / 1e6:.2f} | {pct(b, node(scene, 'cycle', 'odfl', 'dram.bytes.nodes'))} |")
    table = "\n".join(lines) + "\n"
    write_atomically(args.out / "layouts.md", lambda f: f.write(table))
    print(table)

    if args.readme:
        text = pattern.sub(lambda _: f"{MARK_BEGIN}\n{table}{MARK_END}", readme.read_text())
        write_atomically(readme, lambda f: f.write(text))
    return 0


if __name__ == "__main__":
    sys.exit(guarded(main))
