#!/usr/bin/env bash
# A one-node SLURM cluster on this machine (Debian's slurm-wlm and munge), for running the pipeline
# through its SLURM profile (workflow/profiles/slurm) and for tests/pipeline/test_slurm.py (.ci/run starts it).
#
#   sudo workflow/slurm/start-local-slurm.sh     # installs if missing, configures, starts, waits for idle
#   sudo workflow/slurm/stop-local-slurm.sh      # cancels every job, waits for them to end, stops the daemons
#
# Idempotent: a running, idle cluster with this configuration is left alone.  The node is this machine
# with SLURM_CPUS (default 2) CPUs and SLURM_MEM_MB (default 8000) MB.  No accounting database: the
# SLURM executor plugin queries job states with squeue (the profile's `slurm-status-command: squeue`),
# which MinJobAge = 3600 s below makes reliable for finished jobs.
set -euo pipefail

CPUS="${SLURM_CPUS:-2}"
MEM_MB="${SLURM_MEM_MB:-8000}"
CONF_DIR=/etc/slurm
LOG_DIR=/var/log/slurm
HOST="$(hostname -s)"

say() { echo "start-local-slurm: $*" >&2; }

if [ "$(id -u)" -ne 0 ]; then
    say "must run as root (installs packages and starts the SLURM daemons)"; exit 1
fi

if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null || ! command -v sbatch >/dev/null \
        || ! command -v munged >/dev/null; then
    # the daemons and the client commands of Debian's slurm-wlm, without the plugins of its other
    # packages (hdf5, influxdb, rrd, ...) that a one-node cluster does not use: 8 packages instead of 43
    pkgs=(slurmctld slurmd slurm-client munge)
    say "installing ${pkgs[*]} (apt-get)"
    export DEBIAN_FRONTEND=noninteractive
    install() { apt-get install -y -qq --no-install-recommends "${pkgs[@]}" </dev/null >/dev/null; }
    install 2>/dev/null || { apt-get update -qq </dev/null && install; }   # update only if the lists are missing or stale
fi

mkdir -p "$CONF_DIR" "$LOG_DIR" /var/spool/slurmctld /var/spool/slurmd /run/munge
conf="$(cat <<CONF
# written by bounce's workflow/slurm/start-local-slurm.sh: one node, this machine
ClusterName=bounce-local
SlurmctldHost=${HOST}
AuthType=auth/munge
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmctldLogFile=${LOG_DIR}/slurmctld.log
SlurmdLogFile=${LOG_DIR}/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MinJobAge=3600
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=30
NodeName=${HOST} CPUs=${CPUS} RealMemory=${MEM_MB} State=UNKNOWN
PartitionName=local Nodes=${HOST} Default=YES MaxTime=INFINITE State=UP
CONF
)"
changed=0
if [ ! -f "$CONF_DIR/slurm.conf" ] || [ "$(cat "$CONF_DIR/slurm.conf")" != "$conf" ]; then
    printf '%s\n' "$conf" > "$CONF_DIR/slurm.conf"
    changed=1
fi

# munge: the key is made by the package; the daemon runs as user munge
if [ ! -f /etc/munge/munge.key ]; then
    mungekey --create >/dev/null 2>&1 || create-munge-key -f >/dev/null
fi
chown -R munge:munge /etc/munge /run/munge /var/lib/munge /var/log/munge 2>/dev/null || true
chmod 0700 /etc/munge; chmod 0400 /etc/munge/munge.key
if ! munge -n </dev/null 2>/dev/null | unmunge >/dev/null 2>&1; then
    say "starting munged"
    runuser -u munge -- /usr/sbin/munged
fi

running() { [ -f "$1" ] && kill -0 "$(cat "$1")" 2>/dev/null; }
if [ "$changed" = 1 ]; then
    running /run/slurmctld.pid && kill "$(cat /run/slurmctld.pid)" && sleep 1
    running /run/slurmd.pid && kill "$(cat /run/slurmd.pid)" && sleep 1
fi
running /run/slurmctld.pid || { say "starting slurmctld"; slurmctld; }
running /run/slurmd.pid || { say "starting slurmd"; slurmd; }

for _ in $(seq 1 60); do
    state="$(sinfo -h -n "$HOST" -o %T 2>/dev/null || true)"
    case "$state" in
        idle|mixed|allocated) say "node $HOST is $state ($CPUS CPUs, $MEM_MB MB), $SECONDS s after this script started"; exit 0 ;;
        down*|drain*) scontrol update NodeName="$HOST" State=RESUME >/dev/null 2>&1 || true ;;
    esac
    sleep 1
done
say "the node did not become idle within 60 s; see $LOG_DIR/slurmctld.log and $LOG_DIR/slurmd.log"
exit 1
