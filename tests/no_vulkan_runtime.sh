#!/usr/bin/env bash
# The packager's library reads and writes archives through the internal format library, without the
# Vulkan runtime: a program built on it alone needs no libvulkan. `statepack` itself, whose `verify`
# creates a device, is the control that the check can fail.
# Usage: no_vulkan_runtime.sh <statepack executable> <program linking only the packager library>...
set -euo pipefail
needs_vulkan() { readelf -d "$1" | grep -E 'NEEDED.*libvulkan' || true; }
control=$1; shift
[[ -n "$(needs_vulkan "$control")" ]] || { echo "FAIL: the control $control does not need libvulkan; the check is broken"; exit 1; }
for binary in "$@"; do
  found=$(needs_vulkan "$binary")
  if [[ -n "$found" ]]; then echo "FAIL: $binary needs the Vulkan loader: $found"; exit 1; fi
  if nm -C "$binary" | grep -qE ' [TtWw] statepack::Dearchiver::'; then echo "FAIL: $binary contains the Dearchiver"; exit 1; fi
  echo "ok: $binary needs no Vulkan runtime"
done
echo "packager library without the Vulkan runtime (control: $(basename "$control"))"
