"""The run's hooks, which run only in the snakemake the user started (never in the jobs).

A local run (`--cores N`) starts the jobs' fork server (bounce.pipeline.taskserver: each job's imports paid
once per run) and stops it at exit.  A run through a cluster executor (workflow/profiles/slurm) gets what it
needs beyond the executor's defaults: SIGTERM cancels its jobs, the profile's no-account setting holds, and
an interrupted run leaves no job queued."""

import atexit
import getpass
import signal
import subprocess

from bounce.pipeline import taskserver


def _slurm_executor():
    """The SLURM executor plugin's executor of this run, or None (local run, other executor)."""
    executor = getattr(getattr(workflow, "scheduler", None), "_executor", None)
    return executor if type(executor).__module__ == "snakemake_executor_plugin_slurm" else None


onstart:
    if workflow.local_exec:
        atexit.register(taskserver.stop, taskserver.start())
    else:
        # SIGTERM (`kill`, a batch system or CI stopping the run) does what Ctrl-C does: cancel every job
        # this run submitted, queued or running, and stop.  Snakemake's own SIGTERM handler waits for all
        # of them, and on a cluster the queued ones may wait for hours; a job cut off is rerun next time
        # (the profile sets rerun-incomplete; every output is written atomically).
        signal.signal(signal.SIGTERM, signal.default_int_handler)
    executor = _slurm_executor()
    if executor is not None and workflow.executor_settings.no_account and executor._fallback_account_arg is None:
        # `slurm-no-account: true` (the profile): submit without -A.  The plugin (2.8.0) accepts the
        # option but no longer reads it, and would try to guess an account with sacct, warning on every
        # run where there is no accounting database; its cached guess, set empty, is what it submits with.
        executor._fallback_account_arg = ""


onerror:
    executor = _slurm_executor()
    if executor is not None:
        # An interrupted run: Snakemake cancels the jobs it knows as submitted, then waits for the
        # submissions still in flight, which would stay queued.  Every job of this run carries its run
        # id as SLURM job name; cancel what is left of them (nothing, after an ordinary job failure).
        subprocess.run(["scancel", "--user", getpass.getuser(), "--name", executor.run_uuid], check=False, timeout=60)
