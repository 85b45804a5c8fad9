#!/usr/bin/env bash
# Each public header compiles on its own, and pulls in no GL header: statepack/gl_dearchiver.hpp names
# GL's types itself, so an application picks its own GL loader (epoxy, glad, GL/gl.h). The -H list of
# every header a translation unit opens is checked; <vulkan/...> is the one third-party include.
# The installed bootstrap library's headers (statepack/bootstrap/) are held to the same warnings, so a
# program that includes them builds under -Wall -Wextra -Werror too; they may include GL (gl_context).
# Usage: headers_stand_alone.sh <include dir> <C++ compiler> <work dir> <bootstrap include dir>
set -euo pipefail
include_dir=$1 cxx=$2 work=$3 bootstrap_dir=$4
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work"
for header in "$include_dir"/statepack/*.hpp; do
  name=statepack/$(basename "$header")
  printf '#include <%s>\n' "$name" > "$work/one.cpp"
  opened=$("$cxx" -std=c++20 -Wall -Wextra -Werror -fsyntax-only -H -I "$include_dir" "$work/one.cpp" 2>&1) ||
    fail "$name does not compile on its own: $opened"
  grep -q "vulkan_core.h\|result.hpp\|export.hpp" <<<"$opened" || fail "-H listed nothing for $name, so the check proves nothing: $opened"
  found=$(grep -E '/(epoxy|GL|GLES[0-9]*|EGL|glad)/' <<<"$opened" || true)
  [[ -z "$found" ]] || fail "$name includes a GL header: $found"
  echo "ok: $name"
done
# The types are GL's own: code that includes a GL header too passes values both ways.
cat > "$work/both.cpp" <<'EOF2'
#include <epoxy/gl.h>
#include <statepack/gl_dearchiver.hpp>
#include <type_traits>
static_assert(std::is_same_v<GLuint, statepack::gl::GLuint> && std::is_same_v<GLenum, statepack::gl::GLenum>);
int main() { statepack::gl::FixedFunctionState s; GLenum mode = s.primitive_mode; return mode == GL_TRIANGLES ? 0 : 1; }
EOF2
"$cxx" -std=c++20 -Wall -Wextra -Werror -fsyntax-only -I "$include_dir" "$work/both.cpp" || fail "with <epoxy/gl.h> too"
bootstrap_headers=("$bootstrap_dir"/statepack/bootstrap/*.hpp)
((${#bootstrap_headers[@]} >= 3)) || fail "no bootstrap headers under $bootstrap_dir"
for header in "${bootstrap_headers[@]}"; do
  name=statepack/bootstrap/$(basename "$header")
  printf '#include <%s>\n' "$name" > "$work/one.cpp"
  out=$("$cxx" -std=c++20 -Wall -Wextra -Werror -fsyntax-only -I "$include_dir" -I "$bootstrap_dir" "$work/one.cpp" 2>&1) ||
    fail "$name does not compile on its own under -Wall -Wextra -Werror: $out"
  echo "ok: $name"
done
echo "public headers: all checks passed"
