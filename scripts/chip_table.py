#!/usr/bin/env python3
"""The chip's layout table: node traffic per layout on a chip of 1, 4 and 16 units.

Whitted depth 4, 512x512, recursive order; each unit a node L1 of 8 KB / 4-way / 64 B / LRU,
screen tiles of 8x8 pixels dealt round-robin to the units, all units sharing an L2 of 1 MB /
16-way / 64 B / LRU in front of DRAM (functional tier). For each scene, layout and unit count:
the node bytes the L1s read from the L2 (l2.bytes.in.nodes) and the node bytes the L2 read from
DRAM (dram.bytes.nodes), beside the study's setting (one unit, no L2: its node DRAM bytes), and
how ODFL's change against DFL moves from the L1s' side of the L2 to DRAM's.
Writes chip_layouts.csv and chip_layouts.md under --out; --doc replaces the table in
docs/chip.md between its <!-- chip-table --> markers.

Usage: scripts/chip_table.py [--scenes kitchen sponza_dabrovic] [--size 512] [--units 1 4 16]
                             [--l2 1048576] [--out out/chip] [--rtusim build/rtusim] [--doc]
"""
import csv
import pathlib
import re
import sys

from layout_table import pct, run as run_layouts
from script_cli import ScriptError, guarded, output_dir, parser, positive_int, write_atomically

ROOT = pathlib.Path(__file__).resolve().parent.parent
LAYOUTS = ["dfl", "odfl", "subtree", "cluster", "profile"]
MARK_BEGIN, MARK_END = "<!-- chip-table -->", "<!-- /chip-table -->"


def main():
    ap = parser(__doc__)
    ap.add_argument("--scenes", nargs="+", default=["kitchen", "sponza_dabrovic"])
    ap.add_argument("--size", type=positive_int, default=512)
    ap.add_argument("--units", nargs="+", type=positive_int, default=[1, 4, 16])
    ap.add_argument("--l2", type=positive_int, default=1 << 20, help="L2 bytes (16-way, 64 B)")
    ap.add_argument("--out", type=pathlib.Path, default=ROOT / "out" / "chip")
    ap.add_argument("--rtusim", type=pathlib.Path, default=ROOT / "build" / "rtusim")
    ap.add_argument("--doc", action="store_true", help="put the table into docs/chip.md")
    args = ap.parse_args()
    for scene in args.scenes:
        if not (ROOT / "configs" / f"{scene}.toml").is_file():
            ap.error(f"--scenes {scene}: no configs/{scene}.toml")
    if not args.rtusim.is_file():
        ap.error(f"--rtusim {args.rtusim}: not found (build first)")
    doc = ROOT / "docs" / "chip.md"
    pattern = re.compile(re.escape(MARK_BEGIN) + ".*?" + re.escape(MARK_END), re.S)
    if args.doc and not (doc.is_file() and pattern.search(doc.read_text())):
        raise ScriptError(f"--doc: {doc}: missing, or no {MARK_BEGIN} ... {MARK_END} markers")
    output_dir(args.out)
    l2 = ["--set", "l2.enable=true", "--set", f"l2.size={args.l2}", "--set", "l2.assoc=16",
          "--set", "l2.line=64", "--set", "l2.policy=lru"]

    # The study's setting (one unit straight to DRAM), then the chip at each unit count.
    stats, rows = {}, []
    for scene in args.scenes:
        stats[(scene, 0)] = run_layouts(args.rtusim, scene, args.size, 8192,
                                        args.out / f"{scene}_no_l2", layouts=LAYOUTS)
        for units in args.units:
            stats[(scene, units)] = run_layouts(args.rtusim, scene, args.size, 8192,
                                                args.out / f"{scene}_{units}_units",
                                                [*l2, "--set", f"chip.units={units}"],
                                                layouts=LAYOUTS)
    for (scene, units), s in stats.items():
        for kind in LAYOUTS:
            p = f"layout.{kind}."
            rows.append({"scene": scene, "units": units, "l2_bytes": args.l2 if units else 0,
                         "layout": kind, "rays": s["rays.total"],
                         "node_memory_bytes": s[p + "tree.bytes"],
                         "l1_misses": s[p + "l1.misses"],
                         "l2_in_node_bytes": s.get(p + "l2.bytes.in.nodes", ""),
                         "l2_in_bytes": s.get(p + "l2.bytes.in", ""),
                         "dram_node_bytes": s[p + "dram.bytes.nodes"],
                         "dram_bytes": s[p + "dram.bytes.total"]})

    def write_csv(f):
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)

    write_atomically(args.out / "chip_layouts.csv", write_csv)

    def get(scene, units, kind, key):
        return stats[(scene, units)][f"layout.{kind}.{key}"]

    mb = lambda b: f"{b / 1e6:.2f}"
    lines = [f"Node traffic per layout on the chip (functional tier; Whitted depth 4, {args.size}x"
             f"{args.size}, recursive order; per unit a node L1 8 KB / 4-way / 64 B / LRU, 8x8 "
             f"tiles dealt round-robin; a shared L2 of {args.l2 // 1024} KB / 16-way / 64 B / "
             "LRU). MB = 10^6 bytes; L1→L2: node bytes the L1s read from the L2; DRAM: node bytes "
             "the L2 read from DRAM; no L2: one unit straight to DRAM (the study's setting). "
             "Written by `scripts/chip_table.py`.", ""]
    head = "| scene | layout | node memory KB | no L2: DRAM MB |"
    rule = "|---|---|---:|---:|"
    for units in args.units:
        head += f" {units} unit{'s' if units > 1 else ''}: L1→L2 MB | DRAM MB |"
        rule += "---:|---:|"
    lines += [head, rule]
    for scene in args.scenes:
        for kind in LAYOUTS:
            line = (f"| {scene} | {kind} | {get(scene, 0, kind, 'tree.bytes') / 1024:,.1f} | "
                    f"{mb(get(scene, 0, kind, 'dram.bytes.nodes'))} |")
            for units in args.units:
                line += (f" {mb(get(scene, units, kind, 'l2.bytes.in.nodes'))} | "
                         f"{mb(get(scene, units, kind, 'dram.bytes.nodes'))} |")
            lines.append(line)
    lines += ["", "ODFL's change of node bytes against DFL (negative = fewer):", "",
              "| scene | no L2: DRAM |" + "".join(f" {u} unit{'s' if u > 1 else ''}: L1→L2 | DRAM |"
                                               for u in args.units),
              "|---|---:|" + "---:|---:|" * len(args.units)]
    for scene in args.scenes:
        line = f"| {scene} | {pct(get(scene, 0, 'odfl', 'dram.bytes.nodes'), get(scene, 0, 'dfl', 'dram.bytes.nodes'))} |"
        for units in args.units:
            for key in ("l2.bytes.in.nodes", "dram.bytes.nodes"):
                line += f" {pct(get(scene, units, 'odfl', key), get(scene, units, 'dfl', key))} |"
        lines.append(line)
    table = "\n".join(lines) + "\n"
    write_atomically(args.out / "chip_layouts.md", lambda f: f.write(table))
    print(table)
    if args.doc:
        text = pattern.sub(lambda _: f"{MARK_BEGIN}\n{table}{MARK_END}", doc.read_text())
        write_atomically(doc, lambda f: f.write(text))
    return 0


if __name__ == "__main__":
    sys.exit(guarded(main))
