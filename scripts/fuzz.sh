#!/usr/bin/env bash
# Coverage-guided fuzzing of the C API (issue 26): scripts/fuzz.sh SECONDS
# Installs clang and libFuzzer if missing, builds libhfcast.a instrumented for coverage
# (sancov, debug assertions, overflow checks; target/fuzz), links the targets of fuzz/
# with -fsanitize=fuzzer,address,undefined, and runs each for SECONDS / (number of
# targets) seconds on one core, from and into the committed corpus fuzz/corpus/<target>/.
# Prints per target its executions, coverage, crashes and timeouts; exits non-zero on
# any crash, hang over 1 s or sanitizer report; the last line is
# `fuzz: N passed, M failed`. Crash inputs land in target/fuzz/artifacts/<target>/.
set -uo pipefail
cd "$(dirname "$0")/.."
SECONDS_TOTAL=${1:-120}
TARGETS=(fuzz_field fuzz_bake fuzz_trace)

pkgs=()
command -v clang >/dev/null 2>&1 || pkgs+=(clang)
dpkg -s libclang-rt-14-dev >/dev/null 2>&1 || pkgs+=(libclang-rt-14-dev)
if [ ${#pkgs[@]} -gt 0 ]; then
  echo "== installing ${pkgs[*]}"
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${pkgs[@]}" >/dev/null
fi

echo "== building libhfcast.a with coverage instrumentation (target/fuzz)"
export CARGO_TARGET_DIR=target/fuzz
HOST=$(rustc -vV | sed -n 's/^host: //p')
# --target keeps the instrumentation off the build scripts (they link without libFuzzer).
RUSTFLAGS="-C passes=sancov-module -C llvm-args=-sanitizer-coverage-level=3 \
-C llvm-args=-sanitizer-coverage-inline-8bit-counters -C llvm-args=-sanitizer-coverage-pc-table \
-C llvm-args=-sanitizer-coverage-trace-compares -C debug-assertions -C overflow-checks" \
  cargo rustc -q --release -p hfcast-capi --lib --crate-type staticlib --target "$HOST" || {
  echo "fuzz: 0 passed, ${#TARGETS[@]} failed"; exit 1; }
LIB=target/fuzz/$HOST/release/libhfcast.a
BIN=target/fuzz/bin
mkdir -p "$BIN"
for t in "${TARGETS[@]}"; do
  clang -g -O1 -Wall -Wextra -Werror -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
    -Iinclude "fuzz/$t.c" -o "$BIN/$t" "$LIB" -lpthread -ldl -lm -lrt -lutil || {
    echo "fuzz: 0 passed, ${#TARGETS[@]} failed"; exit 1; }
done

per=$((SECONDS_TOTAL / ${#TARGETS[@]}))
[ "$per" -ge 1 ] || per=1
passed=0
failed=0
for t in "${TARGETS[@]}"; do
  corpus=fuzz/corpus/$t
  art=target/fuzz/artifacts/$t
  log=target/fuzz/$t.log
  mkdir -p "$corpus" "$art"
  echo "== $t: $per s"
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
    "$BIN/$t" -max_total_time="$per" -timeout=1 -rss_limit_mb=2048 -max_len=8192 \
    -len_control=20 -print_final_stats=1 -artifact_prefix="$art/" \
    "$corpus" >"$log" 2>&1
  rc=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  final=$(grep -E '^#[0-9]+' "$log" | tail -1)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$final")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$final")
  crashes=$(find "$art" -name 'crash-*' -newer "$BIN/$t" | wc -l)
  timeouts=$(find "$art" -name 'timeout-*' -newer "$BIN/$t" | wc -l)
  ooms=$(find "$art" -name 'oom-*' -newer "$BIN/$t" | wc -l)
  reports=$(grep -cE '^SUMMARY: (Address|UndefinedBehavior|Leak)Sanitizer|fuzz violation' "$log")
  echo "$t: executions ${execs:-0}, cov ${cov:-0}, ft ${ft:-0}, crashes $crashes, timeouts $timeouts, ooms $ooms, sanitizer reports $reports (rc $rc, log $log)"
  if [ "$rc" -eq 0 ] && [ "$crashes" -eq 0 ] && [ "$timeouts" -eq 0 ] && [ "$ooms" -eq 0 ] && [ "$reports" -eq 0 ]; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    grep -E 'fuzz violation|ERROR:|SUMMARY|Test unit written' "$log" | head -5
  fi
done
# The findings of fuzz/findings/ (README there), settled by issue 25: each input must
# now pass fuzz_field under the flag that used to report it.
while read -r name flag; do
  flog=target/fuzz/finding_$name.log
  if env "$flag=1" "$BIN/fuzz_field" "fuzz/findings/$name.fuzz_field" >"$flog" 2>&1; then
    echo "finding $name ($flag=1): passes"
    passed=$((passed + 1))
  else
    echo "finding $name ($flag=1): fails (log $flog)"
    failed=$((failed + 1))
  fi
done <<'FINDINGS'
maxmip_flat_ray FZ_STRICT
maxmip_side_wall FZ_EXTREME
FINDINGS
echo "fuzz: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
