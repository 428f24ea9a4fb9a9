#!/usr/bin/env bash
# A sharded bake on a real scheduler (issue 25): starts a one-node SLURM cluster (slurmctld and
# slurmd as root, auth/none and cred/none, no munge) with a configuration in a temporary folder,
# submits `sbatch --array=0-3` of `exao bake --shard auto` and a merge job with
# --dependency=afterok, checks the merged files against one unsharded bake byte for byte, and
# stops the daemons. Exit 77 (CTest: skipped) when SLURM is not installed or not root.
#
#   bash tests/slurm_shards.sh build/cli/exao
set -euo pipefail

exao=$(realpath "${1:?usage: slurm_shards.sh EXAO_BINARY}")
for tool in slurmctld slurmd sbatch squeue scontrol; do
  if ! command -v "$tool" >/dev/null; then
    echo "SKIPPED: $tool not found (bash scripts/install-slurm.sh installs SLURM)"
    exit 77
  fi
done
if [ "$(id -u)" != 0 ]; then
  echo "SKIPPED: the one-node cluster runs slurmd as root"
  exit 77
fi

work=$(mktemp -d /tmp/exao-slurm.XXXXXX)
chmod 755 "$work"
pids=()
cleanup() {
  # Only the daemons this script started, by their process ids.
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT

node=$(hostname -s)
# Ports of this run only, so that two runs on one machine do not meet.
base=$((20000 + ($$ % 20000)))
mkdir -p "$work/state" "$work/spool" "$work/one" "$work/farm"
export SLURM_CONF="$work/slurm.conf"
cat > "$SLURM_CONF" <<CONF
ClusterName=exao-test
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$base
SlurmdPort=$((base + 1))
AuthType=auth/none
CredType=cred/none
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
ReturnToService=2
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
MinJobAge=600
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=exao Nodes=$node Default=YES MaxTime=INFINITE State=UP OverSubscribe=FORCE:4
CONF

slurmctld -D -c -f "$SLURM_CONF" > "$work/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -N "$node" -f "$SLURM_CONF" > "$work/slurmd.out" 2>&1 &
pids+=($!)

# The node is up when sinfo says idle (bounded: a broken configuration fails, never hangs).
for _ in $(seq 1 120); do
  if sinfo -h -N -o '%T' 2>/dev/null | grep -q idle; then break; fi
  sleep 0.5
done
if ! sinfo -h -N -o '%T' 2>/dev/null | grep -q idle; then
  echo "FAILED: the one-node cluster did not come up"
  tail -n 20 "$work/slurmctld.log" "$work/slurmd.log" 2>/dev/null || true
  exit 1
fi

bake=(bake room --texture 512 -n 32 --preview "" -o room.glb)
(cd "$work/one" && "$exao" "${bake[@]}" > bake.log)

# One array task per shard, K and N from SLURM's variables; the merge waits for all of them.
array=$(sbatch --parsable --array=0-3 --chdir="$work/farm" --output="$work/farm/shard-%a.log" \
  --wrap "exec '$exao' bake room --texture 512 -n 32 --preview '' -o room.glb --shard auto")
merge=$(sbatch --parsable --dependency=afterok:"$array" --chdir="$work/farm" --output="$work/farm/merge.log" \
  --wrap "exec '$exao' merge room.glb.part-*-of-0004.exao -o room.glb")
echo "submitted array $array and merge $merge"

# Done when the merge job has left the queue (bounded by the test's CTest timeout as well).
for _ in $(seq 1 1200); do
  state=$(scontrol show job "$merge" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | cut -d= -f2 || true)
  case "$state" in COMPLETED|FAILED|CANCELLED|TIMEOUT|NODE_FAIL|OUT_OF_MEMORY) break ;; esac
  sleep 0.5
done
echo "merge job: $state"
for k in 0 1 2 3; do cat "$work/farm/shard-$k.log"; done
cat "$work/farm/merge.log" || true
if [ "$state" != COMPLETED ]; then
  echo "FAILED: the merge job ended $state"
  exit 1
fi
# Every task computed a part of the receivers (the array really was spread).
for k in 0 1 2 3; do
  if ! grep -Eq "^shard $k/4: [1-9][0-9]* of" "$work/farm/shard-$k.log"; then
    echo "FAILED: array task $k did not compute part $k of 4"
    exit 1
  fi
done
status=0
for file in room.glb room_ao.png room_ao.exr; do
  if cmp "$work/one/$file" "$work/farm/$file"; then
    echo "identical: $file"
  else
    echo "FAILED: $file differs from the unsharded bake"
    status=1
  fi
done
exit $status
