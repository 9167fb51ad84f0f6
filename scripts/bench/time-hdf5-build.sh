#!/usr/bin/env bash
# Times what the first build of a profile spends on HDF5: builds the hdf5-metno-src crate
# (HDF5 from source through CMake) in a fresh target folder and prints the wall time.
# The PyPI cmake install (if no CMake >= 3.26 is on PATH) is included in the time.
#
#   scripts/bench/time-hdf5-build.sh [--release]     # nice'd; uses all cores cargo sees
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
start=$(date +%s)
CARGO_TARGET_DIR="$tmp" nice cargo build --quiet -p hdf5-metno-src "$@"
end=$(date +%s)
echo "HDF5 build ($([ "${1:-}" = --release ] && echo release || echo dev) profile, $(nproc) cores): $((end - start)) s"
