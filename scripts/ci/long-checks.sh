#!/usr/bin/env bash
# The long physics checks: tests too slow for the suite a developer runs often
# (`cargo test --workspace`), marked `#[ignore]` there and run here by exact name. .ci/run
# calls this after the quick suite. Each line: the test target, then the test. They run with
# `--workspace`, as the quick suite does, so cargo reuses its build (selecting one package
# unifies features differently and rebuilds the dependencies).
#
#   scripts/ci/long-checks.sh          # all of them
#   scripts/ci/long-checks.sh --list   # their names
set -euo pipefail
cd "$(dirname "$0")/../.."
checks=(
  # bSTAB's published basin stability at 20 belt speeds, 655,360 cells (tests/bstab_friction.rs).
  "--test bstab_friction squeal_matches_the_published_basin_stability"
  # Early stopping against runs to settlement off the paper's parameters, 4 x 2 scans of 64 x 64.
  "--test off_paper early_stopping_agrees_with_settlement_off_the_paper"
  # The transient lifetimes above two folds of an atlas, 8 band starts at 10 dampings each.
  "--test atlas an_atlas_measures_transient_lifetimes_above_each_fold"
  # The atlas against ulc and critical at three dampings of Table 1 (2-3 min of the quick
  # suite's time on a loaded 2-core machine).
  "--test atlas atlas_reproduces_the_single_point_commands"
  # Labels of scan, classify and trajectory against runs to t = 20000 around the folds at
  # lambda 0.3, 0.5, 1 (issue 31), 12 x 10 starts (2-3 min).
  "--test fold_truth labels_agree_with_long_runs_around_the_fold"
)
if [ "${1:-}" = --list ]; then
  printf '%s\n' "${checks[@]}"
  exit 0
fi
for c in "${checks[@]}"; do
  read -r -a words <<<"$c"
  name=${words[-1]}
  unset 'words[-1]'
  echo "long check: $name"
  cargo test --workspace "${words[@]}" -- --ignored --exact "$name"
done
