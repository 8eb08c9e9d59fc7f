#!/usr/bin/env bash
# Stop the one-node SLURM of start-local-slurm.sh: cancel every job, wait until the node has ended them
# (a job leaves squeue only once slurmd has killed its processes), then stop slurmd, slurmctld and munged
# by their pid files and wait for them to exit.
set -euo pipefail
say() { echo "stop-local-slurm: $*" >&2; }
running() { [ -f "$1" ] && kill -0 "$(cat "$1")" 2>/dev/null; }

jobs=()
if running /run/slurmctld.pid && running /run/slurmd.pid; then
    mapfile -t jobs < <(squeue -h -o %i 2>/dev/null || true)
fi
if [ "${#jobs[@]}" -gt 0 ]; then
    say "cancelling ${#jobs[@]} job(s)"
    scancel "${jobs[@]}" || true
    for _ in $(seq 1 60); do
        [ -z "$(squeue -h -o %i 2>/dev/null)" ] && break
        sleep 1
    done
    left="$(squeue -h -o '%i %T' 2>/dev/null || true)"
    [ -z "$left" ] || say "jobs still listed after 60 s, stopping anyway: $left"
fi
for pidfile in /run/slurmd.pid /run/slurmctld.pid /run/munge/munged.pid; do
    if running "$pidfile"; then
        pid="$(cat "$pidfile")"
        kill "$pid"
        for _ in $(seq 1 30); do kill -0 "$pid" 2>/dev/null || break; sleep 0.5; done
        say "stopped $(basename "$pidfile" .pid)"
    fi
done
