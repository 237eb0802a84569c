#!/usr/bin/env bash
# Submits a sharded softwrist job to Slurm: an array of N shards and a merge job that runs once they have all ended.
#   scripts/slurm/submit.sh CONFIG --shards N --out DIR [options] [-- SBATCH_OPTION...]
#       softwrist run CONFIG --shard K/N for K = 1..N, merged into DIR/merged (softwrist merge)
#   scripts/slurm/submit.sh diagnose-bench --shards N --out DIR [--bench "OPTIONS"] [options] [-- SBATCH_OPTION...]
#       softwrist diagnose-bench --generator independent OPTIONS --shard K/N, merged into DIR/merged.json
# Options:
#   --softwrist PATH   the softwrist executable (default: build/release/src/cli/softwrist, else softwrist on PATH);
#                      the compute nodes must see it and DIR at the same paths (a shared file system)
#   --cpus N           CPUs per shard (--cpus-per-task; the shard's --jobs), default 1
#   --resume           submit only the shards of DIR that have not succeeded, then the merge
#   --wait             wait for the merge and exit with its status (sbatch --wait)
#   -- SBATCH_OPTION   passed to both sbatch calls: --partition=P, --time=HH:MM:SS, --mem=4G, --account=A, ...
# Prints the array's and the merge's job ids. The merge names every shard that failed and why (DIR/merge.failed).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
usage() { sed -n 2,14p "$0" >&2; exit 2; }
[ $# -ge 1 ] || usage
target=$1
shift
count="" out="" softwrist="" cpus=1 resume=0 wait=0 bench="" sbatch_options=()
while (($#)); do
  case "$1" in
    --shards) count=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --softwrist) softwrist=$2; shift 2 ;;
    --cpus) cpus=$2; shift 2 ;;
    --bench) bench=$2; shift 2 ;;
    --resume) resume=1; shift ;;
    --wait) wait=1; shift ;;
    --) shift; sbatch_options=("$@"); break ;;
    -h|--help) usage ;;
    *) echo "submit.sh: unknown option '$1'" >&2; usage ;;
  esac
done
[[ "$count" =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: --shards N needs a whole number >= 1 (got '$count')" >&2; exit 2; }
[[ "$cpus" =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: --cpus N needs a whole number >= 1 (got '$cpus')" >&2; exit 2; }
[ -n "$out" ] || { echo "submit.sh: --out DIR is required" >&2; exit 2; }
command -v sbatch >/dev/null || { echo "submit.sh: sbatch not found (is this a Slurm login node?)" >&2; exit 2; }

if [ -z "$softwrist" ]; then
  softwrist="$here/../../build/release/src/cli/softwrist"
  [ -x "$softwrist" ] || softwrist=$(command -v softwrist || true)
fi
[ -n "$softwrist" ] && [ -x "$softwrist" ] || { echo "submit.sh: no softwrist executable (--softwrist PATH)" >&2; exit 2; }
softwrist=$(realpath "$softwrist")
mkdir -p "$out/logs" "$out/status"
out=$(realpath "$out")

if [ "$target" = diagnose-bench ]; then
  kind=diagnose-bench
  read -r -a args <<<"$bench"
  # The shards run in DIR (--chdir), where diagnose-bench's default rig files (relative to the repository) are not.
  rigs="$here/../../experiments/independent_device"
  [[ " ${args[*]} " == *" --torque-rig "* ]] || args+=(--torque-rig "$(realpath "$rigs/torque_rig.json")")
  [[ " ${args[*]} " == *" --prototype "* ]] || args+=(--prototype "$(realpath "$rigs/prototype.json")")
  args=(--generator independent "${args[@]}")
else
  [ -f "$target" ] || { echo "submit.sh: no config file '$target'" >&2; exit 2; }
  [ -z "$bench" ] || { echo "submit.sh: --bench is for diagnose-bench" >&2; exit 2; }
  kind=run
  args=("$(realpath "$target")")
fi

# The shards to submit: all, or with --resume those without a success record.
tasks=()
for ((k = 1; k <= count; ++k)); do
  if ((resume)) && [ -f "$out/status/shard-$k.ok" ]; then continue; fi
  tasks+=("$k")
done
dependency=()
if ((${#tasks[@]} > 0)); then
  array=$(IFS=,; echo "${tasks[*]}")
  array_id=$(sbatch --parsable --array="$array" --cpus-per-task="$cpus" --chdir="$out" \
    --output="$out/logs/slurm-shard-%a.out" "${sbatch_options[@]}" \
    "$here/shard.sbatch" "$out" "$kind" "$count" "$softwrist" "${args[@]}")
  array_id=${array_id%%;*}
  echo "submit.sh: shards $array of $count: job $array_id"
  # afterany, not afterok: with afterok a failed shard leaves the merge pending forever (DependencyNeverSatisfied)
  # and nobody is told; the merge instead runs and names the shards that failed, and why.
  dependency=(--dependency="afterany:$array_id")
else
  echo "submit.sh: every shard of $out has succeeded; only the merge is submitted"
fi
wait_option=()
((wait)) && wait_option=(--wait)
set +e
merge_id=$(sbatch --parsable "${dependency[@]}" --chdir="$out" --output="$out/logs/slurm-merge.out" \
  "${sbatch_options[@]}" "${wait_option[@]}" "$here/merge.sbatch" "$out" "$kind" "$count" "$softwrist")
status=$?
set -e
merge_id=${merge_id%%;*}
echo "submit.sh: merge: job $merge_id -> $out/$([ "$kind" = run ] && echo merged || echo merged.json)"
if ((wait)); then
  if ((status != 0)); then
    cat "$out/merge.failed" >&2 2>/dev/null || echo "submit.sh: the merge job failed (exit $status)" >&2
  fi
  exit $status
fi
