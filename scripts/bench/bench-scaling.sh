#!/usr/bin/env bash
# How squeal scales with the threads: each shape run at 1, 2, ... N threads
# (N = nproc; --threads LIST to choose), with the phase times the binary itself prints under
# SQUEAL_TIMINGS=1 (crates/cli/src/cmd/timings.rs: a scan's start, cells, prepare, sink, redo, finish,
# picture; an atlas's start, units, maps, finish, picture). Prints each run's wall time and
# phases, each shape's phase shares at 1 thread, the serial fraction f from the 1- and
# N-thread wall times (Amdahl: speed-up S = T1/TN, f = (N/S - 1)/(N - 1)), and the speed-up
# that f allows on 16 and 64 cores (1 / (f + (1 - f)/P)); beside it the idle share of the
# N-thread run alone (its CPU time against N x its wall time) and how much the CPU time grew
# from the first count to N (what cores slowing each other add to f). Where the first count
# A is not 1, f comes from the runs at A and N alone (T_A/T_N = g(A)/g(N), g(P) = f +
# (1 - f)/P, solved for f), so a shape too long to run on one thread still gets its fraction.
#
#   cargo build --release && scripts/bench/bench-scaling.sh [--quick] [--threads 1,2]
#       [--atlas-threads 8,16] [--shapes bstab,fig9-4096,atlas,stribeck-steady,nu-sweep]
#       [--base OLD/squeal]
#
# --atlas-threads LIST: the atlas's own thread counts (default: --threads). Its 64 x 64
# chart takes about 1500 s of CPU (the runs that confirm each line's fold and critical
# damping), too long for one thread within a lent machine's 15 minutes; on 16
# cores, --threads 1,16 --atlas-threads 8,16 runs in about 8 minutes.
#
# Shapes: bSTAB's belt-speed study (scans/bstab-friction.toml); Fig. 9 at 4096 x 4096
# (scans/fig9.toml with the counts raised, 16.8M cells); the 64 x 64 atlas
# (scans/atlas-lambda-nu.toml, --no-render); the Stribeck map whose every start ends in
# steady slip (bstab-friction at v_d = 2.225 only, 512 x 256); the damping sweep
# (scans/nu-sweep.toml). --quick shrinks each (a 512 x 512 Fig. 9, a 4 x 4 atlas, the
# others a quarter of the cells or fewer) so that the script is checked in a minute or two.
# --base BIN also times BIN (an older squeal, no phase times) on fig9-4096 and atlas at
# N threads, alternating old, new, old, new (ROUNDS=2 by default), and prints the ratio.
# REPEAT=N runs each shape N times at each thread count, interleaved, and uses each count's
# fastest run (on a shared machine one run's noise moves the serial fraction by +-3%).
# The machine is shared: say the load average (printed) beside the figures.
set -euo pipefail
bin=${SQUEAL:-target/release/squeal}
threads=""
atlas_threads=""
quick=0
base=""
shapes="bstab,fig9-4096,atlas,stribeck-steady,nu-sweep"
rounds=${ROUNDS:-2}
repeat=${REPEAT:-1}
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --threads) threads=$2; shift ;;
    --atlas-threads) atlas_threads=$2; shift ;;
    --shapes) shapes=$2; shift ;;
    --base) base=$2; shift ;;
    -h|--help) sed -n '2,35p' "$0"; exit 0 ;;
    *) echo "bench-scaling.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
  shift
done
[ -x "$bin" ] || { echo "build first: cargo build --release (or set SQUEAL=...)" >&2; exit 2; }
[ -z "$base" ] || [ -x "$base" ] || { echo "--base $base: no such binary" >&2; exit 2; }
if [ -z "$threads" ]; then threads=$(seq -s, 1 "$(nproc)"); fi
[ -n "$atlas_threads" ] || atlas_threads=$threads
work=$(mktemp -d "${TMPDIR:-/tmp}/squeal-scaling.XXXXXX")
trap 'rm -rf "$work"' EXIT

# The spec of each shape, written to $work (the output path is given with -o).
grid() { # file x0count v0count -> replaces the grid's counts
  sed -E -e "s/^(x0 = .*count = )[0-9]+/\1$2/" -e "s/^(v0 = .*count = )[0-9]+/\1$3/" "$1"
}
make_spec() {
  local s=$1 f=$work/$1.toml
  case "$s" in
    bstab)
      if [ $quick = 1 ]; then
        grid scans/bstab-friction.toml 64 32 | sed -E 's/count = 20 \}/count = 4 }/' > "$f"
      else cp scans/bstab-friction.toml "$f"; fi ;;
    fig9-4096)
      if [ $quick = 1 ]; then grid scans/fig9.toml 512 512 > "$f"
      else grid scans/fig9.toml 4096 4096 > "$f"; fi ;;
    atlas)
      if [ $quick = 1 ]; then sed -E 's/count = 64,/count = 4,/' scans/atlas-lambda-nu.toml > "$f"
      else cp scans/atlas-lambda-nu.toml "$f"; fi ;;
    stribeck-steady)
      if [ $quick = 1 ]; then n="128 64"; else n="512 256"; fi
      # shellcheck disable=SC2086
      grid scans/bstab-friction.toml $n \
        | sed -E 's/^v_d = .*/v_d = 2.225/; s/^name = .*/name = "stribeck-steady"/' > "$f" ;;
    nu-sweep)
      if [ $quick = 1 ]; then grid scans/nu-sweep.toml 48 48 > "$f"
      else cp scans/nu-sweep.toml "$f"; fi ;;
    *) echo "unknown shape $s" >&2; exit 2 ;;
  esac
  echo "$f"
}
cmd_of() { # shape -> the subcommand and its extra flags
  case "$1" in atlas) echo "atlas --no-render" ;; *) echo "scan" ;; esac
}
# One run: prints "wall phase=secs ..." (phases from SQUEAL_TIMINGS).
one() { # binary shape spec threads
  local b=$1 s=$2 spec=$3 t=$4 out=$work/$2.h5 err=$work/err t0 t1
  rm -f "$work/$s".*.png "$work/$s.png" "$out"
  t0=$(date +%s.%N)
  # shellcheck disable=SC2046
  if ! SQUEAL_TIMINGS=1 "$b" $(cmd_of "$s") "$spec" -o "$out" --threads "$t" --quiet --force \
      > /dev/null 2> "$err"; then
    echo "bench-scaling.sh: $b failed on $s at $t threads:" >&2; cat "$err" >&2; exit 1
  fi
  t1=$(date +%s.%N)
  printf '%s' "$(echo "$t1 - $t0" | bc -l)"
  # The run's CPU time, user and system (this subshell's children: the run, and the
  # milliseconds of date): bash's `times`, second line "XmY.YYYs XmY.YYYs".
  times > "$work/times" # a builtin, not forked (a fork's children are none of these)
  awk 'NR == 2 { c = 0; for (i = 1; i <= 2; i++) { split($i, a, /[ms]/); c += 60 * a[1] + a[2] }
    printf " cpu=%.2f", c }' "$work/times"
  awk '/^squeal timing: / { printf " %s=%s", $3, $4 }' "$err"
  echo
}

date -u '+%Y-%m-%d %H:%M UTC'
lscpu | grep 'Model name' || true
echo "cores: $(nproc); threads: $threads (atlas $atlas_threads); repeat: $repeat; quick: $quick; binary: $bin ($("$bin" --version 2>/dev/null || true))"
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
IFS=, read -r -a slist <<< "$shapes"
summary=()
for s in "${slist[@]}"; do
  spec=$(make_spec "$s")
  counts=$threads
  [ "$s" != atlas ] || counts=$atlas_threads
  IFS=, read -r -a tlist <<< "$counts"
  nmax=${tlist[-1]}
  echo
  echo "== $s ($(cmd_of "$s") $(basename "$spec"), threads $counts)"
  declare -A wall=() cpu=()
  # REPEAT rounds, the thread counts interleaved within each (a drift of the machine's
  # load then reaches every count alike); each count's fastest run is the one used.
  for rep in $(seq "$repeat"); do
    for t in "${tlist[@]}"; do
      r=$(one "$bin" "$s" "$spec" "$t")
      w=${r%% *}
      if [ -z "${wall[$t]:-}" ] || [ "$(echo "$w < ${wall[$t]}" | bc -l)" = 1 ]; then
        wall[$t]=$w
        cpu[$t]=$(echo "$r" | tr ' ' '\n' | awk -F= '$1 == "cpu" { print $2 }')
        if [ "$t" = "${tlist[0]}" ]; then first="$r"; fi
      fi
      printf '  threads %-3s wall %8.2f s  %s  (load %s%s)\n' "$t" "$w" \
        "$(echo "${r#* }" | tr ' ' '\n' | awk -F= 'NF == 2 { printf "%s %.2f  ", $1, $2 }')" \
        "$(cut -d' ' -f1 /proc/loadavg)" "$([ "$repeat" = 1 ] || echo ", round $rep")"
    done
  done
  # Shares of the wall time at the first thread count (the phases inside "cells", prepare
  # and sink, are shown as shares too but overlap it).
  echo "$first" | awk '{ w = $1; printf "  shares at %s thread(s):", "'"${tlist[0]}"'"
    for (i = 2; i <= NF; i++) { split($i, kv, "="); printf " %s %.1f%%", kv[1], 100 * kv[2] / w }
    print "" }'
  if [ "${#tlist[@]}" -gt 1 ]; then
    a=${tlist[0]}
    line=$(awk -v ta="${wall[$a]}" -v tn="${wall[$nmax]}" -v ca="${cpu[$a]}" -v cn="${cpu[$nmax]}" \
        -v a="$a" -v n="$nmax" -v s="$s" 'BEGIN {
      # Amdahl: T_P = T_1 g(P), g(P) = f + (1 - f)/P; R = T_A/T_N = g(A)/g(N) solved for f
      # (with A = 1: f = (N/S - 1)/(N - 1), S = T_1/T_N).
      R = ta / tn; f = (1 / a - R / n) / (R - R / n - 1 + 1 / a)
      a16 = 1 / (f + (1 - f) / 16); a64 = 1 / (f + (1 - f) / 64)
      # From the N-thread run alone: its threads idle N T_N - C_N thread-seconds, which Amdahl
      # puts at f C (N - 1) if the CPU time C is the same on any count. The wall-time f also
      # holds what the CPU time grows by from A to N threads (cores that slow each other, a
      # virtual machine sharing its host); the idle f does not.
      fi = (n * tn - cn) / (cn * (n - 1))
      printf "%-16s %d thread(s) %8.2f s, %d threads %8.2f s: speed-up %.2f, serial fraction %.1f%%, allows %.1fx on 16 cores, %.1fx on 64 (over 1 thread); idle at %d threads %.1f%%, CPU time %+.1f%% from %d to %d threads", s, a, ta, n, tn, R, 100 * f, a16, a64, n, 100 * fi, 100 * (cn / ca - 1), a, n }')
    echo "  $line"
    summary+=("$line")
  fi
  unset wall cpu
done
if [ -n "$base" ]; then
  echo
  echo "== against $base ($("$base" --version 2>/dev/null || true)), alternating, $rounds round(s)"
  for s in fig9-4096 atlas; do
    case ",$shapes," in *",$s,"*) ;; *) continue ;; esac
    counts=$threads
    [ "$s" != atlas ] || counts=$atlas_threads
    nmax=${counts##*,}
    spec=$work/$s.toml
    ob=0; nb=0
    for _ in $(seq "$rounds"); do
      o=$(one "$base" "$s" "$spec" "$nmax"); o=${o%% *}
      n=$(one "$bin" "$s" "$spec" "$nmax"); n=${n%% *}
      printf '  %-10s %s threads: old %8.2f s  new %8.2f s  (load %s)\n' "$s" "$nmax" "$o" "$n" "$(cut -d' ' -f1 /proc/loadavg)"
      ob=$(echo "$ob + $o" | bc -l); nb=$(echo "$nb + $n" | bc -l)
    done
    line=$(printf '%s: old/new wall %.2fx (old %.2f s, new %.2f s, mean of %s)' "$s" \
      "$(echo "$ob / $nb" | bc -l)" "$(echo "$ob / $rounds" | bc -l)" "$(echo "$nb / $rounds" | bc -l)" "$rounds")
    echo "  $line"
    summary+=("$line")
  done
fi
echo
echo "== summary (load average after: $(cut -d' ' -f1-3 /proc/loadavg))"
printf '%s\n' "${summary[@]}"
