"""The errata register: every distinct erratum of the paper as printed, once, as data.

A claim row of kind ``erratum`` (:mod:`bounce.checks.base`) checks a printed formula or statement with numbers or
algebra; several rows may back one erratum (the nonlinear dissipation rate's missing factor 2 is checked on every
power-law scene), and most typos, index slips and cross-references are not numerical claims at all.  The register
is what is counted: one :class:`Erratum` per error of the text, with its location, the text as printed and the
correct text, a severity, one line of evidence, and the claim rows (``group/claim-id``) that check it, if any.
The report counts errata here (distinct, by severity, with the rows backing them), not rows.

Contract (tests/checks/test_errata_register.py): every erratum-kind claim of every group is named by at least one
entry; every row an entry names exists and is of kind erratum; ids are unique; where the paper's LaTeX is at hand
(beside the clone, or ``BOUNCE_PAPER_TEX``), each entry's ``printed`` text occurs on its stated ``line`` and its
``label`` is a ``\\label`` of the source.

The module is data shared by the claim groups' rows and the report, not a claim group: in a plug-in folder such a
module is a private helper (``_name``, tests/test_layout.py).

Locations are those of the LaTeX source ``stopping-time-bouncing-ball.tex``: its line numbers, and its section
numbers as LaTeX assigns them (1 Introduction ... 4 Absence of Inelastic Collapse, 5 Asymptotic State,
6 Non-Genericity, 7 Numerical Results, 8 Discussion and Conclusions, 9 Appendix).  The claim rows' ``paper_ref``
texts number the sections from the collapse part on one higher (sec. 5 = 4.3 here, sec. 8.1 = 7.1, sec. 9 = 8).
``label`` is the ``\\label`` of the equation, lemma or theorem the text belongs to (or follows), else of its
section; empty where the section has none (the abstract, the introduction).  Sources: the referee's re-read
(notes/errata-reread.md, CONFIRMED items only), a second independent re-read of the whole source (its CONFIRMED items:
intro-restitution-increasing, sticky-dissipated-bound, td-drop-criterion, xddot-squared-dots, giorgio-parentheses,
english-continous, bib-duran-title; three SUSPECTED items, the free-fall time T_psi of eq. char-times, the reference
of l. 1132 and the t_0 = 0 convention, are left out until settled) and the erratum rows that predate them.
"""

from __future__ import annotations

from dataclasses import dataclass

TYPO, XREF, FORMULA, STATEMENT = "typo", "cross-reference", "wrong formula", "wrong statement"
#: from the most to the least consequential
SEVERITIES = (FORMULA, STATEMENT, XREF, TYPO)


@dataclass(frozen=True)
class Erratum:
    id: str
    section: str  # section title, with the number LaTeX gives it
    label: str  # \label of the equation / lemma / theorem (or section) it belongs to; "" where there is none
    line: int  # line of the .tex where ``printed`` occurs
    printed: str  # the text as printed: a verbatim excerpt of that line
    correct: str
    severity: str
    evidence: str  # one line
    rows: tuple = ()  # the claim rows (group/claim-id) that check it numerically, if any

    def __post_init__(self) -> None:
        if self.severity not in SEVERITIES:
            raise ValueError(f"erratum {self.id}: severity must be one of {SEVERITIES}, got {self.severity!r}")


ABSTRACT, INTRO, MODEL = "Abstract", "1 Introduction", "2 Equations of Motion"
STICKY = "3 Anomalous Contacts"
RELATIONS, NOCOLLAPSE = "4.2 Asymptotic relationships at collapse", "4.3 Absence of Inelastic Collapse"
ASYMPTOTIC, PROOF_STATIC, PROOF_MAIN = ("5 Asymptotic State", "5.1 Proof of Theorem static-equilibrium",
                                        "5.2 Proof of the Main Theorem")
NONGENERIC = "6 Non-Genericity of Zero-Velocity Contacts"
RESTITUTION = "7.1 On the Nature of the Restitution Coefficient"
DISCUSSION, APPENDIX, REFERENCES = "8 Discussion and Conclusions", "9 Appendix", "References"

REGISTER: tuple[Erratum, ...] = (
    # ------------------------------------------------------------------ wrong formulas
    Erratum("nonlin-dissipation-factor-2", DISCUSSION, "eq:nonlin-energy", 1447,
            r"\frac{dE}{dt}=-\mu\dot{\xi}^{2}\left|\xi\right|^{b}",
            r"\frac{dE}{dt}=-2\mu\dot{\xi}^{2}\left|\xi\right|^{b}", FORMULA,
            "dE/dt along eq. eq-motion-nonlin-psi-xi is -2 mu xi'^2 |xi|^b; a = b = 0 must give eq. energy-dissipation, "
            "-2 mu xi'^2; measured on every power-law scene: c = 2",
            ("nonlinear/printed-dissipation-rate",)),
    Erratum("nonlin-equilibrium-psi", DISCUSSION, "eq:nonlin-equilibrium-xi", 1443,
            r"\psi=\dot{\psi}=\dot{\xi}=0,\quad\xi=-\left(\frac{\gamma}{\rho}\right)^{\frac{1}{a+1}}",
            r"\psi=\xi=-\left(\frac{\gamma}{\rho}\right)^{\frac{1}{a+1}},\quad\dot{\psi}=\dot{\xi}=0", FORMULA,
            "at rest on the floor x = psi - xi = 0; the printed state is off the floor by |xi_eq| and the simulator "
            "started there lands; it is not the minimum of eq. nonlin-energy (higher by gamma |xi_eq|)",
            ("nonlinear/printed-equilibrium-state",)),
    Erratum("energy-limit-gamma-over-2", PROOF_STATIC, "thm:static-equilibrium", 945,
            r"\lim_{n\rightarrow\infty}E(t_{n}^{+})=-\gamma/2.",
            r"\lim_{n\rightarrow\infty}E(t_{n}^{+})=-\gamma^{2}/2 (and -\gamma^{2}/2 in the display of l. 947)", FORMULA,
            "eq. Emin: E_m = -gamma^2/2; the simulated energy tends to -gamma^2/2 on every scene",
            ("static-equilibrium/printed-energy-limit",)),
    Erratum("xddot-infinity-remainder", NOCOLLAPSE, "eq:tauOXdot", 704,
            r"\ddot{X}_{\infty}=\lim_{n\rightarrow\infty}\left(-2\frac{\dot{X}_{n}}{\tau_{n}}+O(\tau_{n}^{2})\right)<0.",
            r"\ddot{X}_{\infty}=\lim_{n\rightarrow\infty}\left(-2\frac{\dot{X}_{n}}{\tau_{n}}+O(\tau_{n})\right)<0.",
            FORMULA, "eq. xddot-tau divided by tau_n leaves -x'''(zeta_n) tau_n/3, O(tau_n); measured ratio -1/3",
            ("errata/xddot-infinity-remainder",)),
    Erratum("main-thm-proof-coefficient", PROOF_MAIN, "thm:main_thm", 986,
            r"\frac{\dot{X}_{n}}{\tau_{n}}=-\frac{\stackrel{..}{X}_{n}}{2}+\stackrel{...}{x}(\zeta_{n})\tau_{n}",
            r"\frac{\dot{X}_{n}}{\tau_{n}}=-\frac{\ddot{X}_{n}}{2}-\frac{1}{6}\dddot{x}(\zeta_{n})\tau_{n}", FORMULA,
            "eq. xddot-tau divided by 2 tau_n; the coefficient measured on the drops is -1/6, not +1 (the limit "
            "Xdot_n/tau_n -> gamma is unaffected)", ("main-theorem/printed-coefficient",)),
    Erratum("rest-coeff-ratio-inverted", RESTITUTION, "eq:proper-rest-coeff", 1197,
            r"r=\dot{\Psi}_{n}/\dot{\Psi}_{n+2}", r"r=\dot{\Psi}_{n+2}/\dot{\Psi}_{n}", FORMULA,
            "before/after a double impact the centre-of-mass speed ratio is 1/r = e^(mu T_xi) on the plateau of fig. "
            "rest-coeff", ("restitution/printed-ratio",)),
    Erratum("sticky-dissipation-factor", STICKY, "thm:Finite-number-sticky-ev", 469,
            r"-\mu\int_{s_{n}}^{t_{n}}\dot{y}^{2}(s)\, ds.", r"-\frac{\mu}{2}\int_{s_{n}}^{t_{n}}\dot{y}^{2}(s)\, ds.",
            FORMULA, "eq. energy-dissipation with xi' = ydot/2 in contact; the simulated sticky phase dissipates "
            "(mu/2) int ydot^2", ("errata/sticky-dissipation",)),
    Erratum("ydot2-series", STICKY, "thm:Finite-number-sticky-ev", 478,
            r"\dot{y}^{2}(s_{n}+t)=\dot{Y}_{s_{n}}^{2}t+\dot{Y}_{s_{n}}\ddot{Y}_{s_{n}}t^{2}",
            r"\int_{0}^{t}\dot{y}^{2}(s_{n}+s)\,ds=\dot{Y}_{s_{n}}^{2}t+\dot{Y}_{s_{n}}\ddot{Y}_{s_{n}}t^{2}+\dots",
            FORMULA, "the series starts with Ydot^2 t: it is that of the integral, which the simulated sticky phase "
            "matches, not of ydot^2", ("errata/ydot2-series",)),
    Erratum("collapse-third-derivative", RELATIONS, "eq:X-derivatives", 666,
            r"\dddot{X}_{n}=Q-\mu P+(\mu Q-2R)T_{n}+O(T_{n}^{2})+O(V_{n})",
            r"\dddot{X}_{n}=Q-\mu P+(\mu Q-2R)T_{n}+(\mu^{2}-\frac{1}{2})\dot{X}_{n}+O(T_{n}^{2})+O(V_{n})", FORMULA,
            "sympy: x''' = -mu x'' - x'/2 + y'/2 + mu y'' just after the impact keeps (mu^2 - 1/2) Xdot_n, of the order "
            "of the kept (mu Q - 2R) T_n (eq. XdotOtau); harmless where used", ("algebra/collapse-third-derivative",)),
    Erratum("our-r-mixed-speeds", DISCUSSION, "eq:our-r", 1397, r"1-\frac{\mu}{3\gamma}u, & u\le u_{c}",
            r"1-\frac{2\mu}{3\gamma}u, & u\le u_{c} with u_{c}=\frac{3\gamma}{2\mu}(1-e^{-\mu T_{\xi}}) (u the "
            r"centre-of-mass speed, as in the large-u branch); or say that u is the lower mass's speed, flight u/\gamma",
            FORMULA, "the small-u branch is eq. restituzione, a map of the lower mass's speed Xdot_n = 2u; in the "
            "centre-of-mass speed of the large-u branch the measured coefficient is 2", ("our-r/our-r-centre-of-mass",)),
    Erratum("tau-simeq-xdot", NOCOLLAPSE, "eq:tauOXdot", 705, r"$\tau_{n}\simeq\dot{X}_{n}$",
            r"$\tau_{n}\simeq2\dot{X}_{n}/|\ddot{X}_{\infty}|$ (or $\tau_{n}\asymp\dot{X}_{n}$: only the order is used)",
            FORMULA, "the display just above gives tau_n ~ 2 Xdot_n/|Xddot_inf|; the two are only of the same order"),
    Erratum("sticky-dissipated-bound", STICKY, "thm:Finite-number-sticky-ev", 486, r"$b=a/4,$ $D=C/2$",
            r"$b=\mu a/8,$ $D=\mu C/4$ (the energy is the rate (mu/2) times the integral of ydot^2, bounded by at^3 - C eps t)",
            FORMULA, "the printed b, D integrate the bound of l. 483 a second time and drop the damping factor; sympy: "
            "int_0^t ydot^2 = eps^2 t - 2 gamma eps t^2 + (4 gamma^2/3 + O(eps)) t^3 (re-read 2, N2); the argument "
            "survives (any positive bound does)"),
    # ------------------------------------------------------------------ wrong statements
    Erratum("main-thm-upper-mass", MODEL, "thm:main_thm", 280, "damped harmonic oscillations",
            "relaxes to equilibrium (with damped oscillations if mu < sqrt 2)", STATEMENT,
            "in permanent contact eq. y-eq-sticky has roots (-mu +- sqrt(mu^2 - 2))/2: no oscillation for mu >= sqrt 2 "
            "(the paper's own mu = 2 figures); the simulated contacts do not cross y_eq there",
            ("errata/main-thm-upper-mass",)),
    Erratum("asymptotics-independent-of-mu", RESTITUTION, "thm:main_thm", 1309,
            r"are independent of the particular value of the damping parameter $\mu$.",
            r"hold for every value of the damping parameter $\mu$ (tau_n ~ 3/(mu n) depends on mu).", STATEMENT,
            "Theorem main_thm: tau_n ~ 3/(mu n), Xdot_n ~ 3 gamma/(mu n); lim n tau_n measured 300 at mu = 0.01, 1.5 "
            "at mu = 2", ("main-theorem/asymptotics-independent-of-mu",)),
    Erratum("td-energy-efolding", RESTITUTION, "eq:char-times", 1180,
            "time associated with energy dissipation from the spring",
            "time of the spring's amplitude (its energy e-folds in T_d/2 = 1/(2 mu))", STATEMENT,
            "xi ~ e^(-mu t) sin(sqrt(1 - mu^2) t): energy ~ e^(-2 mu t) (eq. energy-dissipation); measured on the "
            "simulator's free spring", ("errata/td-energy-efolding",)),
    Erratum("our-r-rigid-6-over-mu-n", DISCUSSION, "eq:our-r", 1405,
            r"Although (\ref{eq:our-r}) is very accurate for large and for small",
            "accurate for small u only with u the lower mass's speed and the flight u/gamma; as a rigid-ball law (flight "
            "2u/gamma) its small-u branch needs 2 mu/(3 gamma)", STATEMENT,
            "Lemma Giorgio's: a rigid ball with the printed branch has tau_n ~ 6/(mu n), twice the dimer's 3/(mu n); "
            "iterated: n tau_n mu/3 -> 2", ("rigid-collapse/our-r-rigid-ball",)),
    Erratum("nonlin-same-asymptotic-law", DISCUSSION, "eq:mappa", 1459, "asymptotic law as the linear case.",
            r"asymptotic law of the same form, \tau_{n}\sim3/(\mu|\xi_{eq}|^{b}n), the linear 3/(\mu n) for b = 0.",
            STATEMENT, "with the printed alpha, tau_n ~ 1/(alpha gamma n) = 3/(mu |xi_eq|^b n): Hertz scene 46.4 vs "
            "3/mu = 10; the b = 0 scene agrees", ("nonlinear/printed-same-asymptotic-law",)),
    Erratum("nonlin-linear-limit-rho", DISCUSSION, "eq:eq-motion-nonlin-psi-xi", 1432,
            r"We recover the linear model for $a=b=0$.", r"We recover the linear model for $a=b=0$ and $\rho=1$.",
            STATEMENT, "xi'' = -rho xi - 2 mu xi' is the linear model only after rescaling time by sqrt(rho) (mu -> "
            "mu/sqrt(rho), gamma -> gamma/rho); simulated at rho = 4 the events differ at O(1)",
            ("nonlinear/printed-linear-limit",)),
    Erratum("nonlin-constraint-strict", DISCUSSION, "eq:eq-motion-nonlin-psi-xi", 1431,
            r"The constraint $\psi(t)>\xi(t)$", r"The constraint $\psi(t)\ge\xi(t)$", STATEMENT,
            "equality holds at every impact (eq. collision-condition-psi-xi, invoked the line before) and at rest"),
    Erratum("our-r-domain", DISCUSSION, "eq:our-r", 1396, r"\exp\left(-\frac{\mu\pi}{\sqrt{1-\mu^{2}}}\right), & u>u_{c}",
            "the same, stated for under-damped springs (mu < 1) only", STATEMENT,
            "eq. our-r and u_c contain sqrt(1 - mu^2); '(for underdamped springs)' sits two sentences later (l. 1407)"),
    Erratum("jump-k1", RELATIONS, "eq:k-derivative_jump", 618,
            r"[x^{(k)}(t_{n})]=-[y^{(k)}(t_{n})]=\bar{c}_{k}\dot{X}_{n}.",
            r"[x^{(k)}(t_{n})]=-[y^{(k)}(t_{n})]=\bar{c}_{k}\dot{X}_{n} for k\ge2 ([\dot{x}]=2\dot{X}_{n}, [\dot{y}]=0)",
            STATEMENT, "eqs. collision-rule-x1, collision-rule-y1 at k = 1; x'' + y'' = -2 gamma gives k >= 2; measured "
            "jumps at impacts (only k >= 2 is used later)", ("errata/jump-k1",)),
    Erratum("sticky-integral-bound", STICKY, "thm:Finite-number-sticky-ev", 484, r"(any $a<16/3\gamma^{2}$",
            r"(any $a<4\gamma^{2}/3$", STATEMENT,
            "the t^3 coefficient is Yddot^2/3 = 4 gamma^2/3 (Yddot_s = -2 gamma); measured lim int ydot^2/t^3 = 4 "
            "gamma^2/3", ("errata/sticky-integral-bound",)),
    Erratum("giorgio2-comparison", APPENDIX, "lem:Giorgio's-2", 1531, r"we have $x_{n}\ge z_{n}$ for all $n\ge0$",
            "we have x_n >= z_n for all n >= N, the comparison started at an N with x_N <= 1/(2c) (z -> z - c z^2 is "
            "increasing only there)", STATEMENT,
            "iterated: sequences with x_0 > 1/(2c) fall below z_n; the lemma itself holds (Xdot_n -> 0 where it is used)",
            ("appendix/giorgio2-comparison",)),
    Erratum("intro-restitution-increasing", INTRO, "", 96, "an increasing function of the impact velocity",
            "a decreasing function of the impact velocity", STATEMENT,
            "r -> 1 as u -> 0 and r < 1 otherwise (the same sentence), and the paper's own r = 1 - (u/U)^(1/5) "
            "(eq. onefifth-rest-coeff) has dr/du < 0"),
    Erratum("td-drop-criterion", RESTITUTION, "eq:char-times", 1214,
            r"shorter than the characteristic dissipation time $T_{d}$",
            "shorter than the energy's e-folding time 1/(2 mu) = T_d/2", STATEMENT,
            "fig. rigid-fall (gamma = mu = 0.01, T_d = 100): every macroscopic flight is shorter than T_d from the first "
            "(66.5, 64.3, 62.1, 56.3, 42.5, ...: bounce.simulate); the drop of the apex comes between the 4th and 6th "
            "flight, where they fall below 1/(2 mu) = 50 (re-read 2, N3; see td-energy-efolding)"),
    # ------------------------------------------------------------------ cross-references
    Erratum("xref-static-equilibrium", STICKY, "lem:td-ts-bound", 444,
            r"removed from the static equilibrium (\ref{thm:static-equilibrium})",
            r"removed from the static equilibrium (\ref{eq:equilibrium})", XREF,
            "prints (2.3), a theorem's number, as an equation number; the state is eq. equilibrium, as at l. 504"),
    Erratum("xref-energy-dissipation", ASYMPTOTIC, "lem:xidot(t)-goes-to-0", 857, r"(see eq. \ref{eq:xi-psi})",
            r"(see eq. \ref{eq:energy-dissipation})", XREF,
            "eq. xi-psi defines psi and xi; dE/dt = -2 mu xi'^2 is eq. energy-dissipation"),
    Erratum("xref-hardcoded-6", PROOF_MAIN, "thm:main_thm", 959, "From the equations of motion (6)",
            r"From the equations of motion (\ref{eq:dimensionless-eq-motion})", XREF,
            "a hand-typed (6); in this source (6) is eq. collision-rule-x1, the equations of motion are (8)"),
    # ------------------------------------------------------------------ typos: indices, notation, signs
    Erratum("Tn-sum-index", NOCOLLAPSE, "eq:Xdot-fasterthan-tau", 734, r"T_{n}=\sum_{h=n}^{\infty}\tau_{n}",
            r"T_{n}=\sum_{h=n}^{\infty}\tau_{h}", TYPO, "summation index h, summand tau_n (eq. Tn-definition)"),
    Erratum("n-to-zero", NOCOLLAPSE, "eq:Tha-Map", 742, r"as $n\rightarrow0$", r"as $n\rightarrow\infty$", TYPO,
            "a sequence indexed by n converges as n -> infinity"),
    Erratum("x3-stray-index", NOCOLLAPSE, "eq:strange-combination", 750, r"\dddot{x}_{n}(\zeta_{n})",
            r"\dddot{x}(\zeta_{n})", TYPO, "x carries no index (eq. tau3, two lines above)"),
    Erratum("td-ts-O-exponent", STICKY, "lem:td-ts-bound", 439, r"$\zeta_{s}=O(\zeta_{s})^{2}$",
            r"$\zeta_{s}=O(\zeta_{s}^{2})$", TYPO, "the square belongs inside O(); the expansion itself checks "
            "(row algebra/td-ts-expansion)"),
    Erratum("Yn-definition", MODEL, "eq:dimensionless-eq-motion", 216, r"$Y_{n}=Y(t_{n})$", r"$Y_{n}=y(t_{n})$", TYPO,
            "Y is not a function; the neighbouring definitions use x and y"),
    Erratum("xdot-n-notation", MODEL, "eq:collision-rule-y1", 199, r"$\dot{x}_{n}(t_{n})=0$",
            r"$\lim_{t\to t_{n}^{-}}\dot{x}(t)=0$", TYPO, "x carries no index n (as in Theorem contact-non-generic)"),
    Erratum("x4-brace", RELATIONS, "eq:X-derivatives", 667, r"X_{n}^{\mathrm{(4})}", r"X_{n}^{(4)}", TYPO,
            "misplaced brace: the parenthesis renders outside the roman group"),
    Erratum("lemma51-strict-ineq", ASYMPTOTIC, "lem:xidot(t)-goes-to-0", 906, r"\dot{E}(t)<-\frac{\delta}{2}.",
            r"\dot{E}(t)\le-\frac{\delta}{2}.", TYPO,
            "E'(t) - E'(s_k) <= delta/2 with E'(s_k) <= -delta gives <= -delta/2 (harmless)"),
    Erratum("lemma51-power-sign", ASYMPTOTIC, "lem:xidot(t)-goes-to-0", 910, r"the power dissipated is at least $-\delta/2$",
            r"the power dissipated is at least $\delta/2$", TYPO, "a dissipated power is positive: dE/dt <= -delta/2"),
    Erratum("xi-lemma-limit-t-to-0", ASYMPTOTIC, "lem:xi(t)-goes-to-0", 931, r"$\lim_{t\rightarrow0}\dot{\xi}(t)=0$",
            r"$\lim_{t\rightarrow\infty}\dot{\xi}(t)=0$", TYPO,
            "Lemma xidot(t)-goes-to-0 is about t -> infinity; xi'(0) is arbitrary (0.1 in the run)",
            ("errata/xi-lemma-typos",)),
    Erratum("xi-lemma-abs-xi-minus-gamma", ASYMPTOTIC, "lem:xi(t)-goes-to-0", 932, r"\left|\xi(t)-\gamma\right|",
            r"\left|\xi(t)+\gamma\right|", TYPO,
            "the contradiction hypothesis is on |xi + gamma| (the line above); |xi - gamma| -> 2 gamma",
            ("errata/xi-lemma-typos",)),
    Erratum("alpha-map-sign", APPENDIX, "lem:alpha-map", 1555, r"$g(x)-f(x)\le-\epsilon^{2}$",
            r"$f(x)-g(x)\le-\epsilon^{2}$", TYPO,
            "eq. g-minus-f gives f - g <= -x^2/(1-x)^3; the next line uses f - g; min (g - f) >= +eps^2",
            ("errata/alpha-map-sign",)),
    Erratum("giorgio-induction-a", APPENDIX, "eq:ineq1", 1481, r"1-(a+\epsilon)x_{n}\leq",
            r"1-(\alpha+\epsilon)x_{n}\leq (and \alpha for a in the induction)", TYPO,
            "sympy: the induction step closes only for a = alpha, the limit of alpha_n", ("algebra/giorgio-induction",)),
    Erratum("xddot-squared-dots", PROOF_MAIN, "thm:main_thm", 978, r"\stackrel{..}{X_{n}^{2}}", r"\ddot{X}_{n}^{2}",
            TYPO, "the dots belong on X_n, not on its square: tau_n ~ 2 Xdot_n/|Xddot_n| gives alpha_n = 4 Delta_n/Xddot_n^2 "
            "-> mu/(3 gamma), the value printed on l. 979"),
    Erratum("giorgio-parentheses", APPENDIX, "lem:Giorgio's", 1489, r"$x/1+(a-\epsilon)x$",
            r"$x/(1+(\alpha-\epsilon)x)$", TYPO,
            "as printed it reads x + (a - eps) x, not the map x_{N+k}/(1 + (a - eps) x_{N+k}) of l. 1488 (so too "
            "1/k(alpha - eps) on l. 1483, 1490 for 1/(k (alpha - eps)))"),
    # ------------------------------------------------------------------ typos: English
    Erratum("english-explicitely", ABSTRACT, "", 27, "explicitely", "explicitly", TYPO, "spelling"),
    Erratum("english-facetes", INTRO, "", 66, "facetes", "facets", TYPO, "spelling"),
    Erratum("english-hypoteses", INTRO, "", 120, "hypoteses", "hypotheses", TYPO, "spelling"),
    Erratum("english-an-basic", MODEL, "sec:model-description", 167, "An basic model", "A basic model", TYPO, "article"),
    Erratum("english-with-of-without", STICKY, "sec:Sticky-Events", 325, "with of without", "with or without", TYPO,
            "word"),
    Erratum("english-the-coincide", STICKY, "lem:Min-sticky-energy", 410, "the coincide", "they coincide", TYPO, "word"),
    Erratum("english-this-this", NOCOLLAPSE, "eq:Tha-Map", 743, "this this map", "this map", TYPO, "repeated word"),
    Erratum("english-have-can", ASYMPTOTIC, "lem:xidot(t)-goes-to-0", 896, "we have can choose", "we can choose", TYPO,
            "grammar"),
    Erratum("english-exherted", NONGENERIC, "eq:force-on-the-floor", 1036, "exherted", "exerted", TYPO, "spelling"),
    Erratum("english-essential", RESTITUTION, "eq:char-times", 1190, "the spring essential", "the spring essentially",
            TYPO, "adverb"),
    Erratum("english-lead", RESTITUTION, "eq:proper-rest-coeff", 1205, "lead to say", "led to say", TYPO,
            "past participle of 'lead' ('we are lead', l. 1204-1205)"),
    Erratum("english-the-is-no", RESTITUTION, "fig:very_rigid_poincare_overdamped", 1331, "the is no disordered",
            "there is no disordered", TYPO, "word"),
    Erratum("english-continous", NONGENERIC, "sec:ZeroMeasure", 1136, "continous", "continuous", TYPO, "spelling"),
    Erratum("bib-duran-title", REFERENCES, "", 1601, r"J. Duran, Sands, \emph{Powders, and Grains",
            r"J. Duran, \emph{Sands, Powders, and Grains", TYPO,
            "the book is 'Sands, Powders, and Grains'; as printed 'Sands,' reads as part of the author's name"),
)


def row_id(claim_id: str) -> str:
    """``group/claim-id`` of a verdict row's id (without its ``[scene]`` label)."""
    return claim_id.split("[", 1)[0]


def entries_by_row(register=REGISTER) -> dict[str, list[Erratum]]:
    """``group/claim-id`` -> the register entries it backs."""
    out: dict[str, list[Erratum]] = {}
    for e in register:
        for r in e.rows:
            out.setdefault(r, []).append(e)
    return out
