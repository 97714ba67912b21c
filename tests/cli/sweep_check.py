"""Checks a sweep's results.csv against one `rtusim run` per point (helper of the sweep CLI tests).

usage: sweep_check.py RTUSIM SWEEP_DIR EVERY_NTH SWEPT_KEY,SWEPT_KEY,...
Runs `rtusim run SWEEP_DIR/base.toml --set KEY=VALUE ...` for every EVERY_NTH point (and the
last) and compares every stats.json key that is not a timing with the row's cell.
"full" goes to rtusim run as it is (the config reads it natively).
"""
import csv
import json
import subprocess
import sys
import tempfile
from pathlib import Path


def timing(key):
    return key.endswith(("seconds", "trace.rays_per_second", "sample.rays_simulated_per_second"))


def cell(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def main():
    rtusim, sweep_dir, every = sys.argv[1], Path(sys.argv[2]), int(sys.argv[3])
    spec_keys = json.loads((sweep_dir / "sweep.json").read_text())
    with open(sweep_dir / "results.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    header = list(rows[0].keys())
    swept = sys.argv[4].split(",")
    if header[:len(swept)] != swept:
        print(f"sweep_check: the first columns are {header[:len(swept)]}, want {swept}")
        return 1
    sets = spec_keys["set"]
    bad = 0
    picked = list(range(0, len(rows), every)) + [len(rows) - 1]
    for i in sorted(set(picked)):
        row = rows[i]
        over = {k: row[k] for k in swept if row[k] != ""}
        with tempfile.TemporaryDirectory() as out:
            cmd = [rtusim, "run", str(sweep_dir / "base.toml"), "--out", out]
            for s in sets + [f"{k}={v}" for k, v in over.items()]:
                cmd += ["--set", s]
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
            stats = json.loads((Path(out) / "stats.json").read_text())
        for k, v in stats.items():
            if timing(k) or k in swept:
                continue
            if k not in row:
                print(f"point {i} {over}: column {k} missing")
                bad += 1
            elif row[k] != cell(v) and float(row[k]) != v:
                print(f"point {i} {over}: {k}: sweep {row[k]}, run {v}")
                bad += 1
    print(f"sweep_check: {len(set(picked))} points compared, {bad} mismatches")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
