#!/usr/bin/env bash
# CMake shim for the static HDF5 build (see .cargo/config.toml).
# Uses `cmake` from PATH when it is >= 3.26; otherwise installs PyPI's cmake wheel once
# under target/cmake-py (needs python3 with pip and access to PyPI) and runs that.
set -euo pipefail
need_major=3 need_minor=26
ok_version() {
  local v
  v=$("$1" --version 2>/dev/null | head -n1 | sed -E 's/[^0-9]*([0-9]+)\.([0-9]+).*/\1 \2/') || return 1
  read -r maj min <<<"$v"
  [ -n "${maj:-}" ] && { [ "$maj" -gt "$need_major" ] || { [ "$maj" -eq "$need_major" ] && [ "$min" -ge "$need_minor" ]; }; }
}
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if sys=$(command -v cmake 2>/dev/null) && [ "$sys" != "${BASH_SOURCE[0]}" ] && ok_version "$sys"; then
  exec "$sys" "$@"
fi
dir="${CARGO_TARGET_DIR:-$root/target}/cmake-py"
bin="$dir/bin/cmake"
if ! ok_version "$bin"; then
  mkdir -p "$dir"
  (
    flock 9
    if ! ok_version "$bin"; then
      echo "squeal: no CMake >= 3.26 on PATH; installing PyPI's cmake into $dir" >&2
      python3 -m pip install --quiet --disable-pip-version-check --prefix "$dir" --ignore-installed 'cmake>=3.26,<4' >&2
    fi
  ) 9>"$dir/.lock"
fi
export PYTHONPATH="$(echo "$dir"/lib/python3*/site-packages)${PYTHONPATH:+:$PYTHONPATH}"
exec "$bin" "$@"
