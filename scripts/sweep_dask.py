#!/usr/bin/env python3
"""Runs the pending jobs of an `rtusim sweep` as Dask tasks (started by `rtusim sweep --scheduler`).

usage: sweep_dask.py --scheduler tcp://HOST:PORT --jobs 0,3,4 -- RTUSIM sweep SPEC [--set ...] --out DIR

Each task runs `RTUSIM sweep SPEC [--set ...] --out WORKER_TMP --group K` on a worker and returns
the job's rows (jobs/K.json); this driver writes them into DIR/jobs/K.json atomically, as they
arrive, so a driver killed midway loses only the jobs in flight and a rerun skips the rest.
Workers need the same rtusim path, spec path and scenes as this machine (a shared or mirrored
file system); they do not need DIR.

Start a cluster by hand:
    dask scheduler --port 8786                        # on one machine
    dask worker tcp://SCHEDULER:8786 --nthreads 1     # on each worker machine, once per core
(each task runs one job on one core: --threads 1)
then: rtusim sweep SPEC --out DIR --scheduler tcp://SCHEDULER:8786
"""
import os
import subprocess
import sys
import tempfile
import uuid
from pathlib import Path

from script_cli import ScriptError, guarded, parser


def run_job(command, job):
    """On a worker: one job of the sweep into a private directory; returns (job, rows text)."""
    with tempfile.TemporaryDirectory(prefix="rtusim-sweep-") as tmp:
        argv = list(command) + ["--out", tmp, "--group", str(job), "--threads", "1", "--no-plots"]
        try:
            done = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        except OSError as e:  # no rtusim at that path on this worker
            return job, None, 127, f"{argv[0]}: cannot run on this worker ({e.strerror})"
        if done.returncode != 0:
            lines = [l for l in done.stdout.splitlines() if l.strip()]
            return job, None, done.returncode, lines[-1] if lines else ""
        return job, (Path(tmp) / "jobs" / f"{job}.json").read_text(), 0, ""


def split_out(command):
    """The job command without its --out DIR, and DIR (a ScriptError when it has none)."""
    if "--out" not in command or command.index("--out") + 1 >= len(command):
        raise ScriptError("the rtusim command after -- has no --out DIR")
    i = command.index("--out")
    return command[:i] + command[i + 2:], Path(command[i + 1])


def main():
    ap = parser(__doc__)
    ap.add_argument("--scheduler", required=True)
    ap.add_argument("--jobs", required=True, help="comma-separated job indices")
    ap.add_argument("command", nargs="...")
    a = ap.parse_args()
    command = a.command[1:] if a.command[:1] == ["--"] else a.command
    command, out_dir = split_out(command)
    try:
        jobs = [int(j) for j in a.jobs.split(",") if j != ""]
    except ValueError:
        raise ScriptError(f"--jobs {a.jobs}: not a comma-separated list of job indices")
    if not (out_dir / "jobs").is_dir():
        raise ScriptError(f"--out {out_dir}: no jobs/ folder (not a planned sweep directory)")
    if not jobs:
        return 0
    try:
        from distributed import Client, as_completed  # only the Dask path needs it
    except ImportError:
        print(f"rtusim: --scheduler {a.scheduler}: the Python package distributed is missing "
              f"(scripts/requirements.txt; RTUSIM_PYTHON names the Python to use)", file=sys.stderr)
        return 1

    tty = sys.stderr.isatty()
    try:
        client = Client(a.scheduler, timeout="10s")
    except (OSError, TimeoutError, ValueError) as e:
        reason = " ".join(str(e).split()) or type(e).__name__
        print(f"rtusim: --scheduler {a.scheduler}: cannot connect ({reason})", file=sys.stderr)
        return 2
    with client:
        # Keys unique to this driver: two drivers on one scheduler must not share a task (a PID
        # alone is not unique across hosts or containers).
        run_id = uuid.uuid4().hex
        futures = [client.submit(run_job, command, j, pure=False, key=f"rtusim-sweep-job-{j}-{run_id}")
                   for j in jobs]
        done = 0
        for future in as_completed(futures):
            job, text, status, last = future.result()
            if text is None:
                # Bad input: the job's own line names the spec and the job.
                print(last if status == 2 and last.startswith("rtusim: ") else
                      f"rtusim: sweep job {job} failed on a Dask worker (exit {status}): {last}",
                      file=sys.stderr)
                client.cancel(futures)
                return 2 if status == 2 else 1
            path = out_dir / "jobs" / f"{job}.json"
            tmp = path.with_name(f"{path.name}.tmp{os.getpid()}")
            tmp.write_text(text)
            os.replace(tmp, path)
            done += 1
            if tty:
                print(f"\rsweep (dask) {done}/{len(jobs)} jobs", end="", file=sys.stderr, flush=True)
        if tty:
            print(file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(guarded(main))
