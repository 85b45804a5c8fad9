#!/usr/bin/env bash
# Packs every valid notation the project ships or documents and verifies each archive on lavapipe with
# the validation layer on: the rule "anything statepack pack accepts, the dearchiver creates with zero
# validation messages", checked on every example a user could copy.
# Usage: verify_examples.sh <statepack> <work dir> <source dir>
set -euo pipefail
statepack=$1 work=$2 src=$3
rm -rf "$work" && mkdir -p "$work/docs"
count=0
pack_and_verify() {  # <notation> <shader dir> <name>
  "$statepack" pack -i "$1" -s "$2" -o "$work/$3.spk" --vulkan >"$work/$3.log" 2>&1 || {
    cat "$work/$3.log"; echo "FAILED to pack $1"; exit 1; }
  "$statepack" verify "$work/$3.spk" >"$work/$3.verify" 2>&1 || {
    cat "$work/$3.verify"; echo "FAILED to verify $1"; exit 1; }
  count=$((count + 1))
}
for f in "$src"/tests/corpus/valid/*.json; do pack_and_verify "$f" "$src/tests/corpus/shaders" "corpus-$(basename "$f" .json)"; done
for f in "$src"/states/*.json; do pack_and_verify "$f" "$src/shaders" "states-$(basename "$f" .json)"; done
# Every ```json block of docs/notation.md that is a whole document (starts with "{") is an example.
awk -v dir="$work/docs" '/^```json/ { n++; file = dir "/example" n ".json"; inside = 1; next }
     /^```/ { inside = 0; next } inside { print > file }' "$src/docs/notation.md"
for f in "$work"/docs/example*.json; do
  [[ -e "$f" ]] || continue
  pack_and_verify "$f" "$src/tests/corpus/shaders" "doc-$(basename "$f" .json)"
done
[[ $count -ge 10 ]] || { echo "only $count notations found"; exit 1; }
echo "all $count verified"
