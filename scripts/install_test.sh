#!/usr/bin/env bash
# Tests scripts/install.sh: installs into a temporary prefix, moves the installed tree
# (the pkg-config and CMake files must not depend on where it was installed), checks
# the SONAME, the symbols and the split debug info, runs the C API tests against the
# installed libraries, and builds and runs examples/cpp from the installed tree only:
# through pkg-config (shared and static) and through CMake. Ends with the line
# "install: N passed, M failed" that scripts/test.sh counts; exits non-zero on failure.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
passed=0
failed=0
# check NAME COMMAND...: runs COMMAND, shows its output only when it fails.
check() {
  local name=$1
  shift
  if "$@" > "$tmp/out" 2>&1; then
    passed=$((passed + 1))
    echo "ok   $name"
  else
    failed=$((failed + 1))
    echo "FAIL $name"
    sed 's/^/    /' "$tmp/out"
  fi
}
summary() {
  echo "install: $passed passed, $failed failed"
  [ "$failed" -eq 0 ]
}

start=$SECONDS
if ! bash scripts/install.sh "$tmp/installed" > "$tmp/install.log" 2>&1; then
  cat "$tmp/install.log"
  failed=1
  summary
fi
tail -n 1 "$tmp/install.log"
echo "install.sh: $((SECONDS - start)) s"
mv "$tmp/installed" "$tmp/prefix"
prefix=$tmp/prefix
lib=$prefix/lib
version=$(sed -n 's/^#define HFCAST_VERSION_STRING "\(.*\)"/\1/p' "$prefix/include/hfcast.h")
IFS=. read -r major minor _ <<<"$version"
if [ "$major" = 0 ]; then abi="0.$minor"; else abi="$major"; fi
so=$lib/libhfcast.so.$version

# ---- The shared library: SONAME, symlinks, exports, split debug info ----
soname_is() { readelf -d "$so" | grep -F "(SONAME)" | grep -qF "[libhfcast.so.$abi]"; }
check "libhfcast.so.$version has SONAME libhfcast.so.$abi" soname_is
links() {
  [ "$(readlink "$lib/libhfcast.so")" = "libhfcast.so.$abi" ] &&
    [ "$(readlink "$lib/libhfcast.so.$abi")" = "libhfcast.so.$version" ]
}
check "libhfcast.so -> libhfcast.so.$abi -> libhfcast.so.$version" links
# Defined symbols, one name a line; `nm` prints "address type name".
globals() { nm "$@" 2>/dev/null | awk 'NF == 3 { print $3 }' | sort; }
globals -D --defined-only "$so" > "$tmp/so.syms"
only_hf() { [ -s "$1" ] && ! grep -v '^hf_' "$1"; }
check "libhfcast.so exports only hf_ symbols ($(wc -l < "$tmp/so.syms"))" only_hf "$tmp/so.syms"
no_debug() { ! readelf -S -W "$1" | grep -F ' .debug_'; }
check "libhfcast.so is stripped" no_debug "$so"
debuglink() {
  readelf -p .gnu_debuglink "$so" | grep -qF "libhfcast.so.$version.debug" &&
    readelf -S -W "$lib/.debug/libhfcast.so.$version.debug" | grep -qF ' .debug_line'
}
check "its debug info is in lib/.debug/libhfcast.so.$version.debug" debuglink
# gdb follows the debuglink (and checks its CRC) to the file in lib/.debug by itself.
gdb_lines() {
  gdb -nx -batch -ex 'info line hf_version' "$so" 2>&1 | tee /dev/stderr | grep -q 'Line [0-9]* of "capi/src/'
}
check "gdb finds the source lines of libhfcast.so" gdb_lines

# ---- The static archive: only hf_ global, no debug info ----
globals -g --defined-only "$lib/libhfcast.a" > "$tmp/a.syms"
check "libhfcast.a defines only hf_ global symbols ($(wc -l < "$tmp/a.syms"))" only_hf "$tmp/a.syms"
check "libhfcast.a and libhfcast.so define the same hf_ symbols" cmp "$tmp/a.syms" "$tmp/so.syms"
check "libhfcast.a has no debug info" no_debug "$lib/libhfcast.a"
echo "sizes (KiB):"
du -k "$lib/libhfcast.a" "$so" "$lib/.debug/libhfcast.so.$version.debug"

# ---- The C API tests (plain, ASan+UBSan; the header alone against .a and .so) ----
# against the installed libraries instead of target/release.
check "C API tests against the installed libhfcast.a and libhfcast.so" \
  make -s -C c_tests HFCAST_LIB_DIR="$lib" OUT="$tmp/c_tests" test

# ---- examples/cpp from the installed tree only: a copy, outside the repository ----
cp -r examples/cpp "$tmp/src"
export PKG_CONFIG_PATH=$lib/pkgconfig
cxx=(c++ -std=c++11 -Wall -Wextra -Werror)
needs() { readelf -d "$1" | grep -F "(NEEDED)" | grep -qF "[libhfcast.so.$abi]"; }
no_repo_path() { ! grep -qF "$repo" "$1"; }
# A binary that reads libhfcast.so must not find it in target/ or elsewhere: run it
# with only the installed lib dir on the library path.
run_shared() { needs "$1" && LD_LIBRARY_PATH=$lib "$1"; }
run_static() { ! readelf -d "$1" | grep -F libhfcast && "$1"; }

build_pc_shared() {
  "${cxx[@]}" "$tmp/src/main.cpp" $(pkg-config --cflags --libs hfcast) -o "$tmp/pc_shared"
}
check "pkg-config: c++ main.cpp \$(pkg-config --cflags --libs hfcast)" build_pc_shared
check "pkg-config: the shared build runs, traces agree" run_shared "$tmp/pc_shared"
cat "$tmp/out"
build_pc_static() {
  "${cxx[@]}" "$tmp/src/main.cpp" $(pkg-config --static --cflags --libs hfcast-static) \
    -o "$tmp/pc_static"
}
check "pkg-config: c++ main.cpp \$(pkg-config --static --cflags --libs hfcast-static)" build_pc_static
check "pkg-config: the static build runs, traces agree" run_static "$tmp/pc_static"

cmake_build() {
  cmake -S "$tmp/src" -B "$tmp/build" -DCMAKE_PREFIX_PATH="$prefix" &&
    cmake --build "$tmp/build" && no_repo_path "$tmp/build/CMakeCache.txt"
}
check "CMake: find_package(hfcast 0.2 CONFIG REQUIRED), hfcast::hfcast, hfcast::hfcast_static" cmake_build
# The CMake build's rpath finds the installed library: no LD_LIBRARY_PATH.
cmake_shared() { needs "$tmp/build/hfcast_example" && "$tmp/build/hfcast_example"; }
check "CMake: the shared build runs, traces agree" cmake_shared
check "CMake: the static build runs, traces agree" run_static "$tmp/build/hfcast_example_static"
# The version file refuses an ABI this library is not.
cmake_wrong_version() {
  sed 's/find_package(hfcast 0.2 /find_package(hfcast 9.0 /' "$tmp/src/CMakeLists.txt" > "$tmp/src/v.txt"
  mkdir -p "$tmp/src9" && cp "$tmp/src/main.cpp" "$tmp/src9/" && mv "$tmp/src/v.txt" "$tmp/src9/CMakeLists.txt"
  ! cmake -S "$tmp/src9" -B "$tmp/build9" -DCMAKE_PREFIX_PATH="$prefix"
}
check "CMake: find_package(hfcast 9.0) fails" cmake_wrong_version

echo "install_test.sh: $((SECONDS - start)) s"
summary
