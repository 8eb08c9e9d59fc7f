"""One catalogue of every stage's figures and captions (the report's list and the Snakefile's figure table),
read from the registries of :mod:`bounce.figures`, :mod:`bounce.studies` and :mod:`bounce.sweeps`.

It lives in the pipeline layer because it reads all three wings: no wing imports another.
"""

from __future__ import annotations

from ..figures import FIGURES
from ..paths import RESULTS, figure_file
from ..studies import registry as study_registry
from ..sweeps import registry


def pipeline_figures(config: dict) -> list[dict]:
    """Every figure the pipeline makes besides the claim groups' own: path of its PNG (from the working directory),
    name, the paper's figure label it reproduces ("" = beyond the paper) and caption; in registry order."""
    out = [dict(path=figure_file("figures", name), name=name, paper=fig.caption.paper, caption=fig.caption.text)
           for name, fig in FIGURES.items()]
    out += [dict(path=figure_file("methods", name), name=name, paper="", caption=study.caption)
            for name, study in study_registry().items()]
    sweeps = registry()
    out += [dict(path=figure_file("sweeps", name), name=name, paper="", caption=sweeps[name].title)
            for name in config.get("sweeps", {})]
    return out


def figure_table(config: dict) -> dict:
    """name -> (input paths, spec) for the Snakefile; the spec carries the figure's ``label``."""
    return {name: ([f"{RESULTS}/{f}.nc" for f in fig.inputs(config)], dict(fig.spec(config), label=name))
            for name, fig in FIGURES.items()}
