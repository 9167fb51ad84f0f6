#!/usr/bin/env bash
# Scan and cycle-location speed (issues 3 and 4): the Numba baseline's grids, 2 threads.
set -euo pipefail
cd "$(dirname "$0")/.."
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
