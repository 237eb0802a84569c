#!/usr/bin/env bash
# Starts a one-node Slurm on this machine (munged, slurmctld and slurmd in the foreground, on localhost, configured
# in a temporary directory, stopped at the end), and checks scripts/slurm/submit.sh against it:
#   1. a 3-shard sweep of experiments/torque_validation.json and its merge equal a one-process run byte for byte;
#   2. a shard that fails makes the merge fail, naming that shard and its reason, and the merge is not written;
#   3. --resume re-runs only that shard, and the merge then equals the one-process run.
# Exit 0 with a last line "slurm selftest: ok, 3 shards, T s"; 77 (skipped) where Slurm or munge is not installed
# (Debian: slurmctld slurmd slurm-client munge; bash scripts/setup.sh --tests installs them).
#   bash scripts/slurm/selftest.sh [--softwrist PATH] [--keep]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
softwrist="$root/build/release/src/cli/softwrist" keep=0
while (($#)); do
  case "$1" in
    --softwrist) softwrist=$2; shift 2 ;;
    --keep) keep=1; shift ;;
    *) echo "selftest.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
done
for tool in munged mungekey slurmctld slurmd sbatch sinfo scancel; do
  command -v "$tool" >/dev/null || { echo "slurm selftest: skipped, '$tool' is not installed"; exit 77; }
done
[ -x "$softwrist" ] || { echo "slurm selftest: no softwrist executable at $softwrist (--softwrist PATH)" >&2; exit 2; }
softwrist=$(realpath "$softwrist")
start=$SECONDS

tmp=$(mktemp -d /tmp/softwrist-slurm.XXXXXX)
pids=()
cleanup() {
  # Only ever the jobs of this test's own cluster: on a real cluster's login node SLURM_CONF would otherwise be the
  # site's, and the user's real jobs would go.
  if [ "${SLURM_CONF:-}" = "$tmp/slurm.conf" ]; then scancel --quiet --user="$(id -un)" 2>/dev/null || true; fi
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  if ((keep)); then echo "slurm selftest: kept $tmp"; else rm -rf "$tmp"; fi
}
trap cleanup EXIT
trap 'exit 143' TERM INT  # a CTest time-out or Ctrl-C still stops the daemons
fail() {
  echo "slurm selftest: FAILED: $*" >&2
  for log in "$tmp"/log/*.log; do echo "--- $log" >&2; tail -n 15 "$log" >&2; done
  exit 1
}

# Three free TCP ports on the loopback (controller, node daemon, srun), chosen by the kernel.
read -r ctld_port slurmd_port srun_port < <(python3 -c '
import socket
socks = [socket.socket() for _ in range(3)]
for s in socks: s.bind(("127.0.0.1", 0))
print(*[s.getsockname()[1] for s in socks])')
mkdir -p "$tmp/log" "$tmp/state" "$tmp/spool" "$tmp/munge"
chmod 711 "$tmp/munge"  # munged wants its socket's directory searchable by every client
dd if=/dev/urandom of="$tmp/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$tmp/munge/munge.key"
socket="$tmp/munge/munge.socket"
munged --foreground --force --key-file="$tmp/munge/munge.key" --socket="$socket" --pid-file="$tmp/munge/munged.pid" \
  --seed-file="$tmp/munge/munged.seed" --log-file="$tmp/log/munged.log" >"$tmp/log/munged.out" 2>&1 &
pids+=($!)

node=$(hostname -s)
user=$(id -un)
cpus=$(nproc)
memory_mb=$(($(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2))
export SLURM_CONF="$tmp/slurm.conf"
cat >"$SLURM_CONF" <<CONF
ClusterName=softwrist-selftest
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SrunPortRange=$srun_port-$srun_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
SlurmdTimeout=60
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory_mb State=UNKNOWN
PartitionName=selftest Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF

for ((i = 0; i < 100; ++i)); do [ -S "$socket" ] && break; sleep 0.1; done
[ -S "$socket" ] || fail "munged did not start"
slurmctld -D -i -f "$SLURM_CONF" >"$tmp/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >"$tmp/log/slurmd.out" 2>&1 &
pids+=($!)
for ((i = 0; i < 600; ++i)); do
  state=$(sinfo --noheader --nodes="$node" --format=%t 2>/dev/null || true)
  [[ "$state" == idle* ]] && break
  sleep 0.1
done
[[ "${state:-}" == idle* ]] || fail "the node did not come up (state '${state:-none}')"
echo "slurm selftest: one-node Slurm up ($(sinfo --version), $cpus CPUs) after $((SECONDS - start)) s"

config="$root/experiments/torque_validation.json"
"$softwrist" run "$config" --out "$tmp/single" --jobs 1 --quiet >/dev/null || fail "the one-process run failed"
same_as_single() {  # every file of the merged run equals the one-process run's, byte for byte
  local merged=$1 file
  for file in $(cd "$tmp/single" && find . -type f | sort); do
    cmp -s "$tmp/single/$file" "$merged/$file" || { echo "differs: $file"; return 1; }
  done
  [ "$(cd "$tmp/single" && find . -type f | sort)" = "$(cd "$merged" && find . -type f | sort)" ] ||
    { echo "other files"; return 1; }
}

# 1. A sweep and its merge.
"$root/scripts/slurm/submit.sh" "$config" --shards 3 --out "$tmp/sweep" --softwrist "$softwrist" --wait \
  || fail "the sharded sweep failed"
same_as_single "$tmp/sweep/merged" || fail "the merged sweep differs from the one-process run"
echo "slurm selftest: 3 shards merged equal the one-process run"

# 2. Shard 2 fails (a softwrist that fails on it), the merge names it and writes nothing.
cat >"$tmp/failing_softwrist" <<WRAPPER
#!/usr/bin/env bash
for a in "\$@"; do [ "\$a" = 2/3 ] && { echo "error: simulated node failure on shard 2" >&2; exit 3; }; done
exec "$softwrist" "\$@"
WRAPPER
chmod +x "$tmp/failing_softwrist"
if "$root/scripts/slurm/submit.sh" "$config" --shards 3 --out "$tmp/faulty" --softwrist "$tmp/failing_softwrist" \
  --wait 2>"$tmp/faulty.err"; then
  fail "the merge succeeded although shard 2 failed"
fi
grep -q "shard 2 of 3 failed: exit 3" "$tmp/faulty/merge.failed" || fail "the merge does not name shard 2's exit"
grep -q "simulated node failure on shard 2" "$tmp/faulty/merge.failed" || fail "the merge does not give the reason"
grep -q "shard 1 of 3\|shard 3 of 3" "$tmp/faulty/merge.failed" && fail "the merge blames a shard that succeeded"
[ ! -e "$tmp/faulty/merged" ] || fail "a merge was written without shard 2"
echo "slurm selftest: a failed shard is named by the merge: $(sed -n 2p "$tmp/faulty/merge.failed" | sed 's/^ *//')"

# 3. --resume re-runs shard 2 only.
before=$(stat -c %Y "$tmp/faulty/shard-1/trials.csv" "$tmp/faulty/shard-3/trials.csv")
"$root/scripts/slurm/submit.sh" "$config" --shards 3 --out "$tmp/faulty" --softwrist "$softwrist" --resume --wait \
  >"$tmp/resume.out" || fail "the resumed sweep failed"
grep -q "shards 2 of 3" "$tmp/resume.out" || fail "--resume did not submit shard 2 alone: $(cat "$tmp/resume.out")"
[ "$before" = "$(stat -c %Y "$tmp/faulty/shard-1/trials.csv" "$tmp/faulty/shard-3/trials.csv")" ] ||
  fail "--resume ran a shard that had succeeded"
same_as_single "$tmp/faulty/merged" || fail "the resumed merge differs from the one-process run"
echo "slurm selftest: --resume re-ran shard 2 only; the merge equals the one-process run"
echo "slurm selftest: ok, 3 shards, $((SECONDS - start)) s"
