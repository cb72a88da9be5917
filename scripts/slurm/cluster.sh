#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for trying the batch scripts and for
# scripts/slurm/selftest.sh: Debian's slurm-wlm and munge (installed when missing), a munge key
# and a generated slurm.conf in a private folder, munged, slurmctld and slurmd listening on
# localhost only. Nothing under /etc is changed. The daemons run as root (slurmd starts job
# steps as their user), through sudo when the caller is not root; jobs run as the caller.
#
#   source scripts/slurm/cluster.sh; cluster_start DIR   # exports SLURM_CONF for sbatch & co.
#   cluster_stop DIR                                     # stops exactly the daemons it started
set -euo pipefail

cluster_log() { echo "[slurm] $*" >&2; }

# Runs a command as root (sudo when not root already), keeping SLURM_CONF.
as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo env SLURM_CONF="${SLURM_CONF:-}" "$@"; fi
}

cluster_install() {
  local sudo="" missing=()
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  for p in slurm-wlm munge; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ "${#missing[@]}" -gt 0 ]; then
    cluster_log "installing ${missing[*]}"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
}

# Two free TCP ports on localhost (slurmctld, slurmd).
cluster_ports() {
  python3 - <<'PY'
import socket
socks = [socket.socket() for _ in range(2)]
for s in socks:
    s.bind(("127.0.0.1", 0))
print(" ".join(str(s.getsockname()[1]) for s in socks))
PY
}

cluster_start() {
  local dir="$1"
  cluster_install
  if [ "$(id -u)" -ne 0 ] && ! sudo -n true 2>/dev/null; then
    echo "error: scripts/slurm/cluster.sh: the Slurm daemons must run as root (slurmd starts job steps as their user): run as root or with password-less sudo" >&2
    return 2
  fi
  mkdir -p "$dir"/{state,spool,munge,log}
  chmod 755 "$dir" "$dir/munge"
  as_root sh -c "umask 077 && dd if=/dev/urandom of='$dir/munge/munge.key' bs=1024 count=1 status=none"
  as_root munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
    --pid-file="$dir/munge/munged.pid" --log-file="$dir/log/munged.log" \
    --seed-file="$dir/munge/munged.seed"
  local host cpus mem ports
  host="$(hostname -s)"
  cpus="$(nproc)"
  mem="$(awk '/MemTotal/ {print int($2 / 1024 * 0.9)}' /proc/meminfo)"
  read -r -a ports <<< "$(cluster_ports)"
  cat > "$dir/slurm.conf" <<CONF
ClusterName=keylo-selftest
SlurmctldHost=${host}(127.0.0.1)
SlurmctldPort=${ports[0]}
SlurmdPort=${ports[1]}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=${dir}/munge/munge.socket
StateSaveLocation=${dir}/state
SlurmdSpoolDir=${dir}/spool/%n
SlurmctldPidFile=${dir}/slurmctld.pid
SlurmdPidFile=${dir}/slurmd.pid
SlurmctldLogFile=${dir}/log/slurmctld.log
SlurmdLogFile=${dir}/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MinJobAge=600
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
NodeName=${host} NodeAddr=127.0.0.1 CPUs=${cpus} RealMemory=${mem} State=UNKNOWN
PartitionName=main Nodes=${host} Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF="$dir/slurm.conf"
  as_root slurmctld -i
  as_root slurmd
  local i
  for i in $(seq 1 60); do
    if sinfo -h -N -o '%T' 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then
      cluster_log "one-node cluster up: ${host}, ${cpus} CPUs, ${mem} MB (SLURM_CONF=$SLURM_CONF)"
      return 0
    fi
    sleep 1
  done
  echo "error: the Slurm node did not become idle in 60 s; logs in $dir/log" >&2
  sinfo -N -l >&2 || true
  tail -5 "$dir"/log/*.log >&2 || true
  return 1
}

cluster_stop() {
  local dir="$1" f
  for f in "$dir/slurmd.pid" "$dir/slurmctld.pid" "$dir/munge/munged.pid"; do
    if [ -s "$f" ]; then as_root kill "$(cat "$f")" 2>/dev/null || true; fi
  done
  sleep 1
  cluster_log "daemons stopped"
}
