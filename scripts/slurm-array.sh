#!/usr/bin/env bash
# Run a squeal scan as a SLURM job array of N shards, then merge the shards.
#
#   scripts/slurm-array.sh scans/nu-sweep.toml 16 [out/nu-sweep.h5]
#
# Submits an array job (one shard per task, each its own process and file, each resumable
# with --resume if a node dies) and a merge job that runs after all tasks succeed.
# Extra sbatch options: SBATCH_OPTS="--partition=short --time=02:00:00".
set -euo pipefail
spec=${1:?usage: slurm-array.sh SPEC.toml N [OUT.h5]}
n=${2:?usage: slurm-array.sh SPEC.toml N [OUT.h5]}
out=${3:-out/$(basename "${spec%.toml}").h5}
bin=${SQUEAL:-target/release/squeal}
[ -x "$bin" ] || { echo "build first: cargo build --release (or set SQUEAL=/path/to/squeal)" >&2; exit 2; }
mkdir -p "$(dirname "$out")" logs
stem=${out%.h5}
array=$(sbatch --parsable ${SBATCH_OPTS:-} --array=1-"$n" --cpus-per-task="${CPUS:-4}" \
  --job-name=squeal-shards --output=logs/squeal-%A_%a.out \
  --wrap "k=\$SLURM_ARRAY_TASK_ID; f=${stem}.shard\$k.h5; if [ -e \$f.journal ]; then r=--resume; else r=; fi; \
          $bin scan $spec -o \$f --shard \$k/$n --threads \$SLURM_CPUS_PER_TASK --quiet \$r")
shards=$(for k in $(seq 1 "$n"); do printf '%s ' "${stem}.shard$k.h5"; done)
sbatch ${SBATCH_OPTS:-} --dependency=afterok:"$array" --job-name=squeal-merge \
  --output=logs/squeal-merge-%j.out --wrap "$bin merge $shards -o $out"
echo "submitted array $array ($n shards) and its merge into $out"
