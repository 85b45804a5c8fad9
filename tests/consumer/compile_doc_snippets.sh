#!/usr/bin/env bash
# Compiles every ```cpp block of README.md and docs/*.md against the installed headers only (the
# dearchiver's and the bootstrap library's: what an application sees), with -std=c++20 -Wall -Wextra
# -Werror, so that the documented code cannot rot: a renamed call, a [[nodiscard]] result ignored or a
# missing include fails the test.
#
# How a block is compiled (the conventions for whoever writes one):
#   - A block whose first line is `#include ...` is a whole source file, compiled as written.
#   - Any other block is a fragment: it becomes the body of `int snippet(PARAMETERS) { ... return 0; }`,
#     after `#include <statepack/dearchiver.hpp>` and `#include <cstdio>`. PARAMETERS are the variables
#     the fragment takes as given, written in an HTML comment (GitHub does not render it) on the line
#     right before the opening fence:
#         <!-- snippet: statepack::Dearchiver* dearchiver, VkFormat swapchain_format -->
#     Without that line the function has no parameters.
#   - A block whose first line is `// not compiled: <reason>` is skipped, and the reason is printed.
# Errors point at the Markdown file and line (#line directives).
#
# Usage: compile_doc_snippets.sh <source root> <C++ compiler> <work dir>
set -euo pipefail
root=$1 cxx=$2 work=$3
include_dir="$root/dearchiver/include"
rm -rf "$work" && mkdir -p "$work"

compiled=0 skipped=0 failed=0
for doc in "$root/README.md" "$root"/docs/*.md; do
  rel=${doc#"$root/"}
  inside=0 number=0 line_no=0 context="" pending="" start=0 body=""
  while IFS= read -r line || [[ -n "$line" ]]; do
    line_no=$((line_no + 1))
    if ((inside == 0)); then
      if [[ "$line" =~ ^'```cpp'[[:space:]]*$ ]]; then
        inside=1 number=$((number + 1)) start=$((line_no + 1)) body="" context=$pending
      elif [[ "$line" =~ ^'<!-- snippet: '(.*)' -->'$ ]]; then
        pending=${BASH_REMATCH[1]}
        continue
      fi
      pending=""
      continue
    fi
    if [[ "$line" =~ ^'```'[[:space:]]*$ ]]; then
      inside=0
      name="$(echo "$rel" | tr '/.' '__')_$number"
      first=${body%%$'\n'*}
      if [[ "$first" =~ ^'// not compiled: '(.*)$ ]]; then
        echo "skipped $rel:$start: ${BASH_REMATCH[1]}"
        skipped=$((skipped + 1))
        continue
      fi
      file="$work/$name.cpp"
      if [[ "$first" == "#include"* ]]; then
        printf '#line %d "%s"\n%s' "$start" "$rel" "$body" >"$file"
      else
        printf '#include <statepack/dearchiver.hpp>\n#include <cstdio>\nint snippet(%s) {\n#line %d "%s"\n%sreturn 0;\n}\n' \
          "$context" "$start" "$rel" "$body" >"$file"
      fi
      if "$cxx" -std=c++20 -Wall -Wextra -Werror -O1 -I"$include_dir" -I"$root/dearchiver/bootstrap/include" -c "$file" -o "$work/$name.o" 2>"$work/$name.log"; then
        compiled=$((compiled + 1))
      else
        echo "FAIL: the C++ block at $rel:$start does not compile:"
        cat "$work/$name.log"
        failed=$((failed + 1))
      fi
      continue
    fi
    body+="$line"$'\n'
  done <"$doc"
  ((inside == 0)) || { echo "FAIL: $rel: a \`\`\`cpp block is not closed"; failed=$((failed + 1)); }
done

echo "documentation snippets: $compiled compiled, $skipped skipped, $failed failed"
((failed == 0 && compiled > 0))
