#!/usr/bin/env bash
# Debian's SLURM (22.05 on bookworm) for the one-node cluster that tests/slurm_shards.sh starts:
# slurmctld, slurmd and the client commands. The packages' own services are not used (the test
# runs its daemons with a configuration of its own, auth/none, no munge), so they are stopped if
# the package started them. Idempotent.
set -euo pipefail
if command -v slurmctld >/dev/null && command -v slurmd >/dev/null && command -v sbatch >/dev/null; then
  exit 0
fi
export DEBIAN_FRONTEND=noninteractive
# Another apt-get may hold the lock (shared machines, CI images warming up): wait for it.
apt_get() { apt-get -o DPkg::Lock::Timeout=600 "$@"; }
apt_get update -qq
apt_get install -y -qq --no-install-recommends slurm-wlm slurm-client >/dev/null
# No systemd in containers: invoke-rc.d may have started nothing, or the packaged daemons with
# /etc/slurm/slurm.conf (absent): stop what runs under the package's own pid files only.
for pidfile in /run/slurmctld.pid /run/slurmd.pid /var/run/slurmctld.pid /var/run/slurmd.pid; do
  if [ -f "$pidfile" ]; then kill "$(cat "$pidfile")" 2>/dev/null || true; fi
done
command -v slurmctld >/dev/null && command -v slurmd >/dev/null && command -v sbatch >/dev/null
