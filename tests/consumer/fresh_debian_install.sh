#!/usr/bin/env bash
# The Debian package on a fresh Debian 12, for real: debootstrap a minimal bookworm from this machine's
# apt mirror, `apt install ./statepack_*.deb` in it (apt fetches every dependency), then, inside it, pack
# the sample notation with the installed statepack, inspect the archive, ask pkg-config for the
# library, and build the consumer project (tests/consumer) against /usr with find_package(statepack) and
# run its application on lavapipe. Not part of the suite: it needs root, chroot and a few minutes of downloads (the suite's
# cmake.debian_package checks the package and apt's simulated install).
# Usage (as root): fresh_debian_install.sh <statepack_*.deb> <statepack source dir> [work dir]
set -euo pipefail
deb=$(realpath "$1") src=$(realpath "$2") work=${3:-/tmp/statepack-fresh-debian}
fail() { echo "FAIL: $*"; exit 1; }
[[ $(id -u) == 0 ]] || fail "run as root (debootstrap and chroot)"
command -v debootstrap >/dev/null || apt-get install -y --no-install-recommends debootstrap
mirror=$(awk '/^URIs:/ {print $2; exit}' /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)
root=$work/root
cleanup() { umount "$root/proc" 2>/dev/null || true; }
trap cleanup EXIT
if [[ ! -x $root/usr/bin/apt-get ]]; then
  rm -rf "$work" && mkdir -p "$work"
  debootstrap --variant=minbase bookworm "$root" "${mirror:-http://deb.debian.org/debian}" >"$work/debootstrap.log" 2>&1 ||
    fail "debootstrap failed: $(tail -5 "$work/debootstrap.log")"
fi
# The same suites as this machine (updates and security too), so the package's versioned Depends resolve.
[[ -f /etc/apt/sources.list.d/debian.sources ]] && cp /etc/apt/sources.list.d/debian.sources "$root/etc/apt/sources.list.d/" &&
  rm -f "$root/etc/apt/sources.list"
mountpoint -q "$root/proc" || mount -t proc proc "$root/proc"
rm -rf "$root/tmp/statepack" && mkdir -p "$root/tmp/statepack"
cp "$deb" "$root/tmp/statepack/" && cp -r "$src/states" "$src/shaders" "$src/tests/consumer" "$root/tmp/statepack/"
in_root() { chroot "$root" env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root "$@"; }
in_root apt-get update -q >"$work/apt.log" 2>&1 || fail "apt-get update: $(tail -5 "$work/apt.log")"
in_root apt-get install -y -q --no-install-recommends "/tmp/statepack/$(basename "$deb")" pkg-config \
  >>"$work/apt.log" 2>&1 || fail "apt-get install: $(tail -20 "$work/apt.log")"
echo "installed: $(in_root dpkg-query -W statepack)"
in_root statepack --version
in_root statepack pack -i /tmp/statepack/states/slice.json -s /tmp/statepack/shaders -o /tmp/statepack/slice.spk \
  --vulkan || fail "the installed statepack cannot pack the sample notation"
in_root statepack inspect /tmp/statepack/slice.spk | head -5
in_root pkg-config --cflags --libs statepack_dearchiver || fail "pkg-config does not know statepack_dearchiver"
# A user's project on the installed package: a compiler, CMake and a Vulkan driver are the user's.
in_root apt-get install -y -q --no-install-recommends g++ cmake ninja-build mesa-vulkan-drivers \
  >>"$work/apt.log" 2>&1 || fail "apt-get install of the build tools: $(tail -20 "$work/apt.log")"
in_root cmake -S /tmp/statepack/consumer -B /tmp/statepack/consumer-build -G Ninja >"$work/consumer.log" 2>&1 ||
  fail "configuring the consumer against /usr: $(tail -20 "$work/consumer.log")"
in_root cmake --build /tmp/statepack/consumer-build >>"$work/consumer.log" 2>&1 ||
  fail "building the consumer: $(tail -20 "$work/consumer.log")"
out=$(in_root /tmp/statepack/consumer-build/consumer_app /tmp/statepack/consumer-build/consumer.spk 2>&1) ||
  fail "consumer_app: $out"
grep -q "unpacked 'Consumer PSO'" <<<"$out" || fail "consumer_app: $out"
echo "consumer project: $out"
echo "fresh Debian 12: the package installs with apt, its packager works, and a project builds against it"
