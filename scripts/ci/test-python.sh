#!/usr/bin/env bash
# The Python package's tests (python/tests): builds the wheel (scripts/tools/build-wheel.sh),
# installs it and pytest into a fresh venv, and runs pytest there with no cargo or rustc
# on PATH, as a user without Rust would. Prints the test count. Arguments go to pytest
# (`scripts/ci/test-python.sh -k shape`: one family). About 2-4 minutes after
# `cargo build --release` (target/ is reused; the test dependencies come from PyPI).
set -euo pipefail
cd "$(dirname "$0")/../.."
wheel=$(scripts/tools/build-wheel.sh)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 -m venv "$work/venv"
"$work/venv/bin/pip" install --quiet "$wheel" pytest
# Only the venv and the system's directories: no ~/.cargo/bin.
clean_path="$work/venv/bin:/usr/local/bin:/usr/bin:/bin"
if PATH=$clean_path command -v cargo >/dev/null || PATH=$clean_path command -v rustc >/dev/null; then
    echo "test-python: cargo or rustc is still on PATH ($clean_path)" >&2
    exit 1
fi
cd "$work"
env -i HOME="$HOME" PATH="$clean_path" LANG=C.UTF-8 \
    "$work/venv/bin/python" -m pytest -q -p no:cacheprovider "$OLDPWD/python/tests" "$@"
