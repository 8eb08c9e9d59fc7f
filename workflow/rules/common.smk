"""Shared helpers: config slices as JSON, the sticky runs, and the registries of the package
(figures: bounce.figures.FIGURES and bounce.pipeline.catalogue; studies: bounce.studies.registry; checks: bounce.checks) read here,
so that no name is listed twice."""

from bounce.paths import dataset, figure_file, gas_scene_file, sticky_dataset
from bounce.pipeline.catalogue import figure_table, pipeline_figures
from bounce.pipeline import taskserver
from bounce.pipeline.config import report_choices
from bounce.studies import study_inputs, study_slices


# The jobs run a task of bounce.pipeline.tasks through its client, a script of the standard library
# (bounce.pipeline.taskserver): forked by the run's task server when there is one, else started afresh.
# Its path is handed to the jobs in the environment (a shell variable in the commands: snakemake's lint
# rightly wants a command's {...} names to be the rule's own, and a path in params would rerun every job
# when the checkout moves).
os.environ["BOUNCE_TASK_CLIENT"] = str(Path(taskserver.__file__))


envvars:
    "BOUNCE_TASK_CLIENT",


def as_json(obj):
    """A config slice as compact JSON for a rule's params (a change reruns only its users)."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"))


def sticky_file(eps):
    return dataset("data", sticky_dataset(eps))


SCENES = sorted(config["scenes"])
GAS_SCENES = sorted(config.get("gas_scenes", {}))
STICKY = config["sticky"]
#: every eps run of eq. sticky-ic a rule reads (eps = 0, the trajectories' and the convergence's), once each
STICKY_EPS = sorted({float(e) for e in [0.0, *STICKY["eps_traj"], *STICKY["eps_convergence"]]})
STICKY_CONV = [sticky_file(0.0)] + [sticky_file(e) for e in STICKY["eps_convergence"] if float(e) != 0.0]

# figure name -> (input datasets, spec): the registry bounce.figures.FIGURES, one line per figure
FIGURES = figure_table(config)
# every figure besides the claim groups' own, with the paper's figure and caption it reproduces (for the report)
PIPELINE_FIGURES = pipeline_figures(config)


CHECKS = sorted(config.get("checks", {}))

# speed-vs-accuracy studies: name -> config slice (the registry bounce.studies.registry)
STUDIES = study_slices(config)
STUDY_INPUTS = study_inputs(config)


def figure_files():
    return [f"results/figures/fig-{name}.{ext}" for name in FIGURES for ext in ("png", "pdf")]
