#!/usr/bin/env bash
# Builds the Python wheel of squeal (PyO3, stable ABI: one wheel for CPython >= 3.9 on
# this platform) into target/wheels/ and prints its path. The wheel holds the native
# module with HDF5 linked statically (as the command line is built: .cargo/config.toml)
# and puts the `squeal` command on PATH: it installs with no Rust and no HDF5.
#
# maturin comes from PyPI into target/py-build/ (once). The build reuses target/ (release
# profile, same features as `cargo build --release`), so HDF5 is not rebuilt.
#   scripts/tools/build-wheel.sh            # -> target/wheels/squeal-<version>-cp39-abi3-<platform>.whl
set -euo pipefail
cd "$(dirname "$0")/../.."
tools=target/py-build
if [[ ! -x $tools/bin/maturin ]]; then
    python3 -m venv "$tools"
    "$tools/bin/pip" install --quiet "maturin>=1.9,<2"
fi
rm -rf target/wheels
"$tools/bin/maturin" build --release --quiet --interpreter python3 --out target/wheels >&2
ls target/wheels/squeal-*.whl
