#!/usr/bin/env bash
# Sizes of libhfcast (issue 8, "leave out what a scene does not need"): the static
# library, the shared library (every exported function kept: here the features
# count), and a linked, stripped C program (c_tests/size_probe.c: a field, the exact
# trace and, where built, a cone bake and trace) for the full build, a one-method build
# (cone step mapping) and the exact-only build, release profile, without and with
# fat LTO (codegen-units = 1). Prints a Markdown table of bytes.
#   scripts/sizes.sh            (builds into target/sizes; SIZES_TARGET overrides)
set -euo pipefail
cd "$(dirname "$0")/.."
T=${SIZES_TARGET:-target/sizes}
CC=${CC:-cc}
BUILDS=("full|" "cone|--no-default-features --features cone" "exact|--no-default-features")

echo "| build | LTO | libhfcast.a | .a without debug info | libhfcast.so, stripped | C program, linked static, stripped (--gc-sections) |"
echo "|---|---|---:|---:|---:|---:|"
for lto in off fat; do
  cgu=16
  [ "$lto" = fat ] && cgu=1
  for b in "${BUILDS[@]}"; do
    name=${b%%|*}
    read -r -a flags <<< "${b#*|}"
    dir=$T/$name-lto-$lto
    mkdir -p "$dir"
    export CARGO_PROFILE_RELEASE_LTO=$lto CARGO_PROFILE_RELEASE_CODEGEN_UNITS=$cgu
    cargo build -q --release -p hfcast-capi "${flags[@]}" --target-dir "$dir"
    cargo run -q --release -p hfcast-capi "${flags[@]}" --example header --target-dir "$dir" > "$dir/hfcast.h"
    lib=$dir/release/libhfcast.a
    cp "$lib" "$dir/nodebug.a"
    strip --strip-debug "$dir/nodebug.a"
    strip -o "$dir/libhfcast.so" "$dir/release/libhfcast.so"
    $CC -O2 -I"$dir" c_tests/size_probe.c -o "$dir/probe" "$lib" -lm -lpthread -ldl -Wl,--gc-sections -s
    "$dir/probe" > /dev/null
    echo "| $name | $lto | $(stat -c %s "$lib") | $(stat -c %s "$dir/nodebug.a") | $(stat -c %s "$dir/libhfcast.so") | $(stat -c %s "$dir/probe") |"
  done
done
