#!/usr/bin/env bash
# Runs every test of hfcast on a fresh Debian machine: installs what is missing, then
# formatting, lints, docs, the workspace tests, and the no_std build of the core.
set -euo pipefail
cd "$(dirname "$0")/.."

# System packages the tests need (none yet beyond the Rust toolchain and a C compiler;
# the C API and OpenGL issues add theirs here).
APT_PACKAGES=()
# C API, C tests, GLSL validation and the OpenGL renderers (issue 6): a C/C++ compiler,
# OSMesa (GL 4.5 core offscreen), GLFW + Xvfb (window test), glslangValidator,
# valgrind, libpng (the renderers read the PNG maps and write images).
APT_PACKAGES+=(gcc g++ make libosmesa6-dev libglfw3-dev xvfb xauth glslang-tools valgrind libpng-dev)
# WGSL ports executed through wgpu on lavapipe, the software Vulkan driver (issue 8).
APT_PACKAGES+=(mesa-vulkan-drivers libvulkan1)
# Embree, the independent oracle of the exact marches (c_tests/embree_bench.c --check).
APT_PACKAGES+=(libembree-dev)
# Installing the C library (issue 24): CMake and pkg-config build the C++ example
# against the installed tree; gdb reads the .so's separate debug info.
APT_PACKAGES+=(cmake pkg-config gdb binutils)
# Coverage-guided fuzzing of the C API (issue 26; scripts/fuzz.sh): clang and libFuzzer.
APT_PACKAGES+=(clang libclang-rt-14-dev)
missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "== installing ${missing[*]}"
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}"
fi
# A real GeoTIFF DEM for tools/tests/world_maps.rs: elev.tif (Luxembourg, 95 x 90, int16 with
# nodata) of Debian's r-cran-terra 1.7-3 (GPL-3+), taken from the package without installing R.
GEOTIFF=target/testdata/terra_elev.tif
if [ ! -f "$GEOTIFF" ]; then
  echo "== fetching $GEOTIFF (Debian r-cran-terra)"
  tmp=$(mktemp -d)
  (cd "$tmp" && { apt-get download -qq r-cran-terra 2>/dev/null || { apt-get update -qq && apt-get download -qq r-cran-terra; }; })
  dpkg -x "$tmp"/r-cran-terra_*.deb "$tmp/x"
  mkdir -p "$(dirname "$GEOTIFF")"
  cp "$tmp/x/usr/lib/R/site-library/terra/ex/elev.tif" "$GEOTIFF"
  rm -rf "$tmp"
fi
rustup component list --installed 2>/dev/null | grep -q '^clippy' || rustup component add clippy rustfmt

echo "== cargo fmt --check"
cargo fmt --all -- --check

echo "== cargo clippy (-D warnings)"
cargo clippy --workspace --all-targets --all-features -- -D warnings

echo "== cargo doc (-D warnings: no broken or private intra-doc links)"
# The core and the C API are both the library `hfcast` (and the tool the binary
# `hfcast`): libraries only, the C API apart.
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --lib -p hfcast -p hfcast-shaders -p hfcast-tools
RUSTDOCFLAGS="-D warnings" CARGO_TARGET_DIR=target/doc-capi cargo doc --no-deps -p hfcast-capi

echo "== no_std build of the core (a second panic handler from std would fail it)"
CARGO_TARGET_DIR=target/nostd cargo build --manifest-path nostd-check/Cargo.toml
echo "== no_std build of the core with every method (the core's default features)"
CARGO_TARGET_DIR=target/nostd cargo build --manifest-path nostd-check/Cargo.toml --features hfcast/all-methods

# ---- Feature matrix (issue 8): each method builds alone, in the core and the C API ----
echo "== feature matrix: cargo check of the core with no method and with each alone"
for f in "" maxmip safety cone qdm relaxed search; do
  cargo check -q -p hfcast --no-default-features ${f:+--features "$f"}
done
echo "== feature matrix: cargo check of the C API without methods, with cone, safety, search"
for f in "" cone safety search; do
  cargo check -q -p hfcast-capi --no-default-features ${f:+--features "$f"}
done

echo "== hfcast report --quick (smoke test of the error-against-time report, < 3 min)"
cargo run --release -p hfcast-tools --bin hfcast -- report --quick --out target/report-quick

echo "== cargo test"
cargo test --workspace --all-features 2>&1 | tee target/test.log

# ---- C API, C tests, GLSL ports, OpenGL renderers (issue 6; see c_tests/Makefile) ----
# Builds libhfcast.{a,so}, then: the API tests (plain, ASan+UBSan, valgrind), the header
# alone as C99 and C++, glslangValidator on every composed shader, the OSMesa GPU/CPU
# parity test of every method, and the GLFW window under Xvfb against the OSMesa image.
echo "== C API: cargo build --release -p hfcast-capi (libhfcast.a, libhfcast.so)"
cargo build --release -p hfcast-capi
export MESA_SHADER_CACHE_DISABLE=true
C_MAKE=(make -s -C c_tests HFCAST_LIB_DIR=../target/release OUT=../target/c_tests)
C_MAPS="../data/dem_jacksboro_fault_403x344.png"
if [ -f ../shared/data/game_etr_i_like_spike_2_128x640.png ]; then
  C_MAPS="$C_MAPS ../../shared/data/game_etr_i_like_spike_2_128x640.png"
fi
: > target/c_tests.log
echo "== C tests: header alone (C99, C++11, .a and .so), API tests plain and with ASan+UBSan"
"${C_MAKE[@]}" test 2>&1 | tee -a target/c_tests.log
echo "== C tests: a library built with cone step mapping only, its header, and a C program"
"${C_MAKE[@]}" one-method 2>&1 | tee -a target/c_tests.log
echo "== C tests under valgrind"
"${C_MAKE[@]}" valgrind 2>&1 | tee -a target/c_tests.log
echo "== C tests: concurrency stress under helgrind (readers-writer protocol clean, --no-lock reported)"
"${C_MAKE[@]}" concurrency 2>&1 | tee -a target/c_tests.log
echo "== GLSL: glslangValidator on every composed shader"
"${C_MAKE[@]}" shaders
echo "== OSMesa (llvmpipe): GPU/CPU parity of every method, 256 x 192"
"${C_MAKE[@]}" render-test MAPS="$C_MAPS" 2>&1 | tee -a target/c_tests.log
echo "== OSMesa (llvmpipe): generated minimal shaders against the general ones and the CPU"
"${C_MAKE[@]}" render-generated-test MAPS="$C_MAPS" 2>&1 | tee -a target/c_tests.log
echo "== GLFW under Xvfb: the window's screenshot against the OSMesa image"
"${C_MAKE[@]}" glfw-test 2>&1 | tee -a target/c_tests.log
echo "== OSMesa (llvmpipe): GPU bakes in GLSL compute (maximum mipmap whole and updated, N-buffers, safety distances, cylinder-cones with N-buffer slopes) against the CPU's, byte for byte, on every map"
GPU_BAKE_MAPS="../data/dem_jacksboro_fault_403x344.png"
for m in ../shared/data/*.png; do
  if [ -f "$m" ]; then GPU_BAKE_MAPS="$GPU_BAKE_MAPS ../$m"; fi
done
"${C_MAKE[@]}" gpu-bake-test GPU_BAKE_MAPS="$GPU_BAKE_MAPS" 2>&1 | tee -a target/c_tests.log
echo "== Dynamic terrain (OSMesa and GLFW under Xvfb): heights edited every frame, the pyramid refreshed on the GPU for the edit, every frame against the CPU"
"${C_MAKE[@]}" dynamic-test MAPS="$C_MAPS" 2>&1 | tee -a target/c_tests.log
"${C_MAKE[@]}" glfw-dynamic-test 2>&1 | tee -a target/c_tests.log
echo "== Camera roll (Qu et al.; OSMesa and GLFW under Xvfb): the unrolled view texture-mapped against the rolled rays, pixel error and frame time"
"${C_MAKE[@]}" roll-test MAPS="$C_MAPS" 2>&1 | tee -a target/c_tests.log
"${C_MAKE[@]}" glfw-roll-test 2>&1 | tee -a target/c_tests.log
echo "== Hybrid rasterization (Qu et al. §4; OSMesa and GLFW under Xvfb): both passes against the CPU ray cast of the view-linear surface and the same passes on the CPU; fragments and frame times"
"${C_MAKE[@]}" hybrid-test MAPS="$C_MAPS" 2>&1 | tee -a target/c_tests.log
"${C_MAKE[@]}" glfw-hybrid-test 2>&1 | tee -a target/c_tests.log
echo "== Six-field impostors (Baboud & Décoret §4; OSMesa and GLFW under Xvfb): the bunny and the procedural tower through the generated GLSL against hf_impostor_trace_batch, clipped against unclipped proxies, depth output, reverse perspective against orthographic"
"${C_MAKE[@]}" impostor-test 2>&1 | tee -a target/c_tests.log
"${C_MAKE[@]}" glfw-impostor-test 2>&1 | tee -a target/c_tests.log
echo "== Embree (watertight) as an oracle: hfcast's exact CC, maximum-mipmap, safety-distance and DDA marches, every hit that differs within rounding"
# The synthetic fields at 256² too: fBm, and one-texel walls and needles (embree_bench.c).
EMBREE_MAPS="$C_MAPS synthetic:fractal:256 synthetic:needles:256"
if [ -f ../shared/data/dem_etopo5_himalaya_1024.png ]; then
  EMBREE_MAPS="$EMBREE_MAPS ../../shared/data/dem_etopo5_himalaya_1024.png"
fi
"${C_MAKE[@]}" embree-check MAPS="$EMBREE_MAPS" 2>&1 | tee -a target/c_tests.log
# Issue 21's costing probe (Embree's packet design on the maximum mipmap) is run by hand
# (make -C c_tests packet-cost); it is built here so that it keeps building.
"${C_MAKE[@]}" packet-cost-build 2>&1 | tee -a target/c_tests.log

echo "== fuzz smoke: scripts/fuzz.sh 120"
bash scripts/fuzz.sh 120 2>&1 | tee -a target/c_tests.log

echo "== install: scripts/install.sh into a temporary prefix; SONAME, hf_-only symbols, examples/cpp through pkg-config and CMake"
bash scripts/install_test.sh 2>&1 | tee -a target/c_tests.log

# The summary line CI reads: totals over every test binary (cargo), plus the C suites'
# "name: N passed, N failed" lines.
awk '/^test result:/ { p += $4; f += $6; i += $8 }
     /^[a-z-]+: [0-9]+ passed, [0-9]+ failed$/ { p += $2; f += $4 }
     END { printf "%d passed, %d failed, %d skipped\n", p, f, i }' target/test.log target/c_tests.log
