"""Method 1: the exact event-driven solver of :mod:`bounce.simulate` (closed-form flights for the linear
spring, Taylor-series flights for the power law; dense samples of y: linear spring only)."""

from __future__ import annotations

import math
import time

import numpy as np

from ..kinds import IMPACT
from ..sampling import sample_trajectory
from ..simulate import simulate
from .base import EXACT_SOLVER, MethodResult, MethodSpec


def run(params, initial, setting=None, *, max_events=1000, t_max=math.inf, sample_times=None) -> MethodResult:
    """Exact solution: impacts to rounding, closed-form samples of y."""
    start = time.process_time()
    traj = simulate(params, initial, max_events=max_events, t_max=t_max)
    cpu = time.process_time() - start
    y = None
    if sample_times is not None:
        s = sample_trajectory(traj, np.asarray(sample_times, dtype=float))
        y = params.y_eq + s["y_minus_yeq"]
    impacts = traj.kind == IMPACT
    return MethodResult(method="exact", setting={}, t=traj.t[impacts], xdot=traj.xdot[impacts], cpu_time=cpu,
                        t_end=traj.t_end, y=y, extra={"stop_reason": traj.stop_reason})


METHOD = MethodSpec(name="exact", run=run, settings_doc="none: exact to rounding (samples of y: linear spring only)",
                    needs=EXACT_SOLVER)
