#!/usr/bin/env bash
# The long physics checks: tests too slow for the suite a developer runs often
# (`cargo test --workspace`), marked `#[ignore]` there and run here by exact name. .ci/run
# calls this after the quick suite. Each line: the test target (`--test NAME`, or `--lib` for
# a library's unit test), then the test. They run with
# `--workspace`, as the quick suite does, so cargo reuses its build (selecting one package
# unifies features differently and rebuilds the dependencies).
#
#   scripts/ci/long-checks.sh          # all of them
#   scripts/ci/long-checks.sh --list   # their names
set -euo pipefail
cd "$(dirname "$0")/../.."
checks=(
  # bSTAB's published basin stability at 20 belt speeds, 655,360 cells (tests/e2e/bstab_friction.rs).
  "--test e2e bstab_friction::squeal_matches_the_published_basin_stability"
  # Early stopping against runs to settlement off the paper's parameters, 4 x 2 scans of 64 x 64.
  "--test scanning off_paper::early_stopping_agrees_with_settlement_off_the_paper"
  # The transient lifetimes above two folds of an atlas, 8 band starts at 10 dampings each.
  "--test e2e atlas::an_atlas_measures_transient_lifetimes_above_each_fold"
  # The atlas against ulc and critical at three dampings of Table 1 (2-3 min of the quick
  # suite's time on a loaded 2-core machine).
  "--test e2e atlas::atlas_reproduces_the_single_point_commands"
  # Labels of scan, classify and trajectory against runs to t = 20000 around the folds at
  # lambda 0.3, 0.5, 1, 12 x 10 starts (2-3 min).
  "--test scanning fold_truth::labels_agree_with_long_runs_around_the_fold"
  # Fates and labels against runs to t = 20000 where steady slip is unstable (k > 1), ten
  # starts at each of lambda 0.1, 0.2, 0.3 (tau = 1, phi = 0.9).
  "--test scanning unstable_steady::fates_agree_with_long_runs_where_steady_slip_is_unstable"
  # Labels, the crisis and the band's trap near the fold against runs to settlement on every
  # path (scan, classify, trajectory), and the band's transient lifetimes against direct runs.
  "--test scanning edge::labels_near_the_fold_agree_with_long_runs_on_every_path"
  "--test scanning edge::the_crisis_lies_where_long_runs_put_it_and_far_starts_stop_below_it"
  "--test scanning edge::the_band_is_trapped_below_the_crisis_and_leaks_above"
  "--test scanning transient::band_lifetimes_match_direct_long_runs"
  # Starts on the edge of McMillan's checked region settle when run to the end.
  "--test scanning shortcuts::runs_from_mcmillans_region_edge_settle"
  # The brake's critical damping and fold (c in N s/m) against runs from its spread of
  # starts, and random samples' basin stability against the grid's within three standard
  # errors.
  "--test e2e physical_outputs::the_brakes_critical_damping_and_fold_agree_with_runs"
  "--test e2e basin_stability::random_samples_agree_with_the_grid_within_three_standard_errors"
  # The located cycle against the label boundary of a fine scan, and early stopping against
  # runs to settlement, on the shipped scans.
  "--test scanning science::cycle_matches_the_label_boundary_of_a_fine_scan"
  "--test scanning science::early_stopping_matches_runs_to_settlement"
  # The shipped chart's folds hold the crisis computed at dt/2 and with the longer horizon.
  "--test scanning fold_crisis::the_charts_folds_hold_the_crisis_at_half_dt_and_with_the_longer_horizon"
  # The clamped brake's fold the same however it is asked for (atlas, critical --fold, c or nu).
  "--test scanning fold_crisis::the_brakes_fold_agrees_however_it_is_asked_for"
  # The default step's figures within 0.1% of their dt -> 0 limits.
  "--test scanning accuracy::default_step_is_within_a_tenth_of_a_percent"
  # The end-to-end runs slowest in the quick suite (each a minute or more on 2 cores): the
  # README's tour run as written, the clamped brake stated by flags and its atlas summary in
  # SI, an atlas's maps over its parameters (with shards and merge), an atlas killed and
  # resumed, a belt-speed sweep end to end.
  "--test e2e cli_doc::the_readme_tour_prints_what_it_shows"
  "--test e2e cli_ulc_critical::physical_flags_give_si_answers"
  "--test e2e physical_outputs::physical_atlas_summary_gives_the_fold_uncertainty_in_both_units"
  "--test e2e atlas_maps::maps_are_stored_over_the_parameters_with_the_cell_schema"
  "--test e2e atlas_files::resume_after_a_kill_gives_the_same_file"
  "--test e2e cli_scan_cases::a_lambda_sweep_end_to_end"
  # The boundary searches: the critical damping of rest within the fold's uncertainty on the
  # shipped chart, shared searches bit for bit the separate ones, and the runs' critical
  # damping at Table 1 against the cycle's (unit tests of squeal-scan).
  "--lib atlas::boundary::tests::the_critical_damping_of_rest_lies_within_the_folds_uncertainty"
  "--lib atlas::boundary::tests::shared_boundaries_equal_separate_ones"
  "--lib fates::tests::the_runs_find_the_cycles_critical_damping_at_table_1"
)
if [ "${1:-}" = --list ]; then
  printf '%s\n' "${checks[@]}"
  exit 0
fi
# One cargo call per test target, with every check of that target as an exact filter, so
# that the harness runs two of them at a time on two cores (one call per check left a core
# idle).
declare -A names=()
order=()
for c in "${checks[@]}"; do
  read -r -a words <<<"$c"
  name=${words[-1]}
  unset 'words[-1]'
  target="${words[*]}"
  [ -n "${names[$target]+x}" ] || order+=("$target")
  names[$target]="${names[$target]:-} $name"
done
for target in "${order[@]}"; do
  read -r -a filters <<<"${names[$target]}"
  read -r -a sel <<<"$target"
  echo "long checks ($target):${names[$target]}"
  cargo test --workspace "${sel[@]}" -- --ignored --exact "${filters[@]}"
done
