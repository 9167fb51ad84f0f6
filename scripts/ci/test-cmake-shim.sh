#!/usr/bin/env bash
# Checks scripts/tools/cmake-shim.sh with no cmake on PATH: the first call installs PyPI's cmake
# into a fresh target folder, the second call finds it again with the package index
# unreachable (PIP_INDEX_URL pointing at a closed port and, where `unshare -rn` works, no
# network at all) and does not try to install again.
#
#   scripts/ci/test-cmake-shim.sh            # needs network access to PyPI for the first call
#
# Exit status 0 when both calls pass.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
shim="$here/../tools/cmake-shim.sh"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# PATH without any directory that holds a cmake, so the shim must use its own.
clean_path=""
IFS=: read -r -a parts <<<"$PATH"
for d in "${parts[@]}"; do
  [ -n "$d" ] && [ ! -x "$d/cmake" ] && clean_path="${clean_path:+$clean_path:}$d"
done

run() {
  env PATH="$clean_path" CARGO_TARGET_DIR="$tmp/target" "$@"
}

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

echo "1. first call (installs into $tmp/target/cmake-py)"
run "$shim" --version >"$tmp/out1" 2>"$tmp/err1" || { cat "$tmp/err1" >&2; fail "first call"; }
grep -q '^cmake version 3\.' "$tmp/out1" || fail "first call printed: $(cat "$tmp/out1")"
grep -q 'installing' "$tmp/err1" || fail "first call did not say it installs cmake"
head -n1 "$tmp/out1"

echo "2. second call, package index unreachable"
offline=(env PIP_INDEX_URL=http://127.0.0.1:9/simple PIP_NO_INDEX=1)
if unshare -rn true 2>/dev/null; then
  offline=(unshare -rn "${offline[@]}")
  echo "   (in a network namespace without network)"
fi
run "${offline[@]}" "$shim" --version >"$tmp/out2" 2>"$tmp/err2" || { cat "$tmp/err2" >&2; fail "second call"; }
grep -q '^cmake version 3\.' "$tmp/out2" || fail "second call printed: $(cat "$tmp/out2")"
if grep -q 'installing' "$tmp/err2"; then fail "second call tried to install again"; fi
head -n1 "$tmp/out2"
echo "PASS: cmake installed once and found again offline"
