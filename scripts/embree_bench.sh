#!/usr/bin/env bash
# hfcast against Embree on the same triangles and rays (c_tests/embree_bench.c): installs
# libembree-dev if missing, builds libhfcast in release, runs the benchmark.
# Usage: bash scripts/embree_bench.sh [--threads N] [MAP [reps]]   one field: a PNG (path
#          relative to c_tests/) or synthetic:fractal / synthetic:needles (1024², or
#          synthetic:NAME:SIDE); default the Himalaya DEM of ../shared/data, 5 repetitions
#        bash scripts/embree_bench.sh [--threads N] --all [reps]   the Himalaya DEM,
#          synthetic:fractal and synthetic:needles in turn (default 5 repetitions each)
#   --threads N: both sides trace on N threads (default 1)
set -euo pipefail
cd "$(dirname "$0")/.."
threads=1
if [ "${1:-}" = --threads ]; then
  threads="${2:?--threads needs a count}"
  shift 2
fi
for p in libembree-dev libpng-dev gcc make; do
  if ! dpkg -s "$p" >/dev/null 2>&1; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$p"
  fi
done
cargo build --release -p hfcast-capi
bench() {
  make -s -C c_tests embree-bench HFCAST_LIB_DIR=../target/release OUT=../target/c_bench \
    ${1:+BENCH_MAP="$1"} ${2:+BENCH_REPS="$2"} BENCH_THREADS="$threads"
}
if [ "${1:-}" = --all ]; then
  for map in ../../shared/data/dem_etopo5_himalaya_1024.png synthetic:fractal synthetic:needles; do
    bench "$map" "${2:-}"
  done
else
  bench "${1:-}" "${2:-}"
fi
