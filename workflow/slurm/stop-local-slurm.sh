#!/usr/bin/env bash
# Stop the one-node SLURM of start-local-slurm.sh (slurmctld, slurmd, munged), by their pid files.
set -euo pipefail
for pidfile in /run/slurmd.pid /run/slurmctld.pid /run/munge/munged.pid; do
    if [ -f "$pidfile" ] && kill -0 "$(cat "$pidfile")" 2>/dev/null; then
        kill "$(cat "$pidfile")"
        echo "stop-local-slurm: stopped $(basename "$pidfile" .pid)" >&2
    fi
done
