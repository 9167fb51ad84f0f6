#!/usr/bin/env bash
# The cost of a map's final-state sensitivity (crates/core/MODEL.md section 14), measured
# in one run: each spec twice per round, with its own `classifier.sensitivity_samples` and
# with 0 (entropies only), alternating, and the phase timings of both (SQUEAL_TIMINGS: the
# sensitivity's runs are in the `finish` phase). The entropies cost nothing beyond the
# labels; the runs' cost is the difference of the two.
#
#   cargo build --release
#   ROUNDS=3 scripts/bench/sensitivity-cost.sh [SPEC ...]   # default: scans/fig9.toml
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${SQUEAL:-target/release/squeal}
rounds=${ROUNDS:-3}
[ -x "$bin" ] || { echo "build first: cargo build --release (or set SQUEAL=...)" >&2; exit 2; }
specs=("$@")
[ ${#specs[@]} -gt 0 ] || specs=(scans/fig9.toml)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
date -u '+%Y-%m-%d %H:%M UTC'
lscpu | grep 'Model name' || true
echo "cores: $(nproc); rounds: $rounds"
for spec in "${specs[@]}"; do
    name=$(basename "$spec" .toml)
    cp "$spec" "$tmp/$name-on.toml"
    # The same spec with no extra runs: sensitivity_samples = 0 in its [classifier].
    if grep -q '^\[classifier\]' "$spec"; then
        sed -e '/^sensitivity_samples/d' -e 's/^\[classifier\]/[classifier]\nsensitivity_samples = 0/' \
            "$spec" > "$tmp/$name-off.toml"
    else
        { cat "$spec"; printf '\n[classifier]\nsensitivity_samples = 0\n'; } > "$tmp/$name-off.toml"
    fi
    for r in $(seq "$rounds"); do
        for mode in off on; do
            /usr/bin/time -o "$tmp/time" -f "%e %U" env SQUEAL_TIMINGS=1 \
                "$bin" scan "$tmp/$name-$mode.toml" -o "$tmp/$name.h5" --force --quiet \
                2> "$tmp/log" >/dev/null
            phases=$(grep -o 'timing: [a-z]* [0-9.]*' "$tmp/log" | awk '{printf "%s %s  ", $2, $3}')
            read -r wall user < "$tmp/time"
            echo "$name round $r sensitivity $mode: wall $wall s, user $user s; $phases"
        done
    done
done
