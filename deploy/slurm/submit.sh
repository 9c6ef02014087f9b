#!/bin/bash
# Submits an hrisim run as N shards (a Slurm job array) and its merge as a job that starts when every
# shard has ended, whatever their verdicts (afterany: a failing gate in one shard is the merged
# report's to say). Prints the two job ids.
#   deploy/slurm/submit.sh N SCENARIO SEEDS RESULTS_DIR [hrisim run options...]
# e.g. deploy/slurm/submit.sh 8 scenarios/elevator.json 1-1000 /shared/nightly --gate 'collisions.max == 0'
# Options for sbatch (partition, account, time) go in SBATCH_* variables, e.g. SBATCH_PARTITION=cpu.
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: $0 N SCENARIO SEEDS RESULTS_DIR [hrisim run options...]" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
# The jobs start in RESULTS_DIR: the scenario and the folder by their full paths.
shards=$1 scenario=$(realpath "$2") seeds=$3 results=$(realpath -m "$4")
mkdir -p "$results"
array=$(sbatch --parsable --array="1-$shards" --chdir="$results" "$here/shard.sbatch" "$scenario" "$seeds" "$results" "${@:5}")
array=${array%%;*}
merge=$(sbatch --parsable --dependency="afterany:$array" --chdir="$results" "$here/merge.sbatch" "$results")
merge=${merge%%;*}
echo "shards: job $array (array 1-$shards); merge: job $merge; report: $results/report.json"
