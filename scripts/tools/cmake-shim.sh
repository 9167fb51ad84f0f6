#!/usr/bin/env bash
# CMake shim for the static HDF5 build (see .cargo/config.toml; cargo's `cmake` crate runs
# whatever the CMAKE variable names).
#
# 1. A `cmake` on PATH that is >= 3.26 is used as it is.
# 2. Otherwise the CMake binary from PyPI's `cmake` wheel, installed under
#    $CARGO_TARGET_DIR/cmake-py (default target/cmake-py), is used. It is installed there
#    once, by the first build that needs it (python3 -m pip, network access to PyPI, about
#    30 s); every later build, of either profile, finds it again without the network.
#
# The wheel's bin/cmake is a Python entry point that only works with the right PYTHONPATH;
# the shim runs the native binary inside the wheel (site-packages/cmake/data/bin/cmake)
# instead, so finding it again needs neither Python nor pip.
# scripts/ci/test-cmake-shim.sh checks that a second call works with the package index
# unreachable.
set -euo pipefail
need_major=3 need_minor=26

ok_version() {
  local v maj min
  [ -x "$1" ] || return 1
  v=$("$1" --version 2>/dev/null | head -n1 | sed -E 's/[^0-9]*([0-9]+)\.([0-9]+).*/\1 \2/') || return 1
  read -r maj min <<<"$v"
  [ -n "${maj:-}" ] && [ -n "${min:-}" ] || return 1
  [ "$maj" -gt "$need_major" ] || { [ "$maj" -eq "$need_major" ] && [ "$min" -ge "$need_minor" ]; }
}

# The native cmake inside an installed wheel under $1, if there is one that works.
find_installed() {
  local c
  for c in "$1"/lib/python3*/site-packages/cmake/data/bin/cmake \
    "$1"/lib64/python3*/site-packages/cmake/data/bin/cmake \
    "$1"/local/lib/python3*/site-packages/cmake/data/bin/cmake; do
    if ok_version "$c"; then
      echo "$c"
      return 0
    fi
  done
  return 1
}

# HDF5's configure call (not `--build`, not `--version`) starts the long compile. cargo shows a
# build script's output only if it fails, and the crate that warns about this
# (crates/hdf5-notice) gets its turn from cargo only once many other crates are built, so
# say it on the terminal, when there is one, as the compile starts.
notice_hdf5() {
  local a configure=0
  for a in "$@"; do
    case $a in
      --build | --version | -E) return 0 ;;
      *[Hh][Dd][Ff]5*) configure=1 ;;
    esac
  done
  if [ "$configure" = 1 ] && { : >/dev/tty; } 2>/dev/null; then
    printf '\r\033[Ksqueal: compiling HDF5 from source (first build of this profile: several minutes; later builds reuse it)\n' >/dev/tty
  fi
  return 0
}
notice_hdf5 "$@"

self="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/$(basename "${BASH_SOURCE[0]}")"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
if sys=$(command -v cmake 2>/dev/null) && [ "$sys" != "$self" ] && ok_version "$sys"; then
  exec "$sys" "$@"
fi

dir="${CARGO_TARGET_DIR:-$root/target}/cmake-py"
if ! bin=$(find_installed "$dir"); then
  mkdir -p "$dir"
  (
    flock 9
    if ! find_installed "$dir" >/dev/null; then
      echo "squeal: no CMake >= 3.26 on PATH; installing PyPI's cmake into $dir (once)" >&2
      python3 -m pip install --quiet --disable-pip-version-check --prefix "$dir" \
        --ignore-installed 'cmake>=3.26,<4' >&2
    fi
  ) 9>"$dir/.lock"
  if ! bin=$(find_installed "$dir"); then
    echo "squeal: installed PyPI's cmake into $dir but found no working cmake binary in it" >&2
    exit 1
  fi
fi
exec "$bin" "$@"
