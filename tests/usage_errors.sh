#!/bin/bash
# Usage errors exit 2 in every program of the project, with a message that names what is wrong; --help
# exits 0. A negative count, size, index or version is a usage error, never a silent default or a
# two's-complement limit. Arguments: NAME=PATH for each program built (statepack is required).
set -u
declare -A bin
for arg in "$@"; do bin[${arg%%=*}]=${arg#*=}; done
[ -n "${bin[statepack]:-}" ] || { echo "usage: $0 statepack=PATH [path_tracer=PATH ...]"; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo '{}' >"$work/empty.json"
failures=0
checked=0

expect() {  # <program> <expected exit> <text the output must contain> <args...>
  local program=$1 want=$2 text=$3
  shift 3
  [ -n "${bin[$program]:-}" ] || return 0
  local out rc
  out=$(cd "$work" && timeout 60 "${bin[$program]}" "$@" 2>&1)
  rc=$?
  checked=$((checked + 1))
  if [ "$rc" != "$want" ] || ! grep -qF -- "$text" <<<"$out"; then
    echo "FAIL: $program $*: exit $rc (want $want), output lacks '$text':"
    echo "$out" | head -5
    failures=$((failures + 1))
  fi
}

pack=(pack -i empty.json -o out.spk --vulkan)
expect statepack 2 "--max-errors: must not be negative" "${pack[@]}" --max-errors -1
expect statepack 2 "--thread: must not be negative" "${pack[@]}" -t -1
expect statepack 2 "--content_version: must not be negative" "${pack[@]}" -v -1
expect statepack 2 "--max-input-size: must not be negative" "${pack[@]}" --max-input-size -1
expect statepack 2 "--cache-max-size: must not be negative" "${pack[@]}" --cache-max-size -1K
expect statepack 2 "--cache-max-size: must not be negative" "${pack[@]}" --cache-max-size " -5"
expect statepack 0 "" "${pack[@]}" --max-errors 0 -t 1 -v 3 --cache-max-size 1M
expect statepack 2 "--device: must not be negative" verify out.spk --device -1
expect statepack 2 "--timeout: must not be negative" verify out.spk --timeout -1
expect statepack 2 "--content_version: must not be negative" merge -o merged.spk out.spk -v -1
expect statepack 2 "--max-size: must not be negative" cache prune --max-size -1 "$work"
expect statepack 2 "The following argument was not expected: --bogus" "${pack[@]}" --bogus
expect statepack 2 "--watch repacks the archive at -o" "${pack[@]}" --watch --check
expect statepack 2 "--watch needs -o" pack -i empty.json --vulkan --watch
expect statepack 2 "--watch-quiet-ms: must not be negative" "${pack[@]}" --watch --watch-quiet-ms -1
expect statepack 2 "--watch-quiet-ms is for --watch" "${pack[@]}" --watch-quiet-ms 10
expect statepack 0 "--watch" pack --help
expect statepack 0 "Exit codes" --help

expect path_tracer 2 "--frames" --frames -1
expect path_tracer 2 "--seed" --seed -1
expect path_tracer 2 "--spp" --headless --spp 0
expect path_tracer 2 "--bogus" --bogus
expect path_tracer 0 "--headless" --help
expect accuracy_report 2 "--seeds" --seeds 0
expect accuracy_report 2 "--width" --width -1
expect accuracy_report 2 "--timing-rounds" --timing-rounds -1
expect accuracy_report 0 "--reference-spp" --help
expect unpack_demo 2 "unexpected argument '--bogus'" --bogus
expect unpack_demo 2 "unexpected argument 'second.spk'" out.spk second.spk
expect unpack_demo 0 "usage: unpack_demo" --help
expect gl_demo 2 "unexpected argument '-1'" -1
expect gl_demo 2 "unexpected argument 'second.spk'" out.spk second.spk
expect load_benchmark 2 "repeats must be a number from 1, not '-1'" out.spk empty.json . -1
expect load_benchmark 2 "unexpected argument 'more'" out.spk empty.json . 3 more
expect gl_load_benchmark 2 "repeats must be a number from 1, not '2x'" out.spk 2x a=b.comp
expect min_dearchiver 2 "usage: min_dearchiver" out.spk one two
expect min_glslang 2 "usage: min_glslang" a.comp b.comp

# What was typed reaches the terminal escaped, in the parser's own messages too.
esc=$'\e[31m'
expect statepack 2 '--bogus\x1b[31m' "${pack[@]}" "--bogus$esc"
expect statepack 2 'not -1\x1b[31m' "${pack[@]}" -t "-1$esc"
expect path_tracer 2 '--bogus\x1b[31m' "--bogus$esc"
expect accuracy_report 2 '--bogus\x1b[31m' "--bogus$esc"
for program in statepack path_tracer accuracy_report; do
  [ -n "${bin[$program]:-}" ] || continue
  checked=$((checked + 1))
  if (cd "$work" && "${bin[$program]}" "--bogus$esc" 2>&1) | grep -q $'\e'; then
    echo "FAIL: $program prints a raw escape character"
    failures=$((failures + 1))
  fi
done

# An output over an input is refused before any work, whatever the program (exit 2).
echo '{}' >"$work/scene.json"
ln "$work/scene.json" "$work/hard.md"
expect accuracy_report 2 "it is the input" --scene scene.json --doc scene.json
expect accuracy_report 2 "it is the input" --scene scene.json --doc hard.md
expect statepack 2 "it is the input" verify out.spk --variants scene.json --cache hard.md

if [ "$failures" -ne 0 ]; then
  echo "$failures of $checked usage checks failed"
  exit 1
fi
echo "all $checked usage checks passed"
