#!/usr/bin/env bash
# Installs the C library of hfcast under a prefix, the way C and C++ programs expect:
#   bash scripts/install.sh PREFIX
#
#   PREFIX/include/hfcast.h
#   PREFIX/lib/libhfcast.so.VERSION            SONAME libhfcast.so.ABI, stripped
#   PREFIX/lib/libhfcast.so.ABI, libhfcast.so  the usual symlinks
#   PREFIX/lib/libhfcast.a                     only the hf_ symbols global, no debug info
#   PREFIX/lib/.debug/libhfcast.so.VERSION.debug  debug info of the .so: gdb finds it by
#                                              the .so's .gnu_debuglink without setup
#   PREFIX/lib/pkgconfig/hfcast.pc, hfcast-static.pc
#   PREFIX/lib/cmake/hfcast/hfcastConfig.cmake, hfcastConfigVersion.cmake
#
# ABI is the part of the version that changes on a breaking release: the major, or for
# 0.y versions (Cargo's semver) "0.y". The pkg-config and CMake files locate the prefix
# from their own place, so the installed tree can be moved. Templates: capi/pkg/.
set -euo pipefail
cd "$(dirname "$0")/.."

if [ $# -ne 1 ]; then
  echo "usage: bash scripts/install.sh PREFIX" >&2
  exit 2
fi
mkdir -p "$1"
prefix=$(cd "$1" && pwd)

# The crate version is the library's (hf_version returns it); the committed header
# must carry the same, or programs would be compiled against another version.
version=$(sed -n '/^\[workspace.package\]/,/^\[/s/^version = "\(.*\)"/\1/p' Cargo.toml)
header_version=$(sed -n 's/^#define HFCAST_VERSION_STRING "\(.*\)"/\1/p' include/hfcast.h)
if [ -z "$version" ] || [ "$version" != "$header_version" ]; then
  echo "install: Cargo.toml version '$version' != include/hfcast.h '$header_version'" >&2
  exit 1
fi
IFS=. read -r major minor _ <<<"$version"
if [ "$major" = 0 ]; then abi="0.$minor"; else abi="$major"; fi
soname="libhfcast.so.$abi"

# A target dir of its own: the SONAME is linked into this build only. In target/release
# it would make the C tests, which run target/release/libhfcast.so through -lhfcast,
# look for libhfcast.so.$abi, and the next plain cargo build would relink. One cargo
# call builds both crate types (the link argument only reaches the cdylib's link) and
# prints the system libraries the static archive needs; cargo replays that note when
# the build is already fresh.
target=target/install
mkdir -p "$target"
echo "== install: cargo rustc --release -p hfcast-capi (SONAME $soname) in $target" >&2
CARGO_TARGET_DIR=$target cargo rustc --release -p hfcast-capi -- \
  -C link-arg=-Wl,-soname,"$soname" --print native-static-libs 2>&1 | tee "$target/build.log" >&2
native_libs=$(sed -n 's/^note: native-static-libs: //p' "$target/build.log" | tail -n 1)
if [ -z "$native_libs" ]; then
  echo "install: rustc printed no native-static-libs (see $target/build.log)" >&2
  exit 1
fi
built=$target/release
stage=$target/stage
rm -rf "$stage"
mkdir -p "$stage"

# Static archive: every object of the staticlib (hfcast, the Rust standard library,
# compiler builtins) linked into one relocatable object, in which every symbol but the
# hf_ ones becomes local, so nothing else can clash with another library's symbols.
# The embedded LLVM bitcode goes: it is not needed to link, and a bfd plugin of
# another LLVM version (LLVMgold) aborts on it when nm or ld open the object.
ld -r --whole-archive "$built/libhfcast.a" -o "$stage/hfcast.o"
objcopy --wildcard --keep-global-symbol='hf_*' --strip-debug \
  --remove-section=.llvmbc --remove-section=.llvmcmd --remove-section=.llvm_addrsig \
  "$stage/hfcast.o"
ar rcs "$stage/libhfcast.a" "$stage/hfcast.o"

# Shared library: stripped, its debug info in a separate file that the debuglink names.
so=libhfcast.so.$version
cp "$built/libhfcast.so" "$stage/$so"
objcopy --only-keep-debug "$stage/$so" "$stage/$so.debug"
objcopy --strip-debug --strip-unneeded --add-gnu-debuglink="$stage/$so.debug" "$stage/$so"

# pkg-config and CMake files from the templates.
cmake_native_libs=$(for l in $native_libs; do echo "${l#-l}"; done | paste -sd ';')
pointer_bytes=$(( $(rustc --print cfg | sed -n 's/^target_pointer_width="\(.*\)"/\1/p') / 8 ))
render() {
  sed -e "s|@VERSION@|$version|g" -e "s|@ABI@|$abi|g" -e "s|@NATIVE_LIBS@|$native_libs|g" \
    -e "s|@CMAKE_NATIVE_LIBS@|$cmake_native_libs|g" -e "s|@POINTER_BYTES@|$pointer_bytes|g" \
    "capi/pkg/$1.in" > "$stage/$1"
}
for f in hfcast.pc hfcast-static.pc hfcastConfig.cmake hfcastConfigVersion.cmake; do
  render "$f"
done

lib=$prefix/lib
install -d "$prefix/include" "$lib/.debug" "$lib/pkgconfig" "$lib/cmake/hfcast"
install -m 644 include/hfcast.h "$prefix/include/"
install -m 755 "$stage/$so" "$lib/"
ln -sfn "$so" "$lib/$soname"
ln -sfn "$soname" "$lib/libhfcast.so"
install -m 644 "$stage/libhfcast.a" "$lib/"
install -m 644 "$stage/$so.debug" "$lib/.debug/"
install -m 644 "$stage/hfcast.pc" "$stage/hfcast-static.pc" "$lib/pkgconfig/"
install -m 644 "$stage/hfcastConfig.cmake" "$stage/hfcastConfigVersion.cmake" "$lib/cmake/hfcast/"

size() { du -k "$1" | cut -f1; }
echo "installed hfcast $version in $prefix: $so $(size "$lib/$so") KiB (SONAME $soname)," \
  "libhfcast.a $(size "$lib/libhfcast.a") KiB, .debug/$so.debug $(size "$lib/.debug/$so.debug") KiB" >&2
