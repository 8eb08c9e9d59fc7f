"""What the paper says it sees in figs. rigid-fall and very_rigid_poincare(_magni), measured.

* fig. rigid-fall (section 8.1): "a sudden drop of the maximum height reached by the
  mechanical system between the fourth and the sixth macroscopic flight";
  macroscopic flights are those longer than T_xi = pi / sqrt(1 - mu^2) (same section).
* fig. very_rigid_poincare: early contacts are double impacts, "whose signature is
  the alternation of negative and positive values of ydot" (zig-zag).
* fig. very_rigid_poincare: "at later times the sequence of states becomes very disordered, and
  lacks any easily recognizable pattern, except a tendency to move towards the equilibrium
  point" (section 8.1).  Measured on the states s_n = (Y_n - y_eq, Ydot_n) just after contact n:
  the phase begins where the zig-zag breaks (Ydot_n, Ydot_{n+1} of one sign) and a pattern is a
  linear return map s_{n+1} = A s_n (the zig-zag and the late spiral are each one, to within a few
  per cent: eq. mappa is linear); the fraction of sum |s_{n+1}|^2 that the best such map leaves
  unexplained over windows of contacts measures the disorder.  Those contacts lie past the float64
  predictability horizon (the methods study ``horizon``: ~120 contacts for this scene), so the
  individual states are not the true trajectory's: what is judged is a property of the sequence.
* fig. very_rigid_poincare_magni: late contacts spiral in towards (0, 0, 0): y - y_eq
  and ydot oscillate with a decaying amplitude.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import xarray as xr

from ..figures.common import WIDTH, plt, save
from ..io import sample_dataset
from ..analysis.theory import T_xi
from .base import NOT_CHECKABLE, PAPER, Check, Falsifier, Verdict, claim, judge, on_input, with_variable

#: the inputs the falsifiers doctor by position (on_input): 0 the fall of fig. rigid-fall, 1 the contacts of
#: fig. very_rigid_poincare


def _var(value, long_name):
    return xr.DataArray(value, attrs={"long_name": long_name, "units": "1"})


def apex_heights(ds, samples_per_flight: int, factor: float) -> tuple[np.ndarray, np.ndarray]:
    """Start times and maximum y of the macroscopic flights (tau > factor T_xi) of a trajectory dataset.

    The paper's boundary is T_xi itself, but the flights inside a double impact last
    about T_xi too (3.0-3.2 for mu = 0.01, T_xi = 3.14), so a factor > 1 separates them.
    """
    mu = float(ds.attrs["mu"])
    t_xi = factor * T_xi(mu)
    t, tau = ds["t"].values, ds["tau"].values
    starts, peaks = [], []
    for k in range(t.size - 1):
        if tau[k + 1] > t_xi:  # the flight after event k ends at event k + 1
            grid = np.linspace(t[k], t[k + 1], samples_per_flight)
            starts.append(t[k])
            peaks.append(np.nanmax(sample_dataset(ds, grid)["y"]))
    return np.array(starts), np.array(peaks)


def contact_states(ds) -> np.ndarray:
    """s_n = (Y_n - y_eq, Ydot_n) just after every contact, shape (n, 2)."""
    return np.stack([ds["y_minus_yeq"].values, ds["ydot"].values], axis=1)


def unexplained(states: np.ndarray) -> float:
    """Fraction of sum |s_{n+1}|^2 that the least-squares linear map s_{n+1} = A s_n (fixed point: the equilibrium)
    leaves unexplained over these consecutive states: ~0 for the zig-zag and the spiral, ~1 without pattern."""
    before, after = states[:-1], states[1:]
    a = np.linalg.lstsq(before, after, rcond=None)[0]
    return float(np.sum((after - before @ a) ** 2) / np.sum(after ** 2))


def disordered_phase(ds, window: int, pattern_max: float) -> SimpleNamespace:
    """The phase after the zig-zag: its first record index (where Ydot_n, Ydot_{n+1} first share a sign), the
    unexplained fraction of consecutive windows of ``window`` contacts from there until one is below ``pattern_max``
    (a linear map explains the sequence again: the spiral), its last record index (the end of the last disordered
    window, or the run's), the same fraction over the zig-zag's last window and the rms distance |s_n| from the
    equilibrium over the phase's two halves."""
    states = contact_states(ds)
    ydot = states[:, 1]
    same_sign = np.nonzero(np.sign(ydot[1:]) == np.sign(ydot[:-1]))[0]
    start = int(same_sign[0]) if same_sign.size else ydot.size
    fractions, end = [], ydot.size
    for lo in range(start, ydot.size - window + 1, window):
        fractions.append(unexplained(states[lo: lo + window]))
        if fractions[-1] < pattern_max:
            end = lo
            break
    before = unexplained(states[start - window: start + 1]) if start >= window else float("nan")
    phase = np.hypot(states[start:end, 0], states[start:end, 1])
    half = phase.size // 2
    rms = [float(np.sqrt(np.mean(part ** 2))) if part.size else float("nan") for part in (phase[:half], phase[half:])]
    return SimpleNamespace(start=start, end=end, fractions=np.array(fractions), zigzag=before, rms_first=rms[0],
                           rms_second=rms[1])


def measure(spec: dict, inputs: list[xr.Dataset]) -> SimpleNamespace:
    """Apex heights of the macroscopic flights of fig. rigid-fall; Ydot_n and Y_n - y_eq of the contacts."""
    fall, contacts = inputs
    starts, peaks = apex_heights(fall, int(spec["samples_per_flight"]), float(spec["macroscopic_factor"]))
    ratios = peaks[1:] / peaks[:-1]
    k = int(np.argmin(ratios)) + 1  # the drop is from macroscopic flight k to k + 1 (1-based)
    n_zig = int(spec["zigzag_contacts"])
    ydot = contacts["ydot"].values
    alternation = float(np.mean(np.sign(ydot[1:n_zig]) != np.sign(ydot[: n_zig - 1])))
    a, b = spec["spiral_contacts"]
    ydev = contacts["y_minus_yeq"].values[a:b]
    sign_changes = int(np.count_nonzero(np.diff(np.sign(ydev)) != 0))
    third = max(ydev.size // 3, 1)
    amp_first, amp_last = float(np.max(np.abs(ydev[:third]))), float(np.max(np.abs(ydev[-third:])))
    disorder = disordered_phase(contacts, int(spec["disorder_window"]), float(spec["pattern_unexplained_max"]))
    disorder.spiral = unexplained(contact_states(contacts)[a:b])
    data = xr.Dataset({
        "apex_time": ("flight", starts, {"long_name": "start of the macroscopic flight", "units": "1"}),
        "apex_height": ("flight", peaks, {"long_name": "maximum height of the upper mass in the flight", "units": "1"}),
        "largest_drop_flight": _var(k, "macroscopic flight after which the largest height drop occurs"),
        "zigzag_fraction": _var(alternation, "fraction of sign alternations of Ydot_n, early contacts"),
        "spiral_sign_changes": _var(sign_changes, "sign changes of Y_n - y_eq, late contacts"),
        "disorder_start": _var(disorder.start + 1, "first contact of the disordered phase (the zig-zag breaks)"),
        "disorder_unexplained": ("window", disorder.fractions,
                                 {"long_name": "fraction of |s_{n+1}|^2 no linear return map explains, windows of "
                                               "contacts from the disordered phase's start", "units": "1"}),
    })
    data.attrs.update(gamma=float(fall.attrs["gamma"]), mu=float(fall.attrs["mu"]))
    return SimpleNamespace(peaks=peaks, ratios=ratios, k=k, alternation=alternation, sign_changes=sign_changes,
                           amp_first=amp_first, amp_last=amp_last, disorder=disorder,
                           n_contacts=contacts.sizes["event"], data=data)


CLAIMS: list = []


def _first_flight_missing(ds):
    """The fall restarted at the landing that ends its first macroscopic flight (flights longer than 2 T_xi): the
    state after that event becomes the initial one, the later records are kept with t from it."""
    k = 1 + int(np.argmax(ds["tau"].values[2:] > 2.0 * T_xi(float(ds.attrs["mu"]))))  # the flight after event k
    out = ds.isel(event=slice(k + 1, None))
    out = out.assign_coords(event=np.arange(out.sizes["event"]))
    out = with_variable(out, "t", out["t"].values - float(ds["t"].values[k]))
    out.attrs.update(x0=0.0, xdot0=float(ds["xdot"].values[k]), xidot0=float(ds["xidot"].values[k]),
                     eta0=float(ds["eta"].values[k]), initial_form="deviations",
                     y0=float(ds["y"].values[k]), ydot0=float(ds["ydot"].values[k]),
                     **{a: float(ds.attrs[a]) - float(ds["t"].values[k]) for a in ("t_valid", "t_end")})
    return out


def _upper_mass_falling(ds):
    """Contacts at which the upper mass is always falling (ydot -> -|ydot|): no zig-zag."""
    return with_variable(ds, "ydot", -np.abs(ds["ydot"].values))


def _spiral_outwards(ds):
    """The contacts' y - y_eq in reverse order: an oscillation growing instead of decaying."""
    return with_variable(ds, "y_minus_yeq", ds["y_minus_yeq"].values[::-1])


def _straight_to_the_spiral(inputs, spec):
    """The contacts from the zig-zag's break on replaced by the late spiral's own linear map (fitted on the contacts
    ``spiral_contacts``, eq. mappa's regime) iterated from the state there: the zig-zag turning straight into the
    spiral."""
    a, b = spec["spiral_contacts"]
    return on_input(1, lambda ds: _iterate_spiral_map(ds, a, b))(inputs, spec)


def _iterate_spiral_map(ds, first: int, last: int):
    states = contact_states(ds)
    ydot = states[:, 1]
    start = int(np.nonzero(np.sign(ydot[1:]) == np.sign(ydot[:-1]))[0][0])
    late = states[first:last]
    a = np.linalg.lstsq(late[:-1], late[1:], rcond=None)[0]
    for n in range(start + 1, states.shape[0]):
        states[n] = states[n - 1] @ a
    return with_variable(with_variable(ds, "y_minus_yeq", states[:, 0]), "ydot", states[:, 1])


@claim(CLAIMS, "height-drop", PAPER, "fig:rigid-fall",
       falsifier=Falsifier("the fall's record missing its first macroscopic flight (flights counted from the second)",
                           on_input(0, _first_flight_missing)))
def height_drop(m, spec) -> Verdict:
    lo, hi = spec["drop_between"]
    k = m.k
    return Verdict("sudden drop of the maximum height between the 4th and the 6th macroscopic flight",
                   "fig. rigid-fall, section 8.1",
                   f"max y per flight longer than {spec['macroscopic_factor']} T_xi; the largest relative drop "
                   "between consecutive ones",
                   f"drop from flight k to k+1 with {lo} <= k, k+1 <= {hi}",
                   f"largest drop from flight {k} to {k + 1} (ratio {m.ratios[k - 1]:.3f}); heights "
                   + ", ".join(f"{h:.2f}" for h in m.peaks[: k + 2]),
                   "exact (flight indices are integers)", judge(lo <= k and k + 1 <= hi))


@claim(CLAIMS, "zigzag", PAPER, "fig:very_rigid_poincare",
       falsifier=Falsifier("contacts with the upper mass always falling (ydot -> -|ydot|)",
                           on_input(1, _upper_mass_falling)))
def zigzag(m, spec) -> Verdict:
    return Verdict("early contacts are double impacts: ydot alternates in sign (zig-zag)",
                   "fig. very_rigid_poincare, section 8.1",
                   f"fraction of sign alternations of Ydot_n over the first {int(spec['zigzag_contacts'])} contacts",
                   ">= 0.9", f"{m.alternation:.3f}", "0.9: a single-impact phase would alternate at most half the time",
                   judge(m.alternation >= 0.9))


@claim(CLAIMS, "spiral", PAPER, "fig:very_rigid_poincare",
       falsifier=Falsifier("the contacts' y - y_eq in reverse order (a spiral outwards)", on_input(1, _spiral_outwards)))
def spiral(m, spec) -> Verdict:
    a, b = spec["spiral_contacts"]
    return Verdict("late contacts spiral towards (0,0,0): damped oscillation of Y_n - y_eq",
                   "fig. very_rigid_poincare_magni, section 8.1",
                   f"sign changes of Y_n - y_eq and its amplitude, first vs last third of contacts {a}-{b}",
                   ">= 4 sign changes, amplitude decreasing",
                   f"{m.sign_changes} sign changes; amplitude {m.amp_first:.2e} -> {m.amp_last:.2e}",
                   "qualitative claim: any oscillation (>= 4 sign changes) with decaying envelope",
                   judge(m.sign_changes >= 4 and m.amp_last < m.amp_first))


@claim(CLAIMS, "disordered-phase", PAPER, "fig:very_rigid_poincare",
       falsifier=Falsifier("the zig-zag turning straight into the late spiral (its linear map iterated from the "
                           "zig-zag's break on)", _straight_to_the_spiral))
def disordered_phase_claim(m, spec) -> Verdict:
    d, window = m.disorder, int(spec["disorder_window"])
    lo, hi = float(spec["disorder_unexplained_min"]), float(spec["pattern_unexplained_max"])
    if not d.fractions.size:
        return Verdict("after the zig-zag the states become very disordered, with a tendency towards equilibrium",
                       "fig. very_rigid_poincare, section 8.1", "the contacts after the zig-zag", "a disordered phase",
                       f"the zig-zag lasts the whole run ({d.start} contacts)", "-", NOT_CHECKABLE)
    ends = (f"a linear map explains contacts {d.end + 1}-{d.end + window} again (the spiral)" if d.end < m.n_contacts
            else "the phase lasts to the end of the run")
    return Verdict("after the zig-zag the states become very disordered, lacking any easily recognizable pattern, "
                   "except a tendency to move towards the equilibrium point",
                   "fig. very_rigid_poincare, section 8.1",
                   f"from the contact where the zig-zag breaks, windows of {window} contacts: the fraction of "
                   "|s_{n+1}|^2, s_n = (Y_n - y_eq, Ydot_n), the best linear return map leaves unexplained, until one "
                   f"leaves < {hi} (compared with the zig-zag's last window and the spiral's contacts); rms |s_n| over "
                   "the phase's two halves",
                   f">= {lo} unexplained in the first window (no map explains half the sequence) and the rms distance "
                   "falling from the first half to the second",
                   f"zig-zag breaks at contact {d.start + 1}; unexplained " + ", ".join(f"{f:.2f}" for f in d.fractions)
                   + f" in windows from contact {d.start + 1} (zig-zag's last {d.zigzag:.3f}, spiral {d.spiral:.3f}); "
                   f"{ends}; rms |s_n| {d.rms_first:.2e} -> {d.rms_second:.2e}",
                   f"{lo}: a sequence with a pattern (a linear map) leaves ~0, one without any leaves ~1; "
                   "the contacts are past the float64 horizon: a property of the sequence is judged, not its states",
                   judge(d.fractions[0] >= lo and d.rms_second < d.rms_first))


def plot(ds, spec, outputs) -> None:
    fig, ax = plt.subplots(figsize=(WIDTH, 2.8))
    h = ds["apex_height"].values
    k = int(ds["largest_drop_flight"])
    idx = np.arange(1, h.size + 1)
    ax.plot(idx, h, "o-", ms=3)
    ax.plot([k, k + 1], h[[k - 1, k]], "r-", lw=2, label=f"largest drop: flight {k} -> {k + 1}")
    ax.axvspan(*spec["drop_between"], color="0.9", label="paper: between the 4th and 6th flight")
    ax.set_xlabel("macroscopic flight (longer than %g $T_\\xi$)" % spec["macroscopic_factor"])
    ax.set_ylabel("max $y$ in the flight  [$L$]")
    ax.set_title("check paper-figures: apex heights of fig. rigid-fall ($\\gamma=\\mu=%g$)" % ds.attrs["gamma"])
    ax.legend()
    save(fig, outputs)


CHECK = Check("paper-figures", measure, tuple(CLAIMS), plot,
              title="What the paper sees in figs. rigid-fall and very_rigid_poincare")
