"""Speed of the gas engines (bounce.gas): events/s on one core on a cooling ring of dimers, and the rigid gas.

What is measured, per N (default 1e3 and 1e5):

* the ring: circumference ell = 1.5 N (mean gap 0.5 rest lengths), grains at uniformly random places,
  springs at rest, velocities normal with standard deviation 0.1 and zero total momentum, mu = 0.05
  (an effective restitution exp(-mu pi / omega) = 0.855 per relaxed collision); after a warm-up of
  10 N events (the cooling regime: internal modes excited, temperature falling), ``--events`` events
  are timed (CPU time of the process, ``--repeats`` times from the same warmed-up state; medians);
* ns/event split three ways, each measured on its own over the same events:
  - prediction: the predictions the engine makes for the first 20000 of those events (the fired pair's
    from its contact, the two neighbours' from the grains' states), recomputed from the recorded
    post-event states of the four grains involved: every window, and the searches the lazy engine
    runs (not those of pending slots predicted again before their window starts, :func:`engine_runs`;
    ``searched``: their number per event);
  - queue: the same sequence of key updates (three per event) replayed on the queue's tree (the second
    update of a pending slot's resolution is not replayed: it counts as bookkeeping);
  - bookkeeping: the rest (advancing grains, the exchange, records): total - prediction - queue;
* the rigid engine on the same initial state (grains of length 1) with r = 0.855, the TC model on
  (t_c = 1e-3 mean free times: without it a ring of N >> N_c(0.855) ~ 13 grains collapses at once):
  events/s over the same number of events.

Peer comparison (``--peer billiards``, issue 23): published event-driven hard-sphere codes (3-D, cell or
neighbour lists, e.g. F. Smallenburg, arXiv:2201.01100, which benchmarks itself against DynamO and others)
are C/C++ programs, not in the package registries reachable here.  PyPI has two event-driven hard-particle
packages: ``hardspheres-2d`` (a Rust/maturin sdist requiring Python >= 3.13; bounce runs on 3.11 and the
Rust crates it needs cannot be fetched here: not run) and ``billiards`` 0.5.0 (pure Python and numpy, 2-D
disks, elastic only, walls but no periodic boundary, an all-pairs time-of-impact table recomputed in O(N)
per collision, no cell list, float64).  The latter runs: the ring's grains become disks of radius 1/2 on a
line between two walls ell apart (same N, density, velocities; r = 1), beside the rigid engine on the ring
with r = 1 and no TC model.  An event is a collision in both (the peer's include the rare ones with a
wall, printed); their first 150 pair collisions are the same pairs at times equal to 4e-11 relative (the
peer's positions accumulate rounding).  The peer is imported only when asked; install it in its own venv
with ``--no-deps`` and put that venv's site-packages on PYTHONPATH.

Every contact time is to rounding in these runs (the engine has no accuracy setting).  The process is
pinned to one core when possible; the machine may be shared: the load average before and after is
printed.  Run::

    python benchmarks/bench_gas.py                     # N = 1e3 and 1e5, 2e6 events, 5 repeats
    python benchmarks/bench_gas.py --n 1000 --events 200000 --repeats 3
    PYTHONPATH=$PYTHONPATH:/work/peer-venv/lib/python3.11/site-packages \
        python benchmarks/bench_gas.py --n 1000 --events 200000 --repeats 3 --peer billiards
"""

from __future__ import annotations

import argparse
import copy
import math
import os
import statistics
import time

import numpy as np
from numba import njit

from bounce.exact.flight import EPS
from bounce.exact.short_flight import MAX_DEGREE
from bounce.gas import GasParameters, GasRun, GasState, RigidParameters, RigidState
from bounce.gas.dimer import (
    G_A, G_ETA, G_U, G_X, _contact_lower_bound, _lazy_key, _pair_gap, _pair_limits, _search, grain_at,
)
from bounce.gas.queue import add_time, build, top, update

MU = 0.05


def ring(n: int, seed: int = 1):
    rng = np.random.default_rng(seed)
    ell = 1.5 * n
    v = rng.normal(0.0, 0.1, n)
    v -= v.mean()
    x = np.concatenate([[0.0], np.cumsum(rng.dirichlet(np.ones(n))[:-1] * (ell - n) + 1.0)])
    return ell, x, v


@njit(cache=True)
def predictions(local, speeds, params, coefs, keys_slot, keys_hi, keys_lo, times, slots, runs, starts):
    """The three predictions of every recorded pair event from the states of its four grains (i-1, i, j, j+1)
    just after it, positions unwrapped (local[e, k] = x, x', xi', eta): the fired pair (i, j) from its
    contact (gap 0, velocity the approach speed), its two neighbours from the grains' states.  Each
    computes its window and the lower bound it may be queued pending at (into ``starts``: the window's start or
    the march's first step, bounce.gas.dimer._contact_lower_bound) and runs its search where ``runs`` says the
    engine does (:func:`engine_runs`); the keys into keys_* (for the queue replay: a search not run leaves the
    lazy key of bounce.gas.dimer._lazy_key)."""
    work = np.empty(MAX_DEGREE + 2)
    g = np.zeros((4, 6))
    m = 0
    for e in range(speeds.size):
        for k in range(4):
            g[k, G_X], g[k, G_U], g[k, G_A], g[k, G_ETA] = local[e, k]
        for which in range(3):
            i = (1, 0, 2)[which]
            j = i + 1
            if which == 0:
                x0, w, sd, s0, noise = 0.0, speeds[e], g[i, G_A] + g[j, G_A], g[i, G_ETA] + g[j, G_ETA], 0.0
            else:
                x0, w, sd, s0, noise = _pair_gap(g, i, j, False, 0.0, 0.0)
                if x0 <= noise:
                    x0 = 0.0
            t_start, t_limit, proves = _pair_limits(x0, w, sd, s0, math.inf)
            bound = _contact_lower_bound(x0, w, sd, s0, t_start, t_limit, params[0])
            starts[e, which] = bound
            keys_slot[m] = slots[e, which]
            if runs[e, which]:
                window = 8.0 * EPS * (abs(s0) + 2.0 * params[0] * abs(sd))
                status, tau, v, sc, eta_t, xid_t, _ = _search(x0, w, sd, s0, 0.0, window, noise / (4.0 * EPS),
                                                              t_start, t_limit, params, coefs, work)
                k_hi, k_lo = add_time(times[e], 0.0, tau if status == 0 else math.inf)
            else:
                k_hi, k_lo = _lazy_key(times[e], bound), 0.0
            keys_hi[m] = k_hi
            keys_lo[m] = k_lo
            m += 1
    return m


def engine_runs(starts, slots, times):
    """Which of the recorded predictions the lazy engine searches: all but a pending one (lower bound > 0)
    whose slot is predicted again (by a later event) before its bound comes (bounce.gas.dimer, "Lazy
    predictions"; those at the end of the stretch count as searched).  The engine also searches at once a
    first-step bound that ends before both neighbours' keys (not known here): such a slot is predicted again
    before its bound only if a neighbour's key moves earlier first, so the count is the engine's to that."""
    runs = np.ones(starts.shape, dtype=np.bool_)
    following = {}  # slot -> time of its next prediction, filled backwards
    for e in range(starts.shape[0] - 1, -1, -1):
        for which in range(3):
            s = int(slots[e, which])
            nxt = following.get(s)
            if starts[e, which] > 0.0 and nxt is not None and nxt < times[e] + starts[e, which]:
                runs[e, which] = False
        for which in range(3):
            following[int(slots[e, which])] = times[e]
    return runs


@njit(cache=True)
def replay(tree, khi, klo, keys_slot, keys_hi, keys_lo, m):
    """The queue's work: the key updates of the events in order, plus a look at the top per event."""
    tops = 0
    for k in range(m):
        update(keys_slot[k], keys_hi[k], keys_lo[k], tree, khi, klo)
        if k % 3 == 2:
            tops += top(tree, khi)
    return tops


def cpu(f):
    t0 = time.process_time()
    out = f()
    return time.process_time() - t0, out


def bench_dimer(n: int, events: int, repeats: int) -> dict:
    ell, x, v = ring(n)
    p = GasParameters(n, "ring", 0.0, MU, ell)
    state = GasState(x, v, np.zeros(n), np.zeros(n))
    warm = GasRun(p, state, math.inf, 0)
    warm.step(10 * n)
    start = warm.arrays()
    totals = []
    for _ in range(repeats):
        run = GasRun(p, state, math.inf, 0, arrays=start)
        sec, _ = cpu(lambda: run.step(events))
        assert run.events == 10 * n + events, run.stop
        totals.append(sec / events * 1e9)
    # the split, on a stretch of at most 20000 events (the post-event states of their four grains are kept)
    m = min(events, 20_000)
    run = GasRun(p, state, math.inf, 0, arrays=start)
    local = np.empty((m, 4, 4))
    slots = np.empty((m, 3), dtype=np.int64)
    speeds = np.empty(m)
    times = np.empty(m)
    for e in range(m):
        rec, k, _ = run.step(1)
        s = int(rec.pair[0])
        grains = [(s - 1) % n, s, (s + 1) % n, (s + 2) % n]
        shift = 0.0
        for kk, grain in enumerate(grains):
            if kk and grain < grains[kk - 1]:
                shift += ell
            x_k, u_k, a_k, eta_k = grain_at(run.g, grain, run.clock[0], run.clock[1], 0.0, *run.osc)
            local[e, kk] = (x_k + shift, u_k, a_k, eta_k)
        slots[e] = (s, (s - 1) % n, (s + 1) % n)
        speeds[e], times[e] = rec.speed[0], rec.t[0]
    keys = (np.empty(3 * m, dtype=np.int64), np.empty(3 * m), np.empty(3 * m))
    starts = np.empty((m, 3))
    predictions(local, speeds, *run.osc, *keys, times, slots, np.zeros((m, 3), np.bool_), starts)  # windows
    runs = engine_runs(starts, slots, times)
    pred = statistics.median(cpu(lambda: predictions(local, speeds, *run.osc, *keys, times, slots, runs, starts))[0]
                             for _ in range(repeats)) / m * 1e9
    queue = []
    for repeat in range(repeats + 1):  # the first compiles
        tree, khi, klo = start["tree"].copy(), start["khi"].copy(), start["klo"].copy()
        build(tree, khi, klo)
        sec = cpu(lambda: replay(tree, khi, klo, *keys, 3 * m))[0]
        if repeat:
            queue.append(sec / m * 1e9)
    total = statistics.median(totals)
    q = statistics.median(queue)
    return {"n": n, "ns_per_event": total, "events_per_s": 1e9 / total, "min": min(totals), "max": max(totals),
            "prediction": pred, "queue": q, "bookkeeping": total - pred - q, "split_events": m,
            "searched": runs.mean() * 3}


def bench_rigid(n: int, events: int, repeats: int) -> dict:
    ell, x, v = ring(n)
    free_time = (ell - n) / n / 0.1
    p = RigidParameters(n, "ring", 0.0, 0.855, ell=ell, size=1.0, t_c=1e-3 * free_time)
    start = GasRun(p, RigidState(x, v), math.inf, 0).arrays()
    state = RigidState(x, v)
    GasRun(p, state, math.inf, 0, arrays=start).step(10)  # compile
    totals = []
    for _ in range(repeats):
        run = GasRun(p, state, math.inf, 0, arrays=start)
        sec, _ = cpu(lambda: run.step(events))
        totals.append(sec / max(run.events, 1) * 1e9)
    return {"n": n, "ns_per_event": statistics.median(totals), "events_per_s": 1e9 / statistics.median(totals),
            "stop": run.stop, "events": run.events}


def bench_rigid_elastic(n: int, events: int, repeats: int) -> dict:
    """The rigid engine on the peer's system: the same ring, r = 1, no TC model."""
    ell, x, v = ring(n)
    p = RigidParameters(n, "ring", 0.0, 1.0, ell=ell, size=1.0)
    state = RigidState(x, v)
    start = GasRun(p, state, math.inf, 0).arrays()
    GasRun(p, state, math.inf, 0, arrays=start).step(10)  # compile
    totals = []
    for _ in range(repeats):
        run = GasRun(p, state, math.inf, 0, arrays=start)
        sec, _ = cpu(lambda: run.step(events))
        assert run.events == events, run.stop
        totals.append(sec / events * 1e9)
    return {"ns_per_event": statistics.median(totals), "events_per_s": 1e9 / statistics.median(totals)}


def billiards_table(n: int):
    """The ring's grains as the peer's disks of radius 1/2 on the line y = 0 (velocities along it), between
    two walls ell apart (the ring's last gap split between them): same N, density and velocities."""
    from billiards import Billiard, InfiniteWall
    ell, x, v = ring(n)
    half_gap = (ell - x[-1] - 1.0) / 2.0
    walls = [InfiniteWall((-half_gap, -1.0), (-half_gap, 1.0), inside="right"),
             InfiniteWall((ell - half_gap, -1.0), (ell - half_gap, 1.0), inside="left")]
    table = Billiard(walls)
    for x_k, v_k in zip(x, v):
        table.add_ball((x_k + 0.5, 0.0), (v_k, 0.0), radius=0.5)
    return table


def bench_peer_billiards(n: int, events: int, repeats: int) -> dict:
    """The peer: ``events`` collisions of :func:`billiards_table`, the next one chosen as its ``evolve`` does."""
    start = billiards_table(n)
    totals, walls = [], 0
    for _ in range(repeats):
        table = copy.deepcopy(start)

        def collide():
            kinds = 0
            for _ in range(events):
                if table.toi_next[0] <= table.obstacles_next[0]:
                    table.bounce_ballball()
                else:
                    table.bounce_ballobstacle()
                    kinds += 1
            return kinds

        sec, walls = cpu(collide)
        totals.append(sec / events * 1e9)
    return {"ns_per_event": statistics.median(totals), "events_per_s": 1e9 / statistics.median(totals),
            "wall_fraction": walls / events}


PEERS = {"billiards": bench_peer_billiards}


def peer_row(name: str, n: int, events: int, peer_events: int, repeats: int) -> None:
    try:
        peer = PEERS[name](n, peer_events, repeats)
    except ImportError as exc:
        print(f"peer {name!r} is not installed ({exc}): install it in its own venv without its dependencies "
              f"(python -m venv /work/peer-venv && /work/peer-venv/bin/pip install --no-deps {name}) and put that "
              "venv's site-packages on PYTHONPATH", flush=True)
        return
    rigid = bench_rigid_elastic(n, events, repeats)
    print(f"{'rigid r=1':<10}{n:>8}{rigid['events_per_s']:>12.3g}{rigid['ns_per_event']:>12.0f}"
          f"   bounce.gas rigid engine, ring, {events} collisions", flush=True)
    print(f"{name:<10}{n:>8}{peer['events_per_s']:>12.3g}{peer['ns_per_event']:>12.0f}"
          f"   peer, box, {peer_events} collisions ({peer['wall_fraction']:.1%} with a wall); "
          f"ratio {peer['ns_per_event'] / rigid['ns_per_event']:.3g}", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="+", default=[1000, 100_000])
    ap.add_argument("--events", type=int, default=2_000_000)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--peer", choices=sorted(PEERS), help="also time this peer beside the rigid engine (r = 1)")
    ap.add_argument("--peer-events", type=int, default=1000, help="collisions per repeat for the peer")
    args = ap.parse_args()
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    load0 = os.getloadavg()
    wall0, cpu0 = time.time(), time.process_time()
    print(f"bounce.gas benchmark: {args.events} events x {args.repeats} repeats per row, one core; "
          f"load average before: {load0[0]:.2f} {load0[1]:.2f} {load0[2]:.2f} ({os.cpu_count()} CPUs)")
    print(f"{'engine':<8}{'N':>8}{'events/s':>12}{'ns/event':>10}{'(min..max)':>16}"
          f"{'prediction':>12}{'queue':>8}{'bookkeeping':>13}")
    for n in args.n:
        d = bench_dimer(n, args.events, args.repeats)
        spread = "({:.0f}..{:.0f})".format(d["min"], d["max"])
        print(f"{'dimer':<8}{n:>8}{d['events_per_s']:>12.3g}{d['ns_per_event']:>10.0f}"
              f"{spread:>16}{d['prediction']:>12.0f}{d['queue']:>8.0f}"
              f"{d['bookkeeping']:>13.0f}   searches/event: {d['searched']:.2f}", flush=True)
        r = bench_rigid(n, args.events, args.repeats)
        print(f"{'rigid':<8}{n:>8}{r['events_per_s']:>12.3g}{r['ns_per_event']:>10.0f}"
              f"{'':>16}{'':>12}{'':>8}{'':>13}   stop: {r['stop']} after {r['events']} events", flush=True)
    if args.peer:
        print(f"\npeer comparison (elastic hard rods of length 1, same N, density and velocities): "
              f"{args.repeats} repeats, medians")
        print(f"{'engine':<10}{'N':>8}{'events/s':>12}{'ns/event':>12}")
        for n in args.n:
            peer_row(args.peer, n, args.events, args.peer_events, args.repeats)
    load1 = os.getloadavg()
    print(f"CPU {time.process_time() - cpu0:.1f} s, wall {time.time() - wall0:.1f} s; load average after: "
          f"{load1[0]:.2f} {load1[1]:.2f} {load1[2]:.2f}")
    print("prediction and queue: the same events' searches and key updates measured alone (medians); "
          "bookkeeping = total - both")


if __name__ == "__main__":
    main()
