#!/usr/bin/env bash
# The progress bar: on a terminal (a pseudo-terminal here) a run longer than its 2 s quiet time
# draws "\r  LABEL [###   ]  NN%" frames with a non-decreasing share, ending at 100% and a
# newline; with stderr not a terminal it draws nothing. RTUSIM_PROGRESS_QUIET_S=0 makes the bar
# draw from the start, so a fast machine still shows frames.
set -euo pipefail
rtusim=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
args=(run "$src/configs/default.toml" --set sim.tier=cycle --set image.width=160 --set image.height=160)
python3 - "$rtusim" "$tmp" "${args[@]}" <<'PY'
import os, pty, re, subprocess, sys
rtusim, tmp, args = sys.argv[1], sys.argv[2], sys.argv[3:]
master, slave = pty.openpty()
env = dict(os.environ, RTUSIM_PROGRESS_QUIET_S="0")
p = subprocess.Popen([rtusim] + args + ["--out", f"{tmp}/tty"], stdout=subprocess.DEVNULL,
                     stderr=slave, close_fds=True, env=env)
os.close(slave)
data = b""
while True:
    try:
        chunk = os.read(master, 4096)
    except OSError:
        break
    if not chunk:
        break
    data += chunk
assert p.wait() == 0, data
text = data.decode()
frames = re.findall(r"\r  (\S+)\s+\[(#*) *\]\s+(\d+)%", text)
assert frames, f"no progress frames in {text!r}"
shares = [int(f[2]) for f in frames]
assert shares == sorted(shares), shares
assert shares[-1] == 100 and frames[-1][1] == "#" * 30, frames[-1]
# The bar is floor(30 f), the percentage round(100 f): they differ by up to 1.15 characters.
assert all(abs(len(f[1]) - int(f[2]) * 30 / 100) <= 1.2 for f in frames), frames
assert text.rstrip(" \r").endswith("\n") or text.endswith("\r\n"), repr(text[-40:])
# Not a terminal: nothing on stderr.
q = subprocess.run([rtusim] + args + ["--out", f"{tmp}/pipe"], stdout=subprocess.DEVNULL,
                   stderr=subprocess.PIPE, check=True, env=env)
assert q.stderr == b"", q.stderr
PY
echo "progress_bar: 1 passed, 0 failed"
