#!/usr/bin/env bash
# Scan speed against an older revision (BASE, default c44a1a5, before the step and scheme
# were chosen for accuracy), ratios measured in one
# run: cells per second of `squeal scan` on 512 x 512 versions of scans/fig9.toml and
# scans/fig9-zoom.toml, 2 threads, alternating old and new runs (ROUNDS of each).
#
# Columns: old = BASE at its defaults (dt = 0.01, zero-order hold); new = this tree at its
# defaults (dt = 0.005, first-order hold: the step chosen for 0.1% accuracy); new@0.01 zoh =
# this tree on the old step and scheme (the per-step speed-up alone).
#
# The old binary is built from a git worktree of BASE in /tmp (kept between runs).
#
# SUITE=decisions (BASE default 6685246): the certified early decisions, old and
# new alternating on the same specs, each pair compared cell by cell with `squeal compare`:
# bSTAB's friction case at v_d = 2.0 (steady_slip_only), 1.0 (stick_slip_only), both
# 128 x 128, and 1.5 (bistable, 256 x 128); scans/fig10.toml above the fold at nu = 0.026,
# 0.03, 0.05, 0.1 and 0.3 (cases above-NU, any NU; mcmillan-above-fold is above-0.03;
# 128 x 128); the 20-speed study scans/bstab-friction.toml at 64 x 32 per speed, or with
# FULL=1 at its own 256 x 128 (about 470 s for the old binary on a quiet machine). Its
# times are wall clock of the whole command (map preparation, cycle search and writing
# included; they were the summary's "cells in" time before 2026-11-24).
set -euo pipefail
cd "$(dirname "$0")/../.."
suite=${SUITE:-fig9}
if [ "$suite" = decisions ]; then BASE=${BASE:-6685246}; fi
base=${BASE:-c44a1a5}
rounds=${ROUNDS:-2}
oldtree=/tmp/squeal-bench-$base
old=${OLD_BIN:-$oldtree/target/release/squeal}  # OLD_BIN: an already built binary of BASE
if [ ! -x "$old" ]; then
  [ -d "$oldtree" ] || git worktree add --detach "$oldtree" "$base" >/dev/null
  (cd "$oldtree" && cargo build --release --quiet)
fi
cargo build --release --quiet
new=target/release/squeal
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
rate() { "$@" --threads 2 --force --quiet | grep -o '[0-9]* cells/s' | cut -d' ' -f1; }
secs() {
  local t0 t1
  t0=$(date +%s.%N)
  "$@" --threads 2 --force --quiet >/dev/null
  t1=$(date +%s.%N)
  echo "scale=2; ($t1 - $t0) / 1" | bc
}
if [ "$suite" = decisions ]; then
  echo "date: $(date -u +%Y-%m-%dT%H:%MZ)  machine: $(lscpu | grep 'Model name' | sed 's/  */ /g')  cpus: $(nproc)  load: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "| spec (2 threads) | round | old s | new s | old/new | agreement (new vs old) |"
  echo "|---|---|---:|---:|---:|---|"
  bstab() { sed -e "s/^v_d = .*/v_d = $1/" -e "s/count = 256 }/count = $2 }/" -e "s/count = 128 }/count = $3 }/" scans/bstab-friction.toml; }
  cases=${CASES:-steady-2.0 stick-1.0 bistable-1.5 above-0.026 above-0.03 above-0.05 above-0.1 above-0.3 bstab-friction}
  for c in $cases; do
    case $c in
      steady-2.0) bstab 2.0 128 128 ;;
      stick-1.0) bstab 1.0 128 128 ;;
      bistable-1.5) bstab 1.5 256 128 ;;
      mcmillan-above-fold) sed -e 's/^nu = .*/nu = 0.03/' -e 's/count = 256/count = 128/g' scans/fig10.toml ;;
      above-*) sed -e "s/^nu = .*/nu = ${c#above-}/" -e 's/count = 256/count = 128/g' scans/fig10.toml ;;
      bstab-friction) if [ "${FULL:-0}" = 1 ]; then cat scans/bstab-friction.toml; else
        sed -e 's/count = 256 }/count = 64 }/' -e 's/count = 128 }/count = 32 }/' scans/bstab-friction.toml; fi ;;
    esac >"$tmp/$c.toml"
    for i in $(seq "$rounds"); do
      a=$(secs "$old" scan "$tmp/$c.toml" -o "$tmp/$c-old.h5")
      b=$(secs "$new" scan "$tmp/$c.toml" -o "$tmp/$c-new.h5")
      agree=$("$new" compare "$tmp/$c-new.h5" "$tmp/$c-old.h5" | grep -o '[0-9]* of [0-9]* decided cells agree' | paste -sd';')
      echo "| $c | $i | $a | $b | $(echo "scale=1; $a / $b" | bc) | $agree |"
    done
    "$new" scan "$tmp/$c.toml" -o "$tmp/$c-new.h5" --threads 2 --force --quiet | grep -E 'reasons:|runs to settlement' | sed 's/^ */    /'
  done
  exit 0
fi
echo "date: $(date -u +%Y-%m-%dT%H:%MZ)  machine: $(lscpu | grep 'Model name' | sed 's/  */ /g')  cpus: $(nproc)"
echo "| grid (512 x 512, 2 threads) | round | old cells/s | new cells/s | new/old | new@0.01 zoh cells/s | ratio |"
echo "|---|---|---:|---:|---:|---:|---:|"
for s in fig9 fig9-zoom; do
  grid() { sed -e 's/count = 256/count = 512/g' "scans/$s.toml"; }
  grid | sed -e '/^scheme = /d' -e 's/^dt = .*/dt = 0.01/' >"$tmp/old.toml"
  grid >"$tmp/new.toml"
  grid | sed -e 's/^scheme = .*/scheme = "zoh"/' -e 's/^dt = .*/dt = 0.01/' >"$tmp/zoh.toml"
  for i in $(seq "$rounds"); do
    a=$(rate "$old" scan "$tmp/old.toml" -o "$tmp/old.h5")
    b=$(rate "$new" scan "$tmp/new.toml" -o "$tmp/new.h5")
    c=$(rate "$new" scan "$tmp/zoh.toml" -o "$tmp/zoh.h5")
    echo "| $s | $i | $a | $b | $(echo "scale=2; $b / $a" | bc) | $c | $(echo "scale=2; $c / $a" | bc) |"
  done
done
