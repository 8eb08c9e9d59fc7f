"""A fork server for the pipeline's jobs: pay start-up once per run, not once per job (issue 22).

Every job of the pipeline is a task of :mod:`bounce.pipeline.tasks`, and a fresh interpreter spends
1-2 s of CPU importing numpy, numba, xarray, matplotlib and sympy and initialising numba's compiler
before the job does anything.  The server imports all that once (:func:`preload`), then forks a child
per job; a child starts where a fresh process would have got after its imports, runs
:func:`bounce.pipeline.tasks.main` and ends as the task would.  Measured (CPU of the job's process,
median of 3, fresh -> served): a scene 1.38 -> 0.09 s, a figure 2.65 -> 1.0 s, the algebra check
4.0 -> 3.0 s; the server's own start-up is ~2.7 s, once per run.

The contract:

1. A rule calls the *client*, this file run as a script (``python -I .../taskserver.py TASK ARGS``:
   the standard library only, no import of bounce).  It sends its arguments, working directory,
   environment and its stdin, stdout and stderr (SCM_RIGHTS) to the server named by
   ``BOUNCE_TASK_SERVER`` and exits with the job's status.  With no server (the variable unset, a
   SLURM job, a server that is gone or that refuses the job) it becomes
   ``python -m bounce.pipeline.tasks TASK ARGS`` (``execv``): the same job, started afresh.  A server
   lost once it has the job fails the job (its outcome is unknown) rather than run it twice.
2. The server serves a job only if its environment is the server's own, up to :data:`PER_JOB`
   (variables nothing reads before a job starts: the shell's bookkeeping, the temporary directory):
   what a fresh process would have read at import (PYTHONPATH, numba's and bounce's cache settings,
   the BLAS thread counts) is then what the server read.  Otherwise it refuses, and the job runs afresh.
3. A child is what the fresh process would be after its imports: its own process group (a cancelled
   job takes its sweep workers with it), the job's descriptors, directory, environment and argv;
   its outputs are the fresh process's, bit for bit (tests/pipeline/test_taskserver.py).  Its
   ``cpu:`` line counts its own CPU from the fork: the imports are the server's, counted once in the
   run's total (the server is the snakemake process's child, waited for when the run ends).
4. A client that goes away (snakemake cancels the job) takes its child's process group with it (SIGTERM).
   The server stops on SIGTERM, or when the snakemake that started it is gone.

The Snakefile starts the server for a local run (``onstart``, :func:`start`) and stops it at exit; a
cluster run, ``--no-hooks`` or ``BOUNCE_TASK_SERVER=off`` runs every job afresh.
"""

from __future__ import annotations

import json
import os
import socket
import struct
import sys

#: the variable naming the server's socket (``off``: start none)
ADDRESS_VARIABLE = "BOUNCE_TASK_SERVER"
#: variables a job's environment may have of its own: nothing reads them before a job starts (the
#: child applies them; tempfile's cached directory is reset so that the job's TMPDIR holds).  The shell's
#: bookkeeping includes its prompts: a non-interactive bash unsets an exported PS1 (a venv's `activate`)
PER_JOB = frozenset({"_", "SHLVL", "PWD", "OLDPWD", "PS1", "PS2", "TMPDIR", "TMP", "TEMP", "TEMPDIR"})
#: what snakemake sets in a one-thread job's environment (snakemake.shell), given to the server too
ONE_THREAD = {name: "1" for name in ("OMP_NUM_THREADS", "GOTO_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                    "MKL_NUM_THREADS", "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")}
REFUSED = -1000  # the server's answer to a job it does not serve
#: what a served job's ``cpu:`` line says of its start (bounce.pipeline.tasks.STARTED_BY)
SERVED = " (forked by the run's task server: imports not counted)"
_PR_SET_PDEATHSIG = 1  # prctl(2)
_LENGTH = struct.Struct("<q")
_STATUS = struct.Struct("<i")


def _receive(sock: socket.socket, size: int) -> bytes:
    data = b""
    while len(data) < size:
        chunk = sock.recv(size - len(data))
        if not chunk:
            raise ConnectionError("connection closed")
        data += chunk
    return data


# ------------------------------------------------------------------------------------------------ client


def run_client(argv: list[str]) -> int:
    """Run the job ``argv`` in the server and return its exit status, or :data:`REFUSED` if no server took it
    (none named, unreachable, or refusing).  A server lost once it has the job leaves its outcome unknown: that
    is a failed job (status 1, one line on stderr), never a second run of it beside a child that may still run."""
    address = os.environ.get(ADDRESS_VARIABLE, "off")
    if address == "off" or "SLURM_JOB_ID" in os.environ:
        return REFUSED
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
        try:
            sock.connect(address)
            payload = json.dumps({"argv": argv, "cwd": os.getcwd(), "env": dict(os.environ)}).encode()
            socket.send_fds(sock, [_LENGTH.pack(len(payload))], [0, 1, 2])
            sock.sendall(payload)  # the server forks only once it has read all of it
        except OSError:
            return REFUSED
        try:
            (status,) = _STATUS.unpack(_receive(sock, _STATUS.size))
        except (OSError, ConnectionError) as lost:
            print(f"bounce.pipeline.taskserver: the run's task server went away during the job ({lost}); its "
                  f"outcome is unknown", file=sys.stderr)
            return 1
    return status


def client_main() -> None:
    status = run_client(sys.argv[1:])
    if status == REFUSED:
        os.execv(sys.executable, [sys.executable, "-m", "bounce.pipeline.tasks", *sys.argv[1:]])
    sys.exit(status if status >= 0 else 128 - status)  # a child killed by signal N: 128 + N, as a shell says


# ------------------------------------------------------------------------------------------------ server


def preload() -> None:
    """Import what the jobs import, initialise numba's compiler (a cached kernel's first call) and save a figure."""
    import importlib

    for name in ("bounce.figures.common", "xarray", "netCDF4", "scipy.integrate", "scipy.optimize", "scipy.stats",
                 "sympy", "bounce.pipeline.tasks", "bounce.io", "bounce.checks", "bounce.figures", "bounce.sweeps",
                 "bounce.studies", "bounce.methods"):
        importlib.import_module(name)
    for optional in ("heyoka",):
        try:
            importlib.import_module(optional)
        except ImportError:
            pass
    from bounce.exact.oscillator import natural_frequency

    natural_frequency(0.01)
    # a process's first saved figure also loads fonts, mathtext and the PDF writer (~0.26 s of CPU): draw one here
    import io

    import matplotlib.pyplot as plt

    from bounce.figures.common import PDF_METADATA

    fig, ax = plt.subplots()
    ax.loglog([1.0, 10.0], [1.0, 0.1], label=r"$\tau_n \sim 3/(\mu n)$")
    ax.set(xlabel="n (1)", ylabel=r"$\tau_n$ (1)", title="warm-up")
    ax.legend()
    for fmt, metadata in (("png", None), ("pdf", PDF_METADATA)):
        fig.savefig(io.BytesIO(), format=fmt, metadata=metadata, bbox_inches="tight")
    plt.close(fig)


def _child(conn: socket.socket, listener: socket.socket, fds: list[int], request: dict, imported_env: dict,
           server: int) -> None:
    """The job, in the forked child (contract, 3); never returns."""
    import ctypes
    import signal
    import tempfile
    import traceback

    status = 1
    try:
        os.setpgid(0, 0)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        # a server gone (killed) takes its children along: its clients fail their jobs, none runs on unseen
        ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
        if os.getppid() != server:
            return
        listener.close()
        conn.close()
        for target, fd in enumerate(fds):
            os.dup2(fd, target)
            os.close(fd)
        os.chdir(request["cwd"])
        os.environ.clear()
        os.environ.update(request["env"])
        os.environ.update(imported_env)
        tempfile.tempdir = None
        sys.argv = ["python -m bounce.pipeline.tasks", *request["argv"]]
        from bounce.pipeline import tasks

        tasks.STARTED_BY = SERVED
        status = tasks.main(request["argv"])
    except SystemExit as stop:  # argparse's errors, sys.exit in a task: what the interpreter would exit with
        code = stop.code
        if code is not None and not isinstance(code, int):
            print(code, file=sys.stderr)
        status = code if isinstance(code, int) else (0 if code is None else 1)
    except BaseException:  # noqa: BLE001 - an uncaught exception: its traceback and status 1, as the interpreter
        traceback.print_exc()
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(status)


def serve(address: str) -> None:
    """Listen on the Unix socket ``address`` and fork a child per job (contract, 2-4)."""
    import gc
    import selectors
    import signal

    own_env = {k: v for k, v in os.environ.items() if k not in PER_JOB}
    preload()
    # what the imports set in the environment (netCDF4: HDF5_PLUGIN_PATH), as a fresh job's imports would
    imported_env = {k: v for k, v in os.environ.items() if own_env.get(k) != v and k not in PER_JOB}
    gc.freeze()  # the children never collect the server's objects (nor copy their pages to do so)
    parent, server = os.getppid(), os.getpid()
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    listener.bind(address)
    listener.listen(64)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))
    selector = selectors.DefaultSelector()
    selector.register(listener, selectors.EVENT_READ, "accept")
    jobs: dict[int, tuple[socket.socket, int]] = {}  # pid -> (client connection, pidfd)
    try:
        print("ready", flush=True)
        while os.getppid() == parent:
            for key, _ in selector.select(timeout=1.0):
                kind = key.data
                if kind == "accept":
                    conn, _ = listener.accept()
                    conn.settimeout(10.0)
                    try:
                        head, fds, _, _ = socket.recv_fds(conn, _LENGTH.size, 3)
                        (size,) = _LENGTH.unpack(head)
                        request = json.loads(_receive(conn, size))
                    except (OSError, ConnectionError, ValueError, struct.error):
                        conn.close()
                        continue
                    env = {k: v for k, v in request["env"].items() if k not in PER_JOB}
                    if env != own_env or len(fds) != 3:
                        differ = sorted(k for k in set(env) | set(own_env) if env.get(k) != own_env.get(k))
                        if len(fds) == 3 and differ:  # said in the job's log, which the fresh job then continues
                            os.write(fds[2], f"bounce.pipeline.taskserver: started afresh, not served: its environment "
                                             f"differs from the server's in {', '.join(differ)}\n".encode())
                        for fd in fds:
                            os.close(fd)
                        conn.sendall(_STATUS.pack(REFUSED))
                        conn.close()
                        continue
                    pid = os.fork()
                    if pid == 0:
                        _child(conn, listener, fds, request, imported_env, server)
                    for fd in fds:
                        os.close(fd)
                    pidfd = os.pidfd_open(pid)
                    jobs[pid] = (conn, pidfd)
                    selector.register(pidfd, selectors.EVENT_READ, ("exited", pid))
                    selector.register(conn, selectors.EVENT_READ, ("client", pid))
                elif kind[0] == "exited":
                    pid = kind[1]
                    conn, pidfd = jobs.pop(pid)
                    _, wait_status = os.waitpid(pid, 0)
                    selector.unregister(pidfd)
                    os.close(pidfd)
                    if conn.fileno() in selector.get_map():
                        selector.unregister(conn)
                    try:
                        conn.sendall(_STATUS.pack(os.waitstatus_to_exitcode(wait_status)))
                    except OSError:
                        pass
                    conn.close()
                else:  # the client's connection is readable before its job ended: the client is gone
                    pid = kind[1]
                    selector.unregister(jobs[pid][0])
                    try:
                        os.killpg(pid, signal.SIGTERM)
                    except ProcessLookupError:
                        pass
    finally:
        for pid in jobs:
            try:
                os.killpg(pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
        listener.close()
        for remove, path in ((os.unlink, address), (os.rmdir, os.path.dirname(address))):
            try:
                remove(path)
            except OSError:
                pass


def start():
    """Start a server for this process's jobs (the Snakefile's ``onstart``): set ``BOUNCE_TASK_SERVER`` in
    this process's environment, which the jobs inherit, and give the server that environment with
    snakemake's one-thread variables (:data:`ONE_THREAD`).  Returns the server's process (stop it with
    :func:`stop`), or None when none is started (``BOUNCE_TASK_SERVER=off``, not Linux) or it failed to start."""
    import shutil
    import subprocess
    import tempfile

    if os.environ.get(ADDRESS_VARIABLE) == "off" or not (hasattr(os, "pidfd_open") and hasattr(socket, "send_fds")):
        return None  # switched off, or not Linux (pidfd_open: Linux >= 5.3)
    # a short path: a Unix socket's address has at most 107 bytes
    address = os.path.join(tempfile.mkdtemp(prefix="bounce-tasks-"), "socket")
    env = dict(os.environ, **ONE_THREAD, **{ADDRESS_VARIABLE: address})
    process = subprocess.Popen([sys.executable, "-m", "bounce.pipeline.taskserver", "--serve", address], env=env,
                               stdout=subprocess.PIPE, stdin=subprocess.DEVNULL)
    if process.stdout.readline().strip() != b"ready":
        process.wait()
        shutil.rmtree(os.path.dirname(address), ignore_errors=True)
        return None
    os.environ[ADDRESS_VARIABLE] = address
    return process


def stop(process) -> None:
    """Stop the server ``process`` and wait for it (its CPU, and its jobs', counts in its parent's)."""
    if process is not None and process.poll() is None:
        process.terminate()
        process.wait()
    os.environ.pop(ADDRESS_VARIABLE, None)


if __name__ == "__main__":
    if sys.argv[1:2] == ["--serve"]:
        serve(sys.argv[2])
    else:
        client_main()
