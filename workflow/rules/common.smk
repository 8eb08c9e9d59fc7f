"""Shared helpers: config slices as JSON, the sticky runs and the figure table."""


def as_json(obj):
    """A config slice as compact JSON for a rule's params (a change reruns only its users)."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"))


def eps_tag(eps):
    """File-name tag of an eps of eq. sticky-ic: 0, 0.001, 1e-06, ..."""
    return f"{float(eps):g}"


def sticky_file(eps):
    return f"results/data/sticky/eps{eps_tag(eps)}.nc"


def sticky_run_spec(w):
    """Scene spec of one eps run: only gamma, mu, Ydot0, horizon and cap (not the eps lists)."""
    return as_json({
        "gamma": STICKY["gamma"], "mu": STICKY["mu"],
        "initial": {"sticky": {"eps": float(w.eps), "ydot": STICKY["ydot0"]}},
        "stop": {"events": STICKY["events"], "t_max": STICKY["t_max"]},
    })


SCENES = sorted(config["scenes"])
STICKY = config["sticky"]
STICKY_TRAJ = [sticky_file(e) for e in STICKY["eps_traj"]]
STICKY_CONV = [sticky_file(0.0)] + [sticky_file(e) for e in STICKY["eps_convergence"] if float(e) != 0.0]

# figure name -> (input datasets, spec); names are the paper's figure labels
FIGURES = {}
for _name, _spec in config["figures"].items():
    _inputs = [f"results/data/{_spec['scene']}.nc"]
    FIGURES[_name] = (_inputs, dict(_spec, label=_name))
    if _name.startswith("very_rigid_poincare"):
        FIGURES[f"{_name}_magni"] = (_inputs, dict(_spec, label=f"{_name}_magni"))
FIGURES["sticky-traj"] = (STICKY_TRAJ, {"t_end": STICKY["t_max"]})
FIGURES["sticky-convergence"] = (["results/data/sticky-convergence.nc"], {})
FIGURES["sticky-inference"] = (["results/data/sticky-inference.nc"], {})
FIGURES["energy-decay"] = (["results/data/asymptotic-underdamped.nc", "results/data/asymptotic-overdamped.nc"], {})
FIGURES["asymptotic-laws"] = (["results/data/asymptotic-underdamped.nc", "results/data/asymptotic-overdamped.nc"], {})


CHECKS = sorted(config.get("checks", {}))

# speed-vs-accuracy studies: name -> config slice
REDUCED = config["reduced"]
STUDIES = {
    "horizon": REDUCED["horizon"],
    "contact-switch": REDUCED["switch"],
    "reduced-vs-dimer": REDUCED["vs_dimer"],
    "least-model": dict(
        REDUCED["least_model"],
        scene_specs={k: config["scenes"][k] for k in REDUCED["least_model"]["scenes"]},
    ),
    "work-precision": config["methods"],
    "stability-map": config["methods"],
}


def figure_files():
    return [f"results/figures/fig-{name}.{ext}" for name in FIGURES for ext in ("png", "pdf")]
