#!/usr/bin/env bash
# Scan and cycle-location speed on the Numba baseline's grids (scans/bench-full.toml,
# scans/bench-zoom.toml), 2 threads, three runs each; then the cycle search's
# bracket, dt/2 check and return-map count (`squeal ulc --nu 1e-3`).
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release --quiet
bin=target/release/squeal
tmp=$(mktemp -d)
for s in bench-full bench-zoom; do
  for i in 1 2 3; do
    "$bin" scan "scans/$s.toml" -o "$tmp/$s.h5" --threads 2 --force --quiet | grep cells/s | sed "s/^/$s: /"
  done
done
"$bin" ulc --nu 1e-3 | grep -E "bracket|dt/2|section returns"
rm -rf "$tmp"
