"""The pipeline's fork server (bounce.pipeline.taskserver): a served job is the fresh job, bit for bit and status for
status; a job whose environment differs is refused and runs afresh; the server stops and cleans up.  The whole
pipeline through it: tests/pipeline/test_pipeline.py (the CI-sized run is served; its byte-identity rerun is not)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time

import pytest

from bounce.pipeline import taskserver
from ci_pipeline import env

pytestmark = pytest.mark.slow  # a server's start-up, ~3 s, and fresh jobs to compare with

SCENE = {"gamma": 0.01, "mu": 0.01, "initial": {"psi": 6.0, "psidot": 0.0, "xi": 0.0, "xidot": 0.0},
         "stop": {"t_max": 60.0, "events": 2000}}


def job_env() -> dict:
    """The jobs' environment: this process's, one-thread variables set (pytest's per-test variable left out)."""
    out = dict(env(), **taskserver.ONE_THREAD)
    out.pop("PYTEST_CURRENT_TEST", None)
    return out


@pytest.fixture(scope="module")
def server():
    """A server started as the Snakefile starts it, in the jobs' environment."""
    saved, jobs = dict(os.environ), job_env()
    os.environ.clear()
    os.environ.update(jobs)
    process = taskserver.start()
    jobs = dict(os.environ)  # the server's address added
    os.environ.clear()
    os.environ.update(saved)
    assert process is not None
    yield jobs
    taskserver.stop(process)


def fresh(argv, cwd):
    return subprocess.run([sys.executable, "-m", "bounce.pipeline.tasks", *argv], cwd=cwd, capture_output=True,
                          text=True, env=env())


def client(server, argv, cwd, **extra_env):
    """The client as a rule runs it (a script of the standard library, -I), in the jobs' environment."""
    return subprocess.run([sys.executable, "-I", taskserver.__file__, *argv], cwd=cwd, capture_output=True,
                          text=True, env=dict(server, **extra_env))


def scene_argv(out):
    return ["scene", "--name", "rigid-fall", "--spec", json.dumps(SCENE), "--out", str(out)]


def test_a_served_job_writes_the_bytes_of_a_fresh_one(server, tmp_path):
    served = client(server, scene_argv("served.nc"), tmp_path)
    alone = fresh(scene_argv("fresh.nc"), tmp_path)
    assert served.returncode == alone.returncode == 0, served.stderr + alone.stderr
    assert taskserver.SERVED in served.stderr and taskserver.SERVED not in alone.stderr
    assert (tmp_path / "served.nc").read_bytes() == (tmp_path / "fresh.nc").read_bytes()
    assert served.stdout == alone.stdout


@pytest.mark.parametrize("argv, status", [
    (["no-such-task", "--out", "x"], 2),  # argparse's refusal
    (["scene", "--name", "rigid-fall", "--spec", "{}", "--out", "x.nc"], 1),  # an uncaught exception
])
def test_a_served_job_fails_as_a_fresh_one(server, tmp_path, argv, status):
    served = client(server, argv, tmp_path)
    alone = fresh(argv, tmp_path)
    assert served.returncode == alone.returncode == status
    assert served.stderr.splitlines()[-1] == alone.stderr.splitlines()[-1]
    assert not (tmp_path / "x.nc").exists()


def test_a_job_in_another_environment_is_refused_and_runs_afresh(server, tmp_path):
    # NUMBA_OPT is read when numba is imported: the server's import would not honour the job's
    alone = client(server, scene_argv("alone.nc"), tmp_path, NUMBA_OPT="2")
    assert alone.returncode == 0 and taskserver.SERVED not in alone.stderr
    assert "not served: its environment differs from the server's in NUMBA_OPT\n" in alone.stderr
    assert (tmp_path / "alone.nc").exists()
    # variables nothing reads before a job starts may differ
    served = client(server, scene_argv("served.nc"), tmp_path, TMPDIR=str(tmp_path), SHLVL="7")
    assert served.returncode == 0 and taskserver.SERVED in served.stderr


def test_under_slurm_or_switched_off_the_client_runs_the_job_afresh(server, tmp_path):
    for extra in ({"SLURM_JOB_ID": "1"}, {taskserver.ADDRESS_VARIABLE: "off"}):
        proc = client(server, scene_argv("x.nc"), tmp_path, **extra)
        assert proc.returncode == 0 and taskserver.SERVED not in proc.stderr


def test_the_server_stops_and_removes_its_socket():
    saved = dict(os.environ)
    os.environ.update(job_env())
    try:
        process = taskserver.start()
        address = os.environ[taskserver.ADDRESS_VARIABLE]
        assert os.path.exists(address)
        taskserver.stop(process)
        assert process.returncode == 0 and not os.path.exists(os.path.dirname(address))
        assert taskserver.ADDRESS_VARIABLE not in os.environ
    finally:
        os.environ.clear()
        os.environ.update(saved)


#: a server with one more task, ``sleep --name SECONDS``: a job that runs until it is stopped
SLEEPY_SERVER = """
import sys, time
from bounce.pipeline import tasks, taskserver
tasks.TASKS["sleep"] = lambda args: time.sleep(float(args.name))
taskserver.serve(sys.argv[1])
"""


@pytest.fixture
def sleeping_job(tmp_path):
    """(server process, client process, the job's process): a served job that sleeps for a minute."""
    psutil = pytest.importorskip("psutil")
    address = str(tmp_path / "socket")
    jobs = dict(job_env(), **{taskserver.ADDRESS_VARIABLE: address})
    server = subprocess.Popen([sys.executable, "-c", SLEEPY_SERVER, address], env=jobs, stdout=subprocess.PIPE)
    assert server.stdout.readline().strip() == b"ready"
    client = subprocess.Popen([sys.executable, "-I", taskserver.__file__, "sleep", "--name", "60", "--out", "x"],
                              env=jobs, cwd=tmp_path, stderr=subprocess.PIPE, text=True)
    for _ in range(200):
        children = psutil.Process(server.pid).children()
        if children:
            break
        time.sleep(0.05)
    assert len(children) == 1
    yield server, client, children[0]
    for process in (client, server):
        process.kill()
        process.wait()


def test_a_job_whose_client_is_gone_is_stopped(sleeping_job):
    server, client, job = sleeping_job
    client.kill()  # snakemake cancelling the job
    job.wait(timeout=10)
    assert server.poll() is None  # the server goes on serving


def test_a_lost_server_fails_its_jobs_and_takes_them_along(sleeping_job):
    server, client, job = sleeping_job
    server.kill()
    assert client.wait(timeout=10) == 1
    assert "went away during the job" in client.stderr.read()
    job.wait(timeout=10)  # not left running unseen
