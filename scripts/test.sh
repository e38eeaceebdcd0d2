#!/usr/bin/env bash
# Runs every test of hfcast on a fresh Debian machine: installs what is missing, then
# formatting, lints, the workspace tests, and the no_std build of the core.
set -euo pipefail
cd "$(dirname "$0")/.."

# System packages the tests need (none yet beyond the Rust toolchain and a C compiler;
# the C API and OpenGL issues add theirs here).
APT_PACKAGES=()
missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "== installing ${missing[*]}"
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}"
fi
rustup component list --installed 2>/dev/null | grep -q '^clippy' || rustup component add clippy rustfmt

echo "== cargo fmt --check"
cargo fmt --all -- --check

echo "== cargo clippy (-D warnings)"
cargo clippy --workspace --all-targets --all-features -- -D warnings

echo "== no_std build of the core (a second panic handler from std would fail it)"
CARGO_TARGET_DIR=target/nostd cargo build --manifest-path nostd-check/Cargo.toml

echo "== hfcast report --quick (smoke test of the error-against-time report, < 2 min)"
cargo run --release -p hfcast-tools --bin hfcast -- report --quick --out target/report-quick

echo "== cargo test"
cargo test --workspace --all-features 2>&1 | tee target/test.log
# The summary line CI reads: totals over every test binary.
awk '/^test result:/ { p += $4; f += $6; i += $8 } END { printf "%d passed, %d failed, %d skipped\n", p, f, i }' target/test.log
