#!/usr/bin/env bash
# The projects the documentation shows, built from the documentation's own text and run, so that what
# an application must link is said where it links and cannot rot: every ```cmake block that follows a
# "<!-- consumer project" comment in README.md and docs/cmake.md, in each of the three ways in:
#   - against the installed package (find_package(statepack <major.minor>)), with Ninja;
#   - with statepack as a subdirectory (the block that says add_subdirectory(statepack)): the dearchiver
#     alone is built (STATEPACK_BUILD_PACKAGER=OFF keeps it short) and statepack_add_archive runs this
#     build's packager from PATH;
#   - with the pkg-config command the README gives.
# Each application is tests/consumer/app.cpp as main.cpp: it calls Vulkan itself (so it must link the
# loader) and unpacks the archive its project packed, under the validation layer.
# Usage: run_doc_projects_test.sh <statepack build dir> <its configuration> <source root> <work dir> <C++ compiler>
set -euo pipefail
build_dir=$1 config=$2 root=$3 work=$4 cxx=$5
here=$(cd "$(dirname "$0")" && pwd)
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work"

# The n-th block after a "<!-- consumer project" comment of a Markdown file.
doc_block() {  # <file> <n>
  awk -v n="$2" '/^<!-- consumer project/ { m++; next }
                 m == n && !inside && /^```cmake/ { inside = 1; next }
                 inside && /^```/ { exit }
                 inside { print }' "$1"
}
# A project directory with the files the blocks name: the notation under states/ and assets/, shaders/,
# and main.cpp.
project_dir() {  # <dir> <CMakeLists.txt text>
  mkdir -p "$1/states" "$1/assets"
  cp "$here/states.json" "$1/states/my_states.json"
  cp "$here/states.json" "$1/assets/RenderStates.json"
  cp -r "$here/shaders" "$1/shaders"
  cp "$here/app.cpp" "$1/main.cpp"
  if ! grep -q '^cmake_minimum_required' <<<"$2"; then  # the README shows the lines a project adds
    printf 'cmake_minimum_required(VERSION 3.25)\nproject(app CXX)\n%s\n' "$2" >"$1/CMakeLists.txt"
  else
    printf '%s\n' "$2" >"$1/CMakeLists.txt"
  fi
}
# shellcheck source=validation.sh
source "$here/validation.sh"  # validated, no_validation_messages
run_app() {  # <label> <executable> <archive>
  local out
  out=$(validated "$2" "$3") || fail "$1: the application failed: $out"
  grep -q "unpacked 'Consumer PSO'" <<<"$out" || fail "$1: $out"
  no_validation_messages "$1" "$out"
  echo "$1: $out"
}

readme_block=$(doc_block "$root/README.md" 1)
complete_block=$(doc_block "$root/docs/cmake.md" 1)
subdirectory_block=$(doc_block "$root/docs/cmake.md" 2)
for b in readme_block complete_block subdirectory_block; do
  grep -q 'statepack::dearchiver' <<<"${!b}" || fail "$b: no marked cmake block that links statepack::dearchiver"
done
grep -q '^add_subdirectory(statepack)' <<<"$subdirectory_block" || fail "docs/cmake.md's second block is not the subdirectory one"

# The version the docs ask for is this release's major.minor, and a different minor is refused (0.x).
version=$("$build_dir/bin/statepack" --version | awk '{ print $2 }')
major_minor=${version%.*}
for b in readme_block complete_block; do
  grep -qF "find_package(statepack $major_minor CONFIG REQUIRED)" <<<"${!b}" ||
    fail "$b does not ask for statepack $major_minor (statepack --version says $version)"
done

cmake --install "$build_dir" --config "$config" --prefix "$work/prefix" >"$work/install.log" ||
  fail "cmake --install failed: $(cat "$work/install.log")"
prefix=$work/prefix

# 1. Installed package: the README's lines and cmake.md's complete project.
export PATH=/usr/bin:/bin  # no statepack on PATH: the installed function runs the installed packager
project_dir "$work/readme" "$readme_block"
cmake -S "$work/readme" -B "$work/readme/build" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" >"$work/readme.log" 2>&1 ||
  fail "README project: configure failed: $(cat "$work/readme.log")"
out=$(cmake --build "$work/readme/build" 2>&1) || fail "README project: build failed: $out"
run_app "README project (installed package)" "$work/readme/build/app" "$work/readme/build/my_states.spk"

project_dir "$work/complete" "$complete_block"
cmake -S "$work/complete" -B "$work/complete/build" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" >"$work/complete.log" 2>&1 ||
  fail "cmake.md's complete project: configure failed: $(cat "$work/complete.log")"
out=$(cmake --build "$work/complete/build" 2>&1) || fail "cmake.md's complete project: build failed: $out"
grep -q "objects ok" <<<"$out" || fail "cmake.md's complete project: VERIFY did not run: $out"
run_app "cmake.md's complete project (installed package)" "$work/complete/build/my_renderer" \
  "$work/complete/build/my_states.spk"

# Another minor version is a different API under 0.x: find_package refuses it, naming the version.
wrong="0.$((${major_minor#*.} + 1))"
project_dir "$work/other_minor" "${readme_block/find_package(statepack $major_minor/find_package(statepack $wrong}"
if cmake -S "$work/other_minor" -B "$work/other_minor/build" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" \
  >"$work/other_minor.log" 2>&1; then
  fail "find_package(statepack $wrong) accepted statepack $version"
fi
grep -q "$version" "$work/other_minor.log" || fail "the refusal does not name the version: $(cat "$work/other_minor.log")"
echo "find_package(statepack $wrong) refused: statepack $version is installed"

# 2. As a subdirectory: the same kind of lines, statepack beside them.
project_dir "$work/sub" "$subdirectory_block"
ln -s "$root" "$work/sub/statepack"
PATH="$build_dir/bin:$PATH" cmake -S "$work/sub" -B "$work/sub/build" -G Ninja -DCMAKE_BUILD_TYPE=Debug \
  -DSTATEPACK_BUILD_PACKAGER=OFF -DSTATEPACK_BUILD_GL=OFF >"$work/sub.log" 2>&1 ||
  fail "subdirectory project: configure failed: $(cat "$work/sub.log")"
out=$(PATH="$build_dir/bin:$PATH" cmake --build "$work/sub/build" 2>&1) || fail "subdirectory project: build failed: $out"
run_app "subdirectory project" "$work/sub/build/app" "$work/sub/build/my_states.spk"

# 3. pkg-config, with the command the README gives.
command=$(grep -o 'pkg-config --cflags --libs statepack_dearchiver[a-z_ ]*' "$root/README.md" | head -1)
[[ "$command" == *" vulkan" ]] || fail "the README's pkg-config command does not ask for the loader: '$command'"
libdir=$(dirname "$(dirname "$(find "$prefix" -name statepack_dearchiver.pc)")")
# shellcheck disable=SC2086 # the command and the flags are words
flags=$(PKG_CONFIG_PATH="$libdir/pkgconfig" $command) || fail "'$command' failed"
# shellcheck disable=SC2086
"$cxx" -std=c++20 "$here/app.cpp" -o "$work/pkg-config-app" $flags || fail "'$command' gave flags that do not link: $flags"
run_app "pkg-config ($command)" "$work/pkg-config-app" "$work/readme/build/my_states.spk"
[[ "$(PKG_CONFIG_PATH="$libdir/pkgconfig" pkg-config --modversion statepack_dearchiver)" == "$version" ]] ||
  fail "pkg-config's version is not $version"

echo "documented projects: all checks passed"
