"""Command-line interface: ``bounce simulate ... --out FILE.nc`` (also ``python -m bounce``).

Example::

    bounce simulate --gamma 0.01 --mu 0.01 --x0 6 --xdot0 0 --y0 7 --ydot0 0 \\
        --events 1000 --dt-sample 0.1 --out run.nc

The initial state is given completely in one of two forms: heights and
velocities ``--x0 --xdot0 --y0 --ydot0``, or the paper's centre-of-mass and
spring variables ``--psi0 --psidot0 --xi0 --xidot0`` (eq. ``xi-psi``).

Bad input exits with status 2 and one line ``error: ...`` on stderr naming the
parameter and its allowed range (also for an option given twice); every name the
run will write (--out, its temporary file, a stream's partial file) and the
sampling step are checked before the run is simulated (or, for --dt-sample, as
soon as the run passes its sampling limit).  A failure while simulating or
writing exits with status 1 (a full disk says so, and the old file is kept);
SIGINT and SIGTERM exit with 130 and 143 after one line (during a write, once
its temporary file is closed: :func:`bounce.io.signals_deferred`).  No file is
left behind on failure, not even a temporary one (a temporary left by SIGKILL is
removed by the next run writing the same file); an interrupted --stream run
keeps its partial file up to its last chunk, for --resume.

Memory is bounded by default: a closed-form run of more than ``--chunk`` events streams (as --stream:
:mod:`bounce.stream`, ~105 bytes per event of one chunk instead of 81 per event of the whole run, and
no page faults of fresh record arrays), unless it needs the whole run in memory (--dt-sample).  A 1e7-event
one-shot run peaked at 1,069 MB (issue 22).

Supported inputs (refused up front otherwise, see
:func:`bounce.model.check_supported`): gamma in [1e-12, 0.5), mu in [0, 1e8],
y0 > x0 >= 0, and an initial energy whose longest possible flight is at most
1e8 time units; every accepted input gives finite results.  Another spring law
(``--spring``, its parameters ``--NAME``: both from :data:`bounce.springs.SPRING_LAWS`)
has its own domain (:mod:`bounce.springs.power`: the equilibrium above the floor,
bounded over-damping and work per flight), refused the same way.

The exact solver the law declares runs by default; ``--method NAME`` runs a
general-purpose method of :mod:`bounce.methods` instead (the only way for a law
without an exact solver) and writes the impacts it reports, with the law's
attributes (:func:`bounce.io.method_dataset`).

Event times ``t`` are correctly rounded sums of the exact phase durations
``tau`` (within 1 ulp when the phases span more than 2^53 in size,
:mod:`bounce.exact.events`); a phase shorter than half an ulp of t (late in the asymptotic regime
after very long runs, or a chattering sticky onset) leaves t unchanged, so
consecutive event times may coincide while tau stays exact.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import math
import signal
import sys
import threading

import numpy as np

from ._version import __version__
from .errors import OneLineParser, UsageError
from .kinds import KIND_NAMES
from .io import CODECS, check_output_path, method_dataset, to_dataset, write_netcdf
from .model import GAMMA_MAX, GAMMA_MIN, MU_MAX, InputError, Parameters, State, check_physical, check_supported
from .simulate import simulate
from .springs import SPRING_LAWS, spring_from_spec
from .springs.base import FLIGHT_MAX
from .stream import (BYTES_PER_EVENT_STREAM, DEFAULT_CHUNK, MAX_STREAM_EVENTS, check_disk, check_memory, check_paths,
                     partial_path, progress_enabled, simulate_chunked, stream_to_netcdf)
from .trajectory import MAX_EVENTS

EXIT_OK, EXIT_FAILURE, EXIT_USAGE = 0, 1, 2
EXIT_SIGINT, EXIT_SIGTERM = 128 + signal.SIGINT, 128 + signal.SIGTERM
MAX_SAMPLES = 10_000_000

XY_FORM = ("x0", "xdot0", "y0", "ydot0")
PSI_FORM = ("psi0", "psidot0", "xi0", "xidot0")


class Terminated(Exception):
    """SIGTERM, raised by the handler so that cleanup (temporary files) runs as for KeyboardInterrupt."""


def _raise_terminated(signum, frame):
    raise Terminated()


# --------------------------------------------------------------------------- argument types

def _number(allowed: str, check=lambda v: True, allow_inf: bool = False):
    """argparse type: a float in ``allowed`` (a range for the message); NaN (and inf unless allowed) rejected."""
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if math.isnan(value) or (math.isinf(value) and not allow_inf) or not check(value):
            kind = "number" if allow_inf else "finite number"
            raise argparse.ArgumentTypeError(f"must be a {kind} (allowed range: {allowed}), got {text!r}")
        return value
    return parse


def _count(text: str, most: int = MAX_EVENTS) -> int:
    """argparse type: an integer in [1, most] (``1000`` or ``1e6``).  Whether the records fit in memory is
    checked once the run is known (:func:`bounce.stream.check_memory`: the whole run without --stream, one
    chunk with it)."""
    try:
        value = float(text)
        ok = math.isfinite(value) and value.is_integer() and 1 <= value <= most
    except ValueError:
        ok = False
    if not ok:
        raise argparse.ArgumentTypeError(f"must be an integer (allowed range: [1, {most:.0e}]), got {text!r}")
    return int(value)


def _event_count(text: str) -> int:
    """--events: up to MAX_STREAM_EVENTS (a --stream run's memory does not grow with it)."""
    return _count(text, MAX_STREAM_EVENTS)


_ANY = _number("(-inf, inf)")


def build_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(
        prog="bounce",
        allow_abbrev=False,
        description="Exact event-driven simulation of the two-mass bouncing ball "
                    "(Cherubini, Metafune, Paparella, 'On the Stopping Time of a Bouncing Ball').",
    )
    parser.add_argument("--version", action="version", version=f"bounce {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    # listed here for --help and the unknown-command error; main() hands `check ...` to bounce.claims_cli
    sub.add_parser("check", add_help=False,
                   help="run one claim of the validation report (or --list them) on the pipeline's datasets; "
                        "bounce check --help")
    p = sub.add_parser(
        "simulate",
        allow_abbrev=False,
        help="simulate one trajectory and write its events (and optional samples) to netCDF",
        description="Simulate from a complete initial state, given either as --x0 --xdot0 --y0 --ydot0 or as "
                    "--psi0 --psidot0 --xi0 --xidot0, and write a CF netCDF file. Dimensionless units: lengths "
                    "in the spring rest length L, times in sqrt(m/2k).",
        epilog=f"Supported: gamma in [{GAMMA_MIN:g}, {GAMMA_MAX:g}), mu in [0, {MU_MAX:g}], y0 > x0 >= 0, and an "
               f"initial energy whose longest possible flight is at most {FLIGHT_MAX:g} time units (the power law: "
               "also the equilibrium above the floor and bounded work per flight); other inputs are refused with the "
               "range. "
               "Event times t are correctly rounded sums of the exact durations tau: phases shorter than half "
               "an ulp of t leave t unchanged (equal consecutive times), tau stays exact.",
    )
    p.add_argument("--gamma", required=True, type=_number("(0, inf)"),
                   help="g m / (2 L k), > 0")
    p.add_argument("--mu", required=True, type=_number("[0, inf)"),
                   help="damping nu / sqrt(2 k m), >= 0")
    _spring_options(p)
    xy = p.add_argument_group("initial state, heights and velocities")
    xy.add_argument("--x0", type=_number("[0, inf)"), help="height of the lower mass, >= 0")
    xy.add_argument("--xdot0", type=_ANY, help="velocity of the lower mass (>= 0 if x0 = 0)")
    xy.add_argument("--y0", type=_ANY, help="height of the upper mass")
    xy.add_argument("--ydot0", type=_ANY, help="velocity of the upper mass")
    pp = p.add_argument_group("initial state, paper variables (psi = (y + x - 1)/2, xi = (y - x - 1)/2)")
    pp.add_argument("--psi0", type=_ANY, help="centre of mass")
    pp.add_argument("--psidot0", type=_ANY)
    pp.add_argument("--xi0", type=_ANY, help="spring deformation")
    pp.add_argument("--xidot0", type=_ANY)
    p.add_argument("--events", type=_event_count, default=1000,
                   help="stop after N events (default 1000)")
    p.add_argument("--t-max", dest="t_max", type=_number("(0, inf]", lambda v: v > 0, allow_inf=True),
                   default=math.inf, help="stop at this time (default inf)")
    p.add_argument("--energy-stop", dest="energy_stop", type=_number("[0, inf)", lambda v: v >= 0),
                   default=0.0, help="stop once E - E_m < E (default 0)")
    p.add_argument("--dt-sample", dest="dt_sample", type=_number("(0, inf)", lambda v: v > 0),
                   help="also sample x, y and velocities on [0, t_valid] with this step")
    p.add_argument("--out", required=True, metavar="FILE.nc", help="output netCDF file (its directory must exist)")
    p.add_argument("--method", metavar="NAME",
                   help="a general-purpose method of bounce.methods (e.g. scipy, penalty, moreau-jean, heyoka) "
                        "instead of the law's exact solver (default); writes the impacts it reports")
    run = p.add_argument_group("long runs and output")
    run.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                     help="progress bar on stderr (default: when stderr is a terminal)")
    run.add_argument("--stream", action="store_true",
                     help="bounded memory: simulate in chunks and append each to FILE.nc.partial, "
                          "moved to FILE.nc at the end (the default for closed-form runs of more than --chunk "
                          "events without --dt-sample)")
    run.add_argument("--resume", action="store_true",
                     help="continue the interrupted streamed run of FILE.nc.partial (same arguments)")
    run.add_argument("--chunk", type=_count, default=DEFAULT_CHUNK,
                     help=f"events per chunk with --stream or --progress (default {DEFAULT_CHUNK})")
    run.add_argument("--keep-first", dest="keep_first", type=_count,
                     help="with --stream: keep only the first N events and --keep-log log-spaced ones after them")
    run.add_argument("--keep-log", dest="keep_log", type=_count, help="see --keep-first (>= 2)")
    run.add_argument("--compression", choices=sorted(CODECS), default="none",
                     help="codec of the event records (default none: the fastest). Smaller only for long runs, "
                          "measured on the drop of fig. rigid-fall: zlib 1.7x at 2e5 events, 2.2x at 2e6, but 11%% "
                          "larger at 1e3; ncdump reads it. zstd 1.2x at 2e5, needs the HDF5 zstd filter to read. "
                          "Both are slower to write (benchmarks/bench_cli.py --compression)")
    return parser


# --------------------------------------------------------------------------- helpers

def _law_parameters() -> dict:
    """option name -> (laws taking it, its interval if one law has it, else None), from the registry."""
    out: dict = {}
    for name, law in SPRING_LAWS.items():
        for p in law.PARAMETERS:
            laws, _ = out.get(p.name, ((), None))
            out[p.name] = (laws + (name,), p.interval() if not laws else None)
    return out


def _spring_options(parser) -> None:
    """``--spring`` and one option per law parameter, from :data:`bounce.springs.SPRING_LAWS` (a law is one
    registry line: its options follow).  The law checks the values (one line naming the parameter)."""
    group = parser.add_argument_group(
        "spring law (paper's Discussion, eq. eq-motion-nonlin-psi-xi: xi'' = -f(xi) - 2 mu xi' g(xi))")
    group.add_argument("--spring", choices=tuple(SPRING_LAWS), default="linear",
                       help="; ".join(f"{name}: {law.summary}" for name, law in SPRING_LAWS.items())
                            + " (default linear)")
    docs = {p.name: p.doc for law in SPRING_LAWS.values() for p in law.PARAMETERS}
    for name, (laws, interval) in _law_parameters().items():
        group.add_argument(f"--{name}", type=_number(interval or "(-inf, inf)"),
                           help=f"{docs[name]}, in {interval} (with --spring {' or '.join(laws)})" if interval
                           else f"a parameter of --spring {' or '.join(laws)}")


def _spring(args):
    """The law of --spring and its parameter options (bounce.springs): every parameter of the law is required,
    no other law's."""
    law = SPRING_LAWS[args.spring]
    own = [p.name for p in law.PARAMETERS]
    others = {name: laws for name, (laws, _) in _law_parameters().items() if name not in own}
    given = [name for name in others if getattr(args, name) is not None]
    if given:
        takes = " ".join(f"--{n}" for n in own) or "no parameters"
        raise UsageError(f"{' '.join('--' + n for n in given)}: only with --spring {' or '.join(others[given[0]])} "
                         f"(the {args.spring} spring takes {takes})")
    missing = [name for name in own if getattr(args, name) is None]
    if missing:
        ranges = "; ".join(f"{p.name} in {p.interval()}" for p in law.PARAMETERS)
        raise UsageError(f"--spring {args.spring} needs {' '.join('--' + n for n in missing)} (allowed ranges: {ranges})")
    return spring_from_spec({"law": args.spring, **{name: getattr(args, name) for name in own}})


def _method(args, params):
    """The general-purpose method of ``--method`` (None: the law's exact solver), checked against the law."""
    if args.method is None or args.method == "exact":
        if params.spring.solver is None:
            raise UsageError(f"the {params.spring.name} spring has no exact solver: choose a general-purpose method "
                             f"with --method ({', '.join(_methods_for(params))})")
        return None
    from .methods import registry

    methods = registry()
    if args.method not in methods or not methods[args.method].supports(params):
        raise UsageError(f"--method must be one of {', '.join(_methods_for(params))} for the {params.spring.name} "
                         f"spring, got {args.method!r}")
    unsupported = [opt for opt, given in (("--stream", args.stream), ("--resume", args.resume),
                                          ("--dt-sample", args.dt_sample is not None),
                                          ("--keep-first", args.keep_first is not None),
                                          ("--energy-stop", args.energy_stop != 0.0)) if given]
    if unsupported:
        raise UsageError(f"{' '.join(unsupported)}: only with the exact solver (drop --method {args.method})")
    return methods[args.method]


def _methods_for(params) -> list[str]:
    """The methods of bounce.methods that can run ``params.spring``."""
    from .methods import registry

    return sorted(name for name, spec in registry().items() if spec.supports(params))


def _initial_state(args) -> State:
    given_xy = [n for n in XY_FORM if getattr(args, n) is not None]
    given_psi = [n for n in PSI_FORM if getattr(args, n) is not None]
    opts = lambda names: " ".join("--" + n for n in names)  # noqa: E731
    if given_xy and given_psi:
        raise UsageError(
            f"{opts(given_xy[:1])} and {opts(given_psi[:1])}: the initial state takes one form, "
            f"either {opts(XY_FORM)} or {opts(PSI_FORM)}, not both"
        )
    if not given_xy and not given_psi:
        raise UsageError(f"the initial state is required: give {opts(XY_FORM)}, or {opts(PSI_FORM)}")
    form = XY_FORM if given_xy else PSI_FORM
    missing = [n for n in form if getattr(args, n) is None]
    if missing:
        raise UsageError(f"incomplete initial state: missing {opts(missing)} (give all of {opts(form)})")
    if form is XY_FORM:
        state = State(args.x0, args.xdot0, args.y0, args.ydot0)
        check_physical(state)
        return state
    try:
        state = State.from_psi_xi(args.psi0, args.psidot0, args.xi0, args.xidot0)
        check_physical(state)
        return state
    except InputError as exc:
        raise InputError(
            f"{exc} (from --psi0 --psidot0 --xi0 --xidot0: x0 = psi0 - xi0, xdot0 = psidot0 - xidot0)"
        ) from None


def _n_samples(end: float, dt: float) -> int:
    """Number of samples k dt <= end (refused beyond MAX_SAMPLES; end/dt may overflow to inf)."""
    ratio = end / dt
    if not ratio < MAX_SAMPLES:
        raise UsageError(
            f"--dt-sample must be >= {end / (MAX_SAMPLES - 1):.6g} to sample [0, {end:.6g}] with at most "
            f"{MAX_SAMPLES} samples (allowed range: [{end / (MAX_SAMPLES - 1):.6g}, inf)), got {dt!r}"
        )
    return math.floor(ratio) + 1


def _simulate_sampled(run, t_max: float, dt: float):
    """``run(t_max)`` stopped where the samples of step ``dt`` would exceed MAX_SAMPLES (the sampled span is the
    whole run, unknown before simulating it): a run going on beyond ``MAX_SAMPLES dt`` is refused there, not
    after simulating all of it.  A finite t_max changes no record before it (the event loop's stop rule), so
    a run ending before that limit is the run of ``t_max``, settings included."""
    limit = MAX_SAMPLES * dt
    if not limit < t_max:
        return run(t_max)
    traj = run(limit)
    if traj.stop_reason == "t_max":
        raise UsageError(
            f"--dt-sample must leave at most {MAX_SAMPLES} samples over the run (allowed range: [(end of the run)/"
            f"{MAX_SAMPLES - 1}, inf)), got {dt!r}: the run goes on beyond t = {limit:.6g}; bound it with --t-max "
            "or take a larger step"
        )
    return dataclasses.replace(traj, settings={**traj.settings, "t_max": t_max})


def _sample_end(traj, t_max: float) -> float:
    """End of the sampled span: t_valid; t_max if the motion is determined forever (sticky_forever),
    or the last event if t_max is infinite too."""
    end = traj.t_valid
    if not math.isfinite(end):
        end = t_max if math.isfinite(t_max) else (float(traj.t[-1]) if len(traj) else 0.0)
    return end


def _sample_times(traj, t_max: float, dt: float) -> np.ndarray:
    """k dt, k = 0, 1, ... on [0, end] (see :func:`_sample_end`)."""
    end = _sample_end(traj, t_max)
    times = np.arange(_n_samples(end, dt), dtype=np.float64) * dt
    return times[times <= end]


def _summary(n_events: int, counts, stop_reason: str, t_end: float, path, n_samples=None) -> str:
    """One line; ``counts`` per kind (np.bincount of the kinds: no loop over events).  A path holding a
    newline or another unprintable character is quoted with escapes (it would split the line)."""
    parts = ", ".join(f"{c} {k}" for k, c in zip(KIND_NAMES, counts) if c)
    text = f"bounce: {n_events} events ({parts or 'none'}), stop: {stop_reason}, t_end = {t_end:.10g}"
    if n_samples is not None:
        text += f", {n_samples} samples"
    name = str(path)
    return text + f"; wrote {name if name.isprintable() else repr(name)}"


def _keep(args, streamed: bool = False) -> dict | None:
    if (args.keep_first is None) != (args.keep_log is None):
        raise UsageError("--keep-first and --keep-log go together")
    if args.keep_first is None:
        return None
    if not streamed:
        raise UsageError("--keep-first/--keep-log thin a --stream run; add --stream")
    if args.keep_log < 2:
        raise UsageError(f"--keep-log must be an integer >= 2 (allowed range: [2, inf)), got {args.keep_log}")
    return {"first": args.keep_first, "log_samples": args.keep_log}


def _stream_command(args, params, initial, out) -> int:
    if args.dt_sample is not None:
        raise UsageError("--dt-sample needs the whole run in memory; it does not combine with --stream")
    check_memory(args.chunk, BYTES_PER_EVENT_STREAM, "--chunk")
    check_disk(out, args.events, _keep(args, True))
    try:
        result = stream_to_netcdf(params, initial, out, args.events, args.t_max, args.energy_stop, args.chunk,
                                  _keep(args, True), args.resume, args.progress, args.compression)
    except (KeyboardInterrupt, Terminated) as exc:
        signame, status = ("SIGINT", EXIT_SIGINT) if isinstance(exc, KeyboardInterrupt) else ("SIGTERM", EXIT_SIGTERM)
        part = partial_path(out)
        left = (f"{part} keeps the run up to its last chunk: continue it with the same command and --resume"
                if part.exists() else "no partial file is left")
        print(f"error: interrupted ({signame}); {left}", file=sys.stderr)
        return status
    counts = [result["counts"][k] for k in KIND_NAMES]
    print(_summary(result["events"], counts, result["stop_reason"], result["t_end"], out)
          + f" ({result['records']} records)")
    return EXIT_OK


def _simulate_command(args) -> int:
    params = Parameters(args.gamma, args.mu, _spring(args))
    initial = _initial_state(args)
    check_supported(params, initial.deviations(params), args.t_max)
    method = _method(args, params)
    # bounded memory by default (module docstring): a closed-form run longer than one chunk streams
    streamed = args.stream or (method is None and params.spring.solver == "exact" and args.dt_sample is None
                               and args.events > args.chunk)
    if args.resume and not streamed:
        raise UsageError("--resume continues a streamed run (--stream, or more than --chunk events); add --stream")
    try:  # every name the run writes, before simulating: the partial file of a stream is checked as --out is
        out = check_paths(args.out)[0] if streamed else check_output_path(args.out)
    except OSError as exc:
        raise UsageError(
            f"--out must be a new file or a regular file in an existing, writable directory: {exc}"
        ) from None
    if method is not None:
        return _method_command(args, method, params, initial, out)
    chunked = streamed or progress_enabled(args.progress)
    if chunked and params.spring.solver != "exact":
        raise UsageError("--stream, --resume and --progress run the closed-form event loop in chunks; "
                         f"the {params.spring.name} spring runs in one call (drop them)")
    if streamed:
        return _stream_command(args, params, initial, out)
    _keep(args)
    # refuse up front what would meet the OOM killer (a closed-form run longer than a chunk streamed above)
    if args.dt_sample is not None:
        hint = "--dt-sample needs the whole run in memory: fewer --events, or no --dt-sample (the run then streams)"
    elif params.spring.solver != "exact":
        hint = f"the {params.spring.name} spring runs in one call: fewer --events"
    else:
        hint = "a smaller --chunk (a run of more events than --chunk streams)"
    check_memory(args.events, hint=hint)
    with _signals_end_the_process():
        def run(t_max):
            stop = {"max_events": args.events, "t_max": t_max, "energy_stop": args.energy_stop}
            if progress_enabled(args.progress):  # in chunks, to draw the bar (the same bits as one call)
                return simulate_chunked(params, initial, chunk=args.chunk, progress=True, **stop)
            return simulate(params, initial, **stop)

        if args.dt_sample is None:
            traj, times = run(args.t_max), None
        else:
            traj = _simulate_sampled(run, args.t_max, args.dt_sample)
            times = _sample_times(traj, args.t_max, args.dt_sample)
        dataset = to_dataset(traj, times)
    write_netcdf(dataset, out, compression=args.compression)
    counts = np.bincount(traj.kind, minlength=len(KIND_NAMES))
    print(_summary(len(traj), counts, traj.stop_reason, traj.t_end, out, None if times is None else len(times)))
    return EXIT_OK


def _method_command(args, method, params, initial, out) -> int:
    """Run the general-purpose ``method`` and write the impacts it reports (bounce.io.method_dataset)."""
    if args.progress:
        raise UsageError(f"--progress: only with the exact solver (drop --method {args.method})")
    check_memory(args.events, 4 * 8)  # t, xdot and the method's per-impact arrays
    with _signals_end_the_process():
        result = method.run(params, initial, max_events=args.events, t_max=args.t_max)
        dataset = method_dataset(result, params, initial, args.events, args.t_max)
    write_netcdf(dataset, out, compression=args.compression)
    stop = result.failure or ("max_events" if len(result.t) >= args.events else "t_max")
    print(f"bounce: {len(result.t)} impacts by method {result.method}, stop: {stop}, t_end = {result.t_end:.10g}; "
          f"wrote {out}")
    return EXIT_OK


@contextlib.contextmanager
def _signals_end_the_process():
    """While the compiled kernels run and nothing is written yet, SIGINT and SIGTERM take their default action:
    the process ends at once (status 128 + signal in the shell), no file touched.  A kernel returns to the
    interpreter only when it is done, and :func:`main`'s handlers run only then (a power-law run of minutes
    ignored both until its end).  A signal the process was started ignoring (SIGINT of a background job)
    stays ignored; the previous handlers are restored for the write."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {}
    for signum in (signal.SIGINT, signal.SIGTERM):
        handler = signal.getsignal(signum)
        if handler is not signal.SIG_IGN:
            previous[signum] = signal.signal(signum, signal.SIG_DFL)
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, signal.SIG_DFL if handler is None else handler)  # None: not set from Python


def _join_negative_numbers(argv: list[str]) -> list[str]:
    """``--opt -1e-3`` -> ``--opt=-1e-3``: argparse takes "-1e-3" and "-inf" for options otherwise."""
    out: list[str] = []
    for tok in argv:
        prev = out[-1] if out else ""
        if tok.startswith("-") and prev.startswith("--") and "=" not in prev and prev not in ("--help", "--version"):
            try:
                float(tok)
            except ValueError:
                pass
            else:
                out[-1] = f"{prev}={tok}"
                continue
        out.append(tok)
    return out


def _reject_repeated_options(argv: list[str]) -> None:
    """An option given twice is an error (argparse would silently keep the last value)."""
    seen = set()
    for tok in argv:
        if tok.startswith("--") and len(tok) > 2:
            name = tok.split("=", 1)[0]
            if name in seen:
                raise UsageError(f"{name} is given more than once (allowed: once per option)")
            seen.add(name)


def _one_line(message) -> str:
    if isinstance(message, OSError) and message.strerror and message.filename is None:
        message = message.strerror
    return " ".join(str(message).split())


def main(argv=None) -> int:
    """Run the CLI on ``argv`` (default ``sys.argv[1:]``); return the exit status.

    SIGTERM is turned into an exception for the duration (temporary files are then
    removed as on any failure) and the previous handler restored afterwards; while a simulation
    computes, before anything is written, SIGINT and SIGTERM end the process at once
    (:func:`_signals_end_the_process`).
    """
    with_handler = True
    try:
        try:
            previous = signal.signal(signal.SIGTERM, _raise_terminated)
        except ValueError:  # not the main thread: leave signals alone
            with_handler = False
        argv = sys.argv[1:] if argv is None else list(argv)
        if argv[:1] == ["check"]:  # one claim of bounce.checks, alone
            from .claims_cli import main as check_main

            return check_main(argv[1:])
        argv = _join_negative_numbers(argv)
        _reject_repeated_options(argv)
        if argv[:1] == ["gas"]:  # a gas of grains (bounce.gas_cli)
            from .gas_cli import main as gas_main

            return gas_main(argv[1:])
        args = build_parser().parse_args(argv)
        if args.command == "simulate":
            return _simulate_command(args)
        raise UsageError(f"unknown command {args.command!r}")  # pragma: no cover (argparse checks)
    except SystemExit as exc:  # --help, --version
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else EXIT_FAILURE)
    except (UsageError, InputError) as exc:
        print(f"error: {_one_line(exc)}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("error: interrupted (SIGINT); the output file is left as it was", file=sys.stderr)
        return EXIT_SIGINT
    except Terminated:
        print("error: terminated (SIGTERM); the output file is left as it was", file=sys.stderr)
        return EXIT_SIGTERM
    except MemoryError:
        print("error: not enough memory (reduce --events or increase --dt-sample)", file=sys.stderr)
        return EXIT_FAILURE
    except (OSError, RuntimeError) as exc:
        print(f"error: {_one_line(exc)}", file=sys.stderr)
        return EXIT_FAILURE
    finally:
        if with_handler:
            signal.signal(signal.SIGTERM, signal.SIG_DFL if previous is None else previous)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
