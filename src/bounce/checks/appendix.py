"""The Appendix's lemmas, iterated: Lemma alpha-map's conclusion, Lemma Giorgio's-2, Lemma Giorgio's with a
varying alpha_n.

* ``alpha-map-conclusion``: the implicit map f(alpha_{n+1}) = g(alpha_n) + b_n (eqs. f, g, fg-map) is
  iterated from a grid of alpha_0 in (0, 1) under several perturbations b_n -> 0 (both signs, powers of n)
  and b_n = 0.  The lemma says a sequence that stays in (0, 1) tends to 0; its proof, that once
  alpha_n^2/(1 - alpha_n)^3 + b_n > 0 the next iterate is larger (eq. g-minus-f), so that a sequence
  bounded away from 0 increases to a fixed point that does not exist.  Both are measured on every
  iterate; a fixed point of the map in (0, 1), or a sequence settling away from 0, would fail the row.
* ``giorgio2-divergence``: sequences with x_{n+1} = x_n + c_n x_n^2, |c_n| <= c (random c_n), whose sums
  must diverge like ln(n)/c at least (Lemma Giorgio's-2 with the comparison map z_{n+1} = z_n - c z_n^2).
* ``giorgio2-comparison`` (erratum): the proof's "x_n >= z_n for all n" needs z -> z - c z^2 increasing on
  the values taken, i.e. x_n <= 1/(2c); an exact rational sequence satisfying the hypotheses with
  x_0 > 1/(2c) breaks it.  The lemma's conclusion is unaffected (start the comparison where x_n <= 1/(2c)).
* ``giorgio-varying-alpha``: x_{n+1} = x_n - alpha_n x_n^2 + x_n^3 with alpha_n -> alpha (the lemma as
  stated, not only constant alpha, which check errata covers): n x_n -> 1/alpha.
"""

from __future__ import annotations

import math
from fractions import Fraction
from types import SimpleNamespace

import numpy as np
import xarray as xr

from .base import ERRATUM, PAPER, Check, Falsifier, Verdict, judge, recorded, variable

NAME = "appendix"


def f_map(x):
    """f(x) = 6x - 4x^2 + x^3 (eq. f)."""
    return 6 * x - 4 * x**2 + x**3


def g_map(x):
    """g(x) = (6x - 8x^2 + 3x^3)/(1 - x)^3 (eq. g)."""
    return (6 * x - 8 * x**2 + 3 * x**3) / (1 - x) ** 3


def f_inverse(v, start=None):
    """alpha in [0, 1] with f(alpha) = v for v in [0, 3] (f' = 6 - 8x + 3x^2 >= 2/3 > 0): Newton from ``start``
    (default v/6) until the step is below 1e-15 (at most 60 steps)."""
    x = np.clip(v / 6 if start is None else start, 0.0, 1.0)
    for _ in range(60):
        step = (f_map(x) - v) / (6 - 8 * x + 3 * x * x)
        x = np.clip(x - step, 0.0, 1.0)
        if np.all(np.abs(step) <= 1e-15):
            break
    return x


def iterate_alpha_map(alpha0, b):
    """Iterate eq. fg-map from each alpha0 with perturbations b[n]; returns (exit index or len(b), last alpha,
    count of steps where alpha^2/(1-alpha)^3 + b_n > 0 but alpha_{n+1} <= alpha_n)."""
    a = np.asarray(alpha0, dtype=float).copy()
    alive = np.ones(a.size, bool)
    exit_at = np.full(a.size, len(b))
    violations = 0
    for n, bn in enumerate(b):
        if not alive.any():
            break
        v = g_map(np.where(alive, a, 0.5)) + bn
        out = alive & ((v <= 0) | (v >= 3))  # f(alpha_{n+1}) outside f([0, 1]) = [0, 3]: alpha_{n+1} leaves (0, 1)
        exit_at[out] = n
        alive &= ~out
        new = f_inverse(np.where(alive, v, 1.0), np.where(alive, a, 0.5))
        rising = alive & (a**2 / (1 - a) ** 3 + bn > 0)
        violations += int(np.sum(rising & (new <= a)))
        a = np.where(alive, new, a)
        out = alive & ((a <= 0) | (a >= 1))
        exit_at[out] = n
        alive &= ~out
    return exit_at, a, violations


def giorgio2_step(x, c):
    """x_{n+1} = x_n + c_n x_n^2, the sequences of lem:Giorgio's-2 (|c_n| <= c)."""
    return x + c * x * x


#: the proof's comparison tested exactly: (x_0, x_1) with x_0 = 9/10 > 1/(2c), c = 1; x_2 = x_1 - c x_1^2
COMPARISON_START = (Fraction(9, 10), Fraction(19, 20))


def giorgio_remainder(x):
    """The o(x_n^2) term of the map of lem:Giorgio's iterated here: x_n^3."""
    return x**3


def measure(spec: dict, inputs=()) -> SimpleNamespace:
    rows: dict[str, Verdict] = {}
    data = {}

    # ---------------------------------------------------------------- Lemma alpha-map
    n_it = int(spec["alpha_iterations"])
    alpha0 = np.linspace(0.01, 0.99, int(spec["alpha_starts"]))
    nn = np.arange(1, n_it + 1, dtype=float)
    families = [("b = 0", np.zeros(n_it))]
    for sign in (-1, 1):
        for B in spec["b_scales"]:
            for p in spec["b_powers"]:
                families.append((f"b = {'+' if sign > 0 else '-'}{B:g} n^-{p:g}", sign * float(B) * nn ** -float(p)))
    stayed, stayed_far, violations, exits = 0, 0, 0, []
    for label, b in families:
        ex, last, viol = iterate_alpha_map(alpha0, b)
        stay = ex == n_it
        stayed += int(stay.sum())
        tail = np.sqrt(np.max(np.abs(b[n_it // 2:])))  # a sequence staying must end below this (proof, eq. g-minus-f)
        stayed_far += int(np.sum(stay & (last > max(tail, 1e-12))))
        violations += viol
        exits.append(ex)
    exits = np.array(exits)
    # a sequence that does stay: alpha_n = 1/(n + 2), with the b_n it defines (-> 0)
    a_seq = 1.0 / (nn + 2)
    b_seq = f_map(a_seq[1:]) - g_map(a_seq[:-1])
    rows["alpha-map-conclusion"] = Verdict(
        claim="A sequence alpha_n in (0, 1) obeying (1 - alpha_n)^3 f(alpha_{n+1}) = g-numerator(alpha_n) + o(1) "
              "tends to 0 (tau_n = o(T_n) in case 3 of sec. 5)",
        paper_ref="lem:alpha-map (eqs. f, g, fg-map, g-minus-f)",
        computed=f"eq. fg-map iterated {n_it} times from {alpha0.size} alpha_0 in [0.01, 0.99] under {len(families)} "
                 f"perturbations (b = 0, +-B n^-p, B in {list(spec['b_scales'])}, p in {list(spec['b_powers'])}); "
                 "on every iterate, whether alpha_n^2/(1-alpha_n)^3 + b_n > 0 implies alpha_{n+1} > alpha_n",
        expected="every sequence leaves (0, 1) or ends below sqrt(max_{n >= N/2} |b_n|); no violation of the "
                 "monotone step",
        measured=f"{int(np.sum(exits < n_it))} of {exits.size} sequences leave (0, 1) (the last at step "
                 f"{int(exits[exits < n_it].max()) if np.any(exits < n_it) else -1}; with b = 0 "
                 f"{int(np.sum(exits[0] < n_it))} of {alpha0.size} leave, by step {int(exits[0].max())}: no fixed point "
                 f"if all); {stayed} stay, {stayed_far} of them above the bound; {violations} violations. A sequence "
                 f"that stays exists (alpha_n = 1/(n+2) with b_n -> 0: |b_N| = {abs(b_seq[-1]):.2g}) and tends to 0",
        tolerance="exact counts (the monotone step is compared in float64 away from ties: violations would be "
                  "steps going down by more than rounding)",
        verdict=judge(stayed_far == 0 and violations == 0 and abs(b_seq[-1]) < abs(b_seq[0])))
    data["alpha_exit"] = variable(("family", "start"), exits, "iterations before alpha_n leaves (0, 1)")
    data["alpha0"] = variable("start", alpha0, "alpha_0")

    # ---------------------------------------------------------------- Lemma Giorgio's-2
    rng = np.random.default_rng(int(spec["seed"]))
    c = float(spec["giorgio2_c"])
    n2 = int(spec["giorgio2_iterations"])
    x0 = np.array([float(v) for v in spec["giorgio2_x0"]])
    k = int(spec["giorgio2_sequences"])
    xs = np.repeat(x0, k)
    zs = xs.copy()
    sums = np.zeros_like(xs)
    checkpoints = {n2 // 10: None, n2: None}
    below_z = 0
    for n in range(1, n2 + 1):
        sums += xs
        cn = rng.uniform(-c, 0.0, xs.size)  # |c_n| <= c; c_n > 0 only helps the divergence
        xs = giorgio2_step(xs, cn)
        zs = zs - c * zs * zs
        below_z += int(np.sum(xs < zs))
        if n in checkpoints:
            checkpoints[n] = sums.copy()
    growth = checkpoints[n2] - checkpoints[n2 // 10]  # diverging like ln(n)/c: at least ln(10)/c per decade
    decade = math.log(10) / c
    rows["giorgio2-divergence"] = Verdict(
        claim="If x_n > 0 and x_{n+1} = x_n + O(x_n^2) then sum x_n = infinity",
        paper_ref="lem:Giorgio's-2 (used in sec. 5, case Xddot_infinity != 0)",
        computed=f"{xs.size} sequences x_{{n+1}} = x_n + c_n x_n^2, c_n uniform in [-{c:g}, 0] (seed {spec['seed']}), "
                 f"x_0 in {x0.tolist()} (<= 1/(2c)), {n2} steps; the proof's comparison z_{{n+1}} = z_n - c z_n^2",
        expected=f"x_n >= z_n throughout; the partial sums grow by >= ln(10)/c = {decade:.4g} per decade of n "
                 "(sum z_n ~ ln(n)/c)",
        measured=f"x_n < z_n at {below_z} steps; growth over the last decade: min {growth.min():.4g}, max "
                 f"{growth.max():.4g}; all x_n > 0: {bool(np.all(xs > 0))}",
        tolerance="growth >= 0.95 ln(10)/c (the O(1/n) corrections of sum z_n over a decade are below 5 % at "
                  f"n >= {n2 // 10})",
        verdict=judge(below_z == 0 and bool(np.all(xs > 0)) and growth.min() >= 0.95 * decade))
    data["giorgio2_growth"] = variable("sequence", growth, "sum of x_n over the last decade of n")

    # the printed comparison, exactly: c = 1, x_0 = 9/10 > 1/(2c)
    cq = Fraction(1)
    x_seq = list(COMPARISON_START)
    x_seq.append(x_seq[1] - cq * x_seq[1] ** 2)
    z_seq = [x_seq[0]]
    for _ in range(2):
        z_seq.append(z_seq[-1] - cq * z_seq[-1] ** 2)
    hyp = all(abs(x_seq[i + 1] - x_seq[i]) <= cq * x_seq[i] ** 2 and x_seq[i + 1] > 0 for i in range(2))
    broken = [i for i in range(3) if x_seq[i] < z_seq[i]]
    rows["giorgio2-comparison"] = Verdict(
        claim="In the proof of Lemma Giorgio's-2: x_{n+1} >= x_n - c x_n^2 and z_{n+1} = z_n - c z_n^2, z_0 = x_0 give "
              "x_n >= z_n for all n >= 0",
        paper_ref="proof of lem:Giorgio's-2",
        computed=f"exact rationals: c = 1, x = ({x_seq[0]}, {x_seq[1]}, {x_seq[1]} - ({x_seq[1]})^2), which obey "
                 "|x_{n+1} - x_n| <= c x_n^2 and x_n > 0; z from the comparison map",
        expected="x_n >= z_n for n = 0, 1, 2 as printed",
        measured=f"x = {[str(v) for v in x_seq]}, z = {[str(v) for v in z_seq]}: hypotheses hold ({hyp}), x_n < z_n at "
                 f"n = {broken}. Erratum: the step needs z -> z - c z^2 increasing on the values taken (x_n, z_n <= "
                 "1/(2c)); start the comparison at an N beyond which x_n <= 1/(2c) (if x_n does not tend to 0, "
                 "sum x_n diverges anyway): the lemma holds",
        tolerance="exact (rational arithmetic)", verdict=judge(hyp and not broken))

    # ---------------------------------------------------------------- Lemma Giorgio's, alpha_n -> alpha
    a_lim = float(spec["giorgio_alpha"])
    n1 = int(spec["giorgio_iterations"])
    x = 0.1
    marks = {n1 // 100: 0.0, n1: 0.0}
    for n in range(1, n1 + 1):  # plain loop: the map itself
        a_n = a_lim * (1 + 1 / math.sqrt(n))
        x = x - a_n * x * x + giorgio_remainder(x)
        if n in marks:
            marks[n] = n * x * a_lim
    errs = {n: abs(v - 1) for n, v in marks.items()}
    bound = 3 / math.sqrt(n1) + 10 * math.log(n1) / n1  # 1/x_n ~ sum alpha_k = alpha (n + 2 sqrt n): n x_n alpha ~ 1 - 2/sqrt n
    rows["giorgio-varying-alpha"] = Verdict(
        claim="x_{n+1} = x_n - alpha_n x_n^2 + o(x_n^2) with alpha_n -> alpha > 0 gives n x_n -> 1/alpha",
        paper_ref="lem:Giorgio's",
        computed=f"alpha_n = {a_lim:g} (1 + n^-1/2), o(x^2) term + x_n^3, x_0 = 0.1, {n1} iterations",
        expected="n x_n alpha -> 1, the error decreasing like n^-1/2 (from sum alpha_k = alpha (n + 2 sqrt n))",
        measured=", ".join(f"n = {n}: n x_n alpha = {marks[n]:.6f}" for n in sorted(marks)),
        tolerance=f"|n x_n alpha - 1| <= 3/sqrt(N) + 10 ln(N)/N = {bound:.3g} at N = {n1}, and smaller than at N/100",
        verdict=judge(errs[n1] <= bound and errs[n1] < errs[n1 // 100]))

    data["family_label"] = variable("family", np.array([f[0] for f in families], dtype=object), "perturbation b_n")
    ds = xr.Dataset({k_: v for k_, v in data.items()}, attrs={"check": NAME})
    return SimpleNamespace(rows=rows, data=ds)


CLAIMS: list = []
for _id, _kind, _subject, _wrong, _falsifier in (
    ("alpha-map-conclusion", PAPER, "lem:alpha-map", "",
     Falsifier("eq. g's numerator 10 % low (0.9 (6x - 8x^2 + 3x^3)): f = g at an alpha* in (0, 1) and the monotone "
               "step fails below it", patch=lambda: {"g_map": lambda x, g=g_map: 0.9 * g(x)})),
    ("giorgio2-divergence", PAPER, "lem:Giorgio's-2", "",
     Falsifier("the sequences x_{n+1} = x_n + c_n x_n^1.8 (exponent 0.2 below the hypothesis: summable)",
               patch=lambda: {"giorgio2_step": lambda x, c: x + c * x**1.8})),
    ("giorgio2-comparison", ERRATUM, "lem:Giorgio's-2",
     "x_n >= z_n for all n needs x_n <= 1/(2c); fails for x_0 > 1/(2c) (the lemma itself holds)",
     Falsifier("a sequence on which the print holds: x = (2/5, 9/20, ...), below 1/(2c) where z -> z - c z^2 increases",
               patch=lambda: {"COMPARISON_START": (Fraction(2, 5), Fraction(9, 20))})),
    ("giorgio-varying-alpha", PAPER, "lem:Giorgio's", "",
     Falsifier("the remainder 0.1 x_n^2 (O(x_n^2), not o: n x_n alpha -> alpha/(alpha - 0.1) = 1.25) in place of x_n^3",
               patch=lambda: {"giorgio_remainder": lambda x: 0.1 * x * x})),
):
    recorded(CLAIMS, _id, _kind, _subject, _wrong, falsifier=_falsifier)


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    from ..figures.common import WIDTH, plt, save

    fig, axs = plt.subplots(1, 2, figsize=(WIDTH, 3.0))
    ax = axs[0]
    exits = ds["alpha_exit"].values
    seen = set()
    for i, fam in enumerate(str(v) for v in ds["family_label"].values):
        group = "b = 0" if fam == "b = 0" else ("$b_n = -B n^{-p}$" if "-" in fam.split("n^")[0] else "$b_n = +B n^{-p}$")
        color = {"b = 0": "k", "$b_n = -B n^{-p}$": "C0", "$b_n = +B n^{-p}$": "C3"}[group]
        ax.semilogy(ds["alpha0"].values, exits[i] + 1, ".-", lw=0.5, ms=2, color=color,
                    label=None if group in seen else group)
        seen.add(group)
    ax.set_xlabel(r"$\alpha_0$")
    ax.set_ylabel(r"1 + step at which $\alpha_n$ leaves (0, 1)")
    ax.set_title("(a) lem. alpha-map: eq. fg-map from a grid of $\\alpha_0$,\nevery perturbation family $b_n\\to 0$",
                 fontsize=8)
    ax.legend(fontsize=5.5)
    ax = axs[1]
    ax.hist(ds["giorgio2_growth"].values, bins=20, color="C0")
    c = float(spec["giorgio2_c"])
    ax.axvline(math.log(10) / c, color="C3", lw=0.8, label=r"$\ln 10/c$ (comparison map)")
    ax.set_xlabel(r"$\sum x_n$ over the last decade of $n$")
    ax.set_ylabel("sequences")
    ax.yaxis.get_major_locator().set_params(integer=True)  # a count: no 0.5, 1.5 ticks
    ax.set_title("(b) lem. Giorgio's-2: the sums keep growing", fontsize=8)
    ax.legend(fontsize=6)
    fig.suptitle(f"Check {NAME}: the Appendix's lemmas iterated (dimensionless)", fontsize=9)
    fig.tight_layout()
    save(fig, outputs)


CHECK = Check(NAME, measure, tuple(CLAIMS), plot, title="The Appendix's lemmas, iterated")
