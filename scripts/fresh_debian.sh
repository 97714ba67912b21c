#!/usr/bin/env bash
# Checks the README's two commands on a fresh Debian 12: a minimal Debian 12 root made with
# debootstrap (--variant=minbase: no Python, no compiler, nothing of rtusim's), a clone of this
# repository's HEAD in it with ../shared beside it (read-only), then, as root in a chroot,
#   1. bash scripts/setup.sh && build/rtusim run configs/default.toml --out out/default
#   2. bash scripts/test.sh
# and, with --ci, .ci/run as well. Logs and times go to ROOTDIR/root/*.log; exit 0 only if every
# command passed. Needs root, debootstrap and the network for Debian's and PyPI's packages; no
# test calls it (it takes 10-20 minutes on 2 cores).
# Usage: scripts/fresh_debian.sh ROOTDIR [--ci]     (ROOTDIR must not exist; removed only by hand)
set -euo pipefail
cd "$(dirname "$0")/.."
root=${1:?usage: scripts/fresh_debian.sh ROOTDIR [--ci]}
ci=${2:-}
[ "$(id -u)" -eq 0 ] || { echo "fresh_debian: run as root (chroot, mounts)" >&2; exit 2; }
[ -e "$root" ] && { echo "fresh_debian: $root exists; give a new directory" >&2; exit 2; }
command -v debootstrap > /dev/null ||
  { echo "fresh_debian: needs debootstrap (apt-get install debootstrap)" >&2; exit 2; }
shared=$(cd .. && pwd)/shared
[ -d "$shared" ] || { echo "fresh_debian: no $shared (the scenes)" >&2; exit 2; }

debootstrap --variant=minbase bookworm "$root" http://deb.debian.org/debian \
  > "$root.debootstrap.log" 2>&1 ||
  { echo "fresh_debian: debootstrap failed: see $root.debootstrap.log" >&2; exit 1; }
mounts=()
cleanup() {
  for ((i = ${#mounts[@]} - 1; i >= 0; i--)); do umount -l "${mounts[$i]}" || true; done
}
trap cleanup EXIT
mount -t proc proc "$root/proc"; mounts+=("$root/proc")  # set -e: a failed mount stops here
mount --rbind /dev "$root/dev"; mounts+=("$root/dev")
mkdir -p "$root/root/shared"
mount --bind -o ro "$shared" "$root/root/shared"; mounts+=("$root/root/shared")
cp /etc/resolv.conf "$root/etc/resolv.conf"
# A proxy's own certificate authority, where this host trusts one (not Debian's default).
if compgen -G "/usr/local/share/ca-certificates/*.crt" > /dev/null; then
  mkdir -p "$root/usr/local/share/ca-certificates"
  cp /usr/local/share/ca-certificates/*.crt "$root/usr/local/share/ca-certificates/"
  [ -f /etc/pip.conf ] && cp /etc/pip.conf "$root/etc/pip.conf"
fi
git clone -q . "$root/root/rtusim"

steps=("bash scripts/setup.sh && build/rtusim run configs/default.toml --out out/default"
       "bash scripts/test.sh")
[ "$ci" = --ci ] && steps+=("bash .ci/run")
rc=0
for i in "${!steps[@]}"; do
  log="$root/root/step$((i + 1)).log"
  start=$(date +%s)
  # (Debian's ca-certificates, which setup.sh's apt-get brings, adds the authority copied above.)
  if chroot "$root" env -i HOME=/root PATH=/usr/sbin:/usr/bin:/sbin:/bin \
       bash -c "cd /root/rtusim && ${steps[$i]}" > "$log" 2>&1; then
    echo "fresh_debian: ok   ($(( $(date +%s) - start )) s) ${steps[$i]}"
  else
    echo "fresh_debian: FAIL ($(( $(date +%s) - start )) s) ${steps[$i]}: see $log"
    rc=1
    break
  fi
done
exit $rc
