#!/usr/bin/env bash
# Run a squeal scan or atlas as a SLURM job array of N shards, then merge the shards.
#
#   KIND=scan scripts/tools/slurm-array.sh scans/nu-sweep.toml 16 [out/nu-sweep.h5]
#   scripts/tools/slurm-array.sh scans/atlas-lambda-nu.toml 8       # an atlas: shards by points
#
# The spec's kind picks the command: an atlas spec (`squeal atlas`: no [grid] table, or one
# of the atlas-only tables [boundaries], [attractor], [operating_point], [disturbance]) runs
# `squeal atlas --shard K/N --no-render`, whose shards are whole lines of points and
# boundary searches; a spec with [sample] runs `squeal scan --shard K/N`. A spec with [grid]
# and none of those tables is valid for both (e.g. scans/atlas-maps.toml, an atlas with
# basin maps): the script then stops and asks for KIND=atlas or KIND=scan, which also
# overrides the guess elsewhere. `squeal merge` joins either kind.
#
# Run it from the repository root (relative paths: the spec, out/, logs/), on a filesystem
# every node sees (the tasks write their shard files and journals there, the merge job reads
# them). If a task fails, the merge job's dependency (afterok) can never be met: it is
# submitted with --kill-on-invalid-dep=yes, so SLURM cancels it instead of leaving it
# pending for ever; rerun the same command line: each task resumes its journal or skips its
# complete shard, and a new merge job is submitted.
# Submits an array job (one shard per task, each its own process and file) and a merge job
# that runs after all tasks succeed. Each task resumes its shard's journal when one exists,
# so a task that is requeued (by `scontrol requeue`, or by SLURM after a node failure or a
# preemption: the tasks are submitted with --requeue) finishes the blocks it had not stored
# instead of starting over; a task whose shard file is already complete does nothing.
# Tested on a real single-node cluster by scripts/ci/slurm-ci.sh.
# Extra sbatch options: SBATCH_OPTS="--partition=short --time=02:00:00"; CPUS per task
# (default 4); SQUEAL=/path/to/squeal (default target/release/squeal).
set -euo pipefail
usage="usage: slurm-array.sh SPEC.toml N [OUT.h5]"
spec=${1:?$usage}
n=${2:?$usage}
out=${3:-out/$(basename "${spec%.toml}").h5}
bin=${SQUEAL:-target/release/squeal}
case $n in '' | *[!0-9]* | 0) echo "N = '$n': expected a number of shards >= 1" >&2; exit 2 ;; esac
[ -f "$spec" ] || { echo "no spec file $spec" >&2; exit 2; }
[ -x "$bin" ] || { echo "build first: cargo build --release (or set SQUEAL=/path/to/squeal)" >&2; exit 2; }
case $out in *.h5) ;; *) echo "output $out: expected a name ending in .h5" >&2; exit 2 ;; esac
kind=${KIND:-}
if [ -z "$kind" ]; then
  if grep -Eq '^[[:space:]]*\[(boundaries|attractor|operating_point|disturbance)\]' "$spec"; then
    kind=atlas
  elif grep -q '^[[:space:]]*\[sample\]' "$spec"; then
    kind=scan
  elif ! grep -q '^[[:space:]]*\[grid\]' "$spec"; then
    kind=atlas
  else
    echo "$spec is valid as a scan and as an atlas (it has [grid]): set KIND=scan or KIND=atlas" >&2
    exit 2
  fi
fi
case $kind in
  atlas) cmd="atlas" extra="--no-render" ;;
  scan) cmd="scan" extra="" ;;
  *) echo "KIND=$kind: expected atlas or scan" >&2; exit 2 ;;
esac
mkdir -p "$(dirname "$out")" logs
stem=${out%.h5}
q() { printf '%q' "$1"; }
# One task: resume the shard's journal if there is one; skip a shard that is complete.
task="k=\$SLURM_ARRAY_TASK_ID; f=$(q "$stem").shard\$k.h5; \
if [ -e \"\$f.journal\" ]; then r=--resume; \
elif [ -e \"\$f\" ]; then echo \"\$f is complete\"; exit 0; else r=; fi; \
exec $(q "$bin") $cmd $(q "$spec") -o \"\$f\" --shard \$k/$n --threads \$SLURM_CPUS_PER_TASK --quiet $extra \$r"
# shellcheck disable=SC2086 # SBATCH_OPTS is a list of options
array=$(sbatch --parsable ${SBATCH_OPTS:-} --array=1-"$n" --cpus-per-task="${CPUS:-4}" --requeue \
  --open-mode=append --job-name=squeal-shards --output=logs/squeal-%A_%a.out --wrap "$task")
array=${array%%;*}
shards=$(for k in $(seq 1 "$n"); do printf '%s ' "$(q "$stem.shard$k.h5")"; done)
# shellcheck disable=SC2086
merge=$(sbatch --parsable ${SBATCH_OPTS:-} --dependency=afterok:"$array" --kill-on-invalid-dep=yes \
  --job-name=squeal-merge \
  --output=logs/squeal-merge-%j.out --wrap "$(q "$bin") merge $shards -o $(q "$out")")
merge=${merge%%;*}
echo "submitted array $array ($n $kind shards) and merge job $merge into $out"
