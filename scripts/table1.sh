#!/usr/bin/env bash
# Table 1 of Baboud, Eisemann, Seidel (2011) side by side (issue 20), into
# docs/report/table1.md: the CPU table of `hfcast table1` (bake seconds, bytes, rays in
# the map's set, fetches and ns per ray, rays that differ from the exact traversal),
# then the OSMesa frame times of the same settings on the same centre crops
# (`render_osmesa table1`: primary rays, llvmpipe, software). `hfcast report` puts the
# file into its README as a section. About 10 minutes on 2 cores (the exterior and
# phi_max bakes at 1024^2 dominate; each is baked once per table).
#   bash scripts/table1.sh [SIDE...]        (default: 256 512 1024)
set -euo pipefail
cd "$(dirname "$0")/.."
MAP=../shared/data/dem_etopo5_himalaya_1024.png
SIDES=("${@:-256}")
[ $# -gt 0 ] || SIDES=(256 512 1024)
OUT=docs/report/table1.md
export MESA_SHADER_CACHE_DISABLE=true
cargo build -q --release -p hfcast-tools -p hfcast-capi
make -s -C c_tests HFCAST_LIB_DIR=../target/release OUT=../target/c_tests ../target/c_tests/render_osmesa
list=$(IFS=,; echo "${SIDES[*]}")
./target/release/hfcast table1 --map "$MAP" --sides "$list" --out "$OUT"
frames=$(./target/c_tests/render_osmesa table1 320 256 "$MAP" "${SIDES[@]}")
{
  echo
  echo "## OSMesa frame times"
  echo
  echo "Made by \`render_osmesa table1 320 256 $(basename "$MAP") ${SIDES[*]}\` (c_tests/render_osmesa.c) in \`bash scripts/table1.sh\`."
  echo "The cameras are the C tests' orbit camera at the same elevations and field of view (not the CPU table's rays pixel for pixel)."
  echo
  echo "$frames"
} >> "$OUT"
echo "table1: wrote $OUT"
