"""``python -m bounce gas ...``: simulate a gas of grains and write its netCDF (bounce.gas.io).

The command line of :mod:`bounce.gas`, in the command-line layer beside :mod:`bounce.cli` (which
dispatches the word ``gas`` here) and :mod:`bounce.claims_cli`.

Example::

    python -m bounce gas --n 1000 --geometry ring --ell 1500 --mu 0.05 --speed 0.1 \\
        --events 1e6 --snapshot-every 10000 --out ring.nc

The model is the dimer gas (default) or ``--model rigid`` (``--r``, ``--size``, ``--t-c``).  The
initial state is read from ``--state FILE.npz`` (arrays psi, psidot, xi, xidot for dimers; x, xdot
for rigid grains) or generated from ``--seed``: springs at rest, velocities normal with standard
deviation ``--speed`` (zero total momentum on the ring), positions uniformly random on the ring
(the free length ell - n L shared by a flat Dirichlet draw, L the grains' length), stacked with
gaps ``--gap`` in the column.  Bad input: one line ``error: ...`` naming the parameter and its
allowed range, exit status 2, no file (the rules of :mod:`bounce.cli`, whose ``main`` prints them: this
module raises :class:`bounce.errors.InputError`; numbers are checked by the parameters' own
validation, :mod:`bounce.gas.model`).  SIGINT and SIGTERM reach the run between chunks of
``--chunk`` events.  A run that stops on overlap, a sticky contact or a collapse still writes its file
and says why.
"""

from __future__ import annotations

import argparse
import math
import signal
import sys

import numpy as np

from .errors import InputError as UsageError
from .gas.common import KIND_NAMES
from .gas.io import BYTES_PER_EVENT, partial_path, stream_to_netcdf, to_dataset
from .gas.model import GasParameters, GasState, RigidParameters, RigidState, random_state
from .gas.simulate import DEFAULT_CHUNK, run_settings, simulate_gas, simulate_rigid
from .io import CODECS, check_output_path, write_netcdf
from .stream import check_memory


EXIT_OK, EXIT_SIGINT = 0, 128 + signal.SIGINT


class _Parser(argparse.ArgumentParser):
    """An ArgumentParser that raises the one-line InputError instead of printing usage and exiting."""

    def error(self, message):
        raise UsageError(message)


def _integer(text: str) -> float:
    """argparse type: a number such as ``1000`` or ``1e6`` (the library checks that it is an integer in range)."""
    return float(text)


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="bounce gas", allow_abbrev=False,
                description="Exact event-driven simulation of a gas of two-mass grains (or of rigid grains) in a "
                            "column on the floor or on a ring; writes a CF netCDF file.")
    p.add_argument("--n", required=True, type=float,
                   help="number of grains, >= 1 (>= 2 on the ring)")
    p.add_argument("--geometry", required=True, choices=("column", "ring"))
    p.add_argument("--model", choices=("dimer", "rigid"), default="dimer")
    p.add_argument("--gamma", type=float, help="gravity (column only; default 0.01)")
    p.add_argument("--mu", type=float, help="damping of the grains' springs (dimer; default 0.05)")
    p.add_argument("--ell", type=float, help="circumference of the ring (ring only, required there)")
    p.add_argument("--r", type=float, help="restitution of the rigid grains (rigid; required there)")
    p.add_argument("--size", type=float, help="length of a rigid grain (rigid; default 1)")
    p.add_argument("--t-c", dest="t_c", type=float,
                   help="TC model: a collision within t_c of a grain's previous one is elastic (rigid; default 0: off)")
    init = p.add_argument_group("initial state")
    init.add_argument("--state", metavar="FILE.npz", help="arrays psi psidot xi xidot (dimer) or x xdot (rigid)")
    init.add_argument("--speed", type=float, default=0.1,
                      help="standard deviation of the generated velocities (default 0.1)")
    init.add_argument("--gap", type=float, default=0.5,
                      help="gap between the generated grains of the column (default 0.5)")
    init.add_argument("--seed", type=int, default=1, help="seed of the generated state, >= 0 (default 1)")
    p.add_argument("--events", type=_integer, default=1000, help="stop after N events (default 1000)")
    p.add_argument("--t-max", dest="t_max", type=float,
                   default=math.inf, help="stop at this time (default inf)")
    p.add_argument("--snapshot-every", dest="snapshot_every", type=_integer, default=0,
                   help="state of all grains every K events (default 0: the final state only)")
    p.add_argument("--out", required=True, metavar="FILE.nc", help="output netCDF file (its directory must exist)")
    run = p.add_argument_group("long runs and output")
    run.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                     help="progress bar on stderr (default: when stderr is a terminal)")
    run.add_argument("--stream", action="store_true",
                     help="bounded memory: append chunks to FILE.nc.partial, moved to FILE.nc at the end")
    run.add_argument("--resume", action="store_true", help="continue the interrupted --stream run (same arguments)")
    run.add_argument("--chunk", type=_integer, default=DEFAULT_CHUNK, help=f"events per chunk (default {DEFAULT_CHUNK})")
    run.add_argument("--compression", choices=sorted(CODECS), default="none", help="codec (default none)")
    return p


def _only(args, model: str, names: tuple[str, ...]) -> None:
    given = [f"--{n.replace('_', '-')}" for n in names if getattr(args, n) is not None]
    if given:
        other = "rigid" if model == "dimer" else "dimer"
        raise UsageError(f"{' '.join(given)}: only with --model {model} (allowed with --model {other}: "
                         f"{'--mu' if other == 'dimer' else '--r --size --t-c'})")


def parameters(args) -> GasParameters | RigidParameters:
    if args.geometry == "ring" and args.gamma is not None:
        raise UsageError(f"--gamma must be 0 on the ring (allowed: omit it; a periodic line has no floor), got "
                         f"{args.gamma!r}")
    if args.geometry == "column" and args.ell is not None:
        raise UsageError("--ell: only with --geometry ring (the ring's circumference)")
    if args.geometry == "ring" and args.ell is None:
        raise UsageError("--ell is required with --geometry ring (allowed range: (0, inf))")
    gamma = 0.0 if args.geometry == "ring" else (0.01 if args.gamma is None else args.gamma)
    n = int(args.n) if float(args.n).is_integer() else args.n
    if args.model == "rigid":
        _only(args, "dimer", ("mu",))
        if args.r is None:
            raise UsageError("--r is required with --model rigid (allowed range: [0, 1])")
        return RigidParameters(n, args.geometry, gamma, args.r, args.ell, 1.0 if args.size is None else args.size,
                               0.0 if args.t_c is None else args.t_c)
    _only(args, "rigid", ("r", "size", "t_c"))
    return GasParameters(n, args.geometry, gamma, 0.05 if args.mu is None else args.mu, args.ell)


def initial_state(args, params) -> GasState | RigidState:
    rigid = isinstance(params, RigidParameters)
    if args.state is not None:
        names = ("x", "xdot") if rigid else ("psi", "psidot", "xi", "xidot")
        try:
            with np.load(args.state) as data:
                arrays = [data[name] for name in names]
        except (OSError, ValueError, KeyError) as exc:
            raise UsageError(f"--state must be an .npz file with arrays {', '.join(names)} (one entry per grain): "
                             f"{exc}") from None
        return RigidState(*arrays) if rigid else GasState(*arrays)
    return random_state(params, args.speed, args.gap, args.seed, prefix="--")


def _summary(n_events: int, counts, stop: str, t_end: float, path, message: str) -> str:
    parts = ", ".join(f"{c} {k}" for k, c in zip(KIND_NAMES, counts) if c)
    text = f"bounce gas: {n_events} events ({parts or 'none'}), stop: {stop}, t_end = {t_end:.10g}; wrote {path}"
    return text + (f" ({message})" if message else "")


def main(argv) -> int:
    """The ``gas`` command on ``argv`` (after the word ``gas``); bad input raises UsageError or InputError
    (:func:`bounce.cli.main` prints the one line and exits with 2)."""
    args = build_parser().parse_args(argv)
    params = parameters(args)
    initial = initial_state(args, params)
    initial.check(params)
    try:
        out = check_output_path(args.out)
    except OSError as exc:
        raise UsageError(f"--out must be a new file or a regular file in an existing, writable directory: {exc}") from None
    events, t_max, every = run_settings(args.events, args.t_max, args.snapshot_every)
    if args.resume and not args.stream:
        raise UsageError("--resume continues a --stream run; add --stream")
    if args.stream:
        try:
            res = stream_to_netcdf(params, initial, out, events, t_max, every, args.chunk, args.resume,
                                   args.progress, args.compression)
        except KeyboardInterrupt:
            print(f"error: interrupted; {partial_path(out)} keeps the run up to its last chunk: continue it with the "
                  "same command and --resume", file=sys.stderr)
            return EXIT_SIGINT
        counts = [res["counts"][k] for k in KIND_NAMES]
        print(_summary(res["events"], counts, res["stop_reason"], res["t_end"], out, res["message"]))
        return EXIT_OK
    snapshot_bytes = len(("x", "xdot") if isinstance(params, RigidParameters) else ("x", "xdot", "xidot", "eta")) * 8
    per_event = BYTES_PER_EVENT + (snapshot_bytes * params.n / every if every else 0)
    check_memory(events, math.ceil(per_event))
    run = simulate_rigid if isinstance(params, RigidParameters) else simulate_gas
    result = run(params, initial, max_events=events, t_max=t_max, snapshot_every=every, chunk=args.chunk,
                 progress=args.progress)
    dataset = to_dataset(result)
    write_netcdf(dataset, out, compression=args.compression)
    counts = np.bincount(result.kind, minlength=len(KIND_NAMES))
    print(_summary(len(result), counts, result.stop_reason, result.t_end, out, result.message))
    return EXIT_OK

