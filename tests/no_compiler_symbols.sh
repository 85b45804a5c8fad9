#!/usr/bin/env bash
# The dearchiver and programs that link only it contain no shader compiler: no glslang, SPIRV-Tools
# or spirv-cross symbol. The packager, which does link them, is the control that the check can fail.
# Usage: no_compiler_symbols.sh <packager executable> <dearchiver library or program>...
set -euo pipefail
pattern='glslang::|spvtools::|spirv_cross::|spvc_|TShader|GlslangToSpv'
control=$1; shift
count=$(nm -C "$control" | grep -cE "$pattern" || true)
[[ $count -gt 0 ]] || { echo "FAIL: the control $control shows no compiler symbols; the check is broken"; exit 1; }
for binary in "$@"; do
  found=$(nm -C "$binary" 2>/dev/null | grep -E "$pattern" | head -3 || true)
  if [[ -n "$found" ]]; then echo "FAIL: $binary contains compiler symbols:"; echo "$found"; exit 1; fi
  echo "ok: $binary ($(stat -c %s "$binary") bytes) has no compiler symbols"
done
echo "no compiler symbols (control: $count in $(basename "$control"))"
