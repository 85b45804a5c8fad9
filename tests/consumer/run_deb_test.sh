#!/usr/bin/env bash
# `cpack -G DEB` as the README says: the package holds the packager, the library, its headers and the
# CMake and pkg-config files under /usr, depends on what they need at run and build time, apt accepts
# it here (a simulated install: dependency names and versions resolve against Debian's), and its
# stripped packager runs.
# Usage: run_deb_test.sh <statepack build dir> <its configuration> <work dir>
set -euo pipefail
build_dir=$1 config=$2 work=$3
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work"

(cd "$build_dir" && cpack -G DEB -C "$config" -B "$work") >"$work/cpack.log" 2>&1 ||
  fail "cpack failed: $(cat "$work/cpack.log")"
deb=$(find "$work" -maxdepth 1 -name 'statepack_*.deb')
[[ -n "$deb" ]] || fail "no statepack_*.deb: $(cat "$work/cpack.log")"

contents=$(dpkg-deb -c "$deb" | awk '{print $NF}')
for f in ./usr/bin/statepack ./usr/include/statepack/dearchiver.hpp ./usr/include/statepack/result.hpp \
  ./usr/lib/libstatepack_dearchiver.a ./usr/lib/cmake/statepack/statepackConfig.cmake \
  ./usr/lib/cmake/statepack/StatepackAddArchive.cmake ./usr/lib/pkgconfig/statepack_dearchiver.pc \
  ./usr/lib/pkgconfig/statepack_gl.pc; do
  grep -qx "$f" <<<"$contents" || fail "the package lacks $f: $contents"
done
depends=$(dpkg-deb -f "$deb" Depends)
for d in libvulkan1 libspirv-cross-c-shared0 libstdc++6 libvulkan-dev libxxhash-dev; do
  [[ "$depends" == *"$d"* ]] || fail "Depends lacks $d: $depends"
done

out=$(apt-get install --simulate --no-install-recommends "$deb" 2>&1) || fail "apt refuses the package: $out"
grep -q "^Inst statepack" <<<"$out" || fail "apt would not install statepack: $out"

dpkg-deb -x "$deb" "$work/root"
version=$("$work/root/usr/bin/statepack" --version) || fail "the packaged statepack does not run"
echo "$(basename "$deb") ($(stat -c %s "$deb") bytes): $version; Depends: $depends"
echo "debian package: all checks passed"
