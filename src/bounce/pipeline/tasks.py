"""Entry points of the Snakemake rules: ``python -m bounce.pipeline.tasks <task> --spec JSON ...``.

Each task takes the config slice it uses as JSON (so a config edit reruns only
what depends on it), reads/writes files, and delegates to the package.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import sys
from pathlib import Path

from ..io import read_dataset, write_netcdf


def _scene(args) -> None:
    from ..scenes import scene_dataset

    write_netcdf(scene_dataset(args.spec, name=args.name), args.out[0])


def _sticky_runs(args) -> None:
    """Every eps run of eq. sticky-ic (``--spec``: gamma, mu, ydot0, stop and the eps list), one file each, in the
    order of ``--out``; each the scene ``sticky-eps<eps>`` (:func:`bounce.paths.sticky_dataset`)."""
    from ..paths import sticky_dataset
    from ..scenes import scene_dataset

    spec = args.spec
    for eps, out in zip(spec["eps"], args.out, strict=True):
        scene = {"gamma": spec["gamma"], "mu": spec["mu"], "initial": {"sticky": {"eps": eps, "ydot": spec["ydot0"]}},
                 "stop": spec["stop"]}
        write_netcdf(scene_dataset(scene, name=f"sticky-{Path(sticky_dataset(eps)).name}"), out)


def _gas_scene(args) -> None:
    from ..scenes import gas_scene_dataset

    write_netcdf(gas_scene_dataset(args.spec, name=args.name), args.out[0])


def _sticky_inference(args) -> None:
    from ..analysis.sticky import t_c_map

    write_netcdf(t_c_map(args.spec), args.out[0])


def _sticky_convergence(args) -> None:
    from ..analysis.sticky import convergence

    reference, *runs = (read_dataset(p) for p in args.inputs)
    write_netcdf(convergence(reference, runs, args.spec["samples"]), args.out[0])


def _figure(args) -> None:
    from ..figures import FIGURES

    FIGURES[args.name].draw([read_dataset(p) for p in args.inputs], args.spec, args.out)


def _check(args) -> None:
    """Run one validation check: its dataset (numbers + verdicts) and its figure."""
    from ..checks import get

    check = get(args.name)
    ds = check.run(args.spec, [read_dataset(p) for p in args.inputs])
    ds.attrs.setdefault("check", args.name)
    write_netcdf(ds, args.out[0])
    if check.plot is not None:
        check.plot(ds, args.spec, args.out[1:])


def _check_experiment(args) -> None:
    """One long simulation of a claim group (``--experiment NAME``), from the config keys it declares."""
    from .._version import __version__
    from ..checks import get
    from ..io import git_info

    ds = get(args.name).experiment(args.experiment).dataset(args.spec)
    commit, dirty = git_info()
    ds.attrs.update({"Conventions": "CF-1.10", "source": f"bounce {__version__}", "git_commit": commit,
                     "git_dirty": dirty, "check": args.name, "config": json.dumps(args.spec, sort_keys=True)})
    write_netcdf(ds, args.out[0])


def _report(args) -> None:
    """Gather every check into results/report/validation.md and the article (results/report/article/)."""
    from .._version import __version__
    from ..io import git_info
    from . import article, report

    figureless = set(args.spec.get("figureless", []))
    figures = [None if Path(p).stem in figureless else str(Path(p).with_name(f"fig-{Path(p).stem}.png"))
               for p in args.inputs]
    subjects = report.ordered_subjects(args.spec)
    meta = {"title": args.spec.get("title", ""), "version": __version__, "commit": git_info()[0],
            "packages": article.package_versions()}
    report.write(args.inputs, figures, args.out[0], subjects, meta, figures=args.spec.get("figures", []))
    article.write(args.inputs, figures, args.out[1], subjects, args.spec["sections"], args.spec["choices"], meta,
                  figures=args.spec.get("figures", []))


def _study(args) -> None:
    """One study (bounce.studies.get): its dataset, its timings, its figure.

    ``--out NC TIMING_NC PNG PDF``: the CPU times go to TIMING_NC so that NC is byte-reproducible.
    """
    from ..io import split_timings
    from ..studies import get

    study = get(args.name)
    build, plot = study.build, study.plot
    ds = build(args.spec)
    result, timings = split_timings(ds)
    write_netcdf(result, args.out[0])
    write_netcdf(timings, args.out[1])
    plot(ds, args.spec, args.out[2:])


def _readme(args) -> None:
    """Rewrite the README's generated block from the outputs under ``--inputs`` (the results folder)."""
    from ..io import git_info
    from .readme import block, update

    update(Path(args.out[0]), block(Path(args.inputs[0]), git_info()[0]))


def _sweep_shard(args) -> None:
    """One shard of a sweep (``--shard K``) on ``--workers`` processes."""
    from ..sweeps import get
    from ..sweeps.base import run_shard

    import time

    start = time.perf_counter()
    ds = run_shard(get(args.name), args.spec, args.shard, args.workers)
    write_netcdf(ds, args.out[0])
    seconds = time.perf_counter() - start
    print(f"{args.name} shard {args.shard}: {ds.sizes['item']} items in {seconds:.1f} s on {args.workers} "
          f"workers ({ds.sizes['item'] / seconds / args.workers:.3g} items/s/core, start-up included)", file=sys.stderr)


def _sweep_gather(args) -> None:
    """Every shard of a sweep -> its dataset (``--out NC``), then its figure drawn from that file alone (``--out NC PNG
    PDF``): one job, as a figure job was mostly start-up (~1 s of CPU)."""
    from ..sweeps import get
    from ..sweeps.base import gather

    sweep = get(args.name)
    write_netcdf(gather(sweep, args.spec, [read_dataset(p) for p in args.inputs]), args.out[0])
    if args.out[1:]:
        sweep.plot(read_dataset(args.out[0]), args.spec, args.out[1:])


def _thumbnails(args) -> None:
    from ..figures.common import thumbnail

    for src, dst in zip(args.inputs, args.out, strict=True):
        thumbnail(src, dst)


#: how this process started, for its cpu: line: afresh (""), or forked by the run's fork server
#: (bounce.pipeline.taskserver sets it), whose imports it does not count
STARTED_BY = ""

#: a job's last log line, as :func:`main` writes it: its own CPU, how it started (:data:`STARTED_BY`), its workers' CPU,
#: and the part of its own CPU spent saving figures (:func:`bounce.figures.common.save`; absent from older logs)
CPU_LINE = re.compile(r"cpu: ([\d.]+) s in this process(.*?), ([\d.]+) s in its worker processes"
                      r"(?:; ([\d.]+) s of it saving figures)?$")

TASKS = {
    "scene": _scene,
    "gas-scene": _gas_scene,
    "sticky-runs": _sticky_runs,
    "sticky-inference": _sticky_inference,
    "sticky-convergence": _sticky_convergence,
    "figure": _figure,
    "check": _check,
    "check-experiment": _check_experiment,
    "report": _report,
    "study": _study,
    "thumbnails": _thumbnails,
    "readme": _readme,
    "sweep-shard": _sweep_shard,
    "sweep-gather": _sweep_gather,
}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bounce.pipeline.tasks", description=__doc__.splitlines()[0])
    parser.add_argument("task", choices=sorted(TASKS))
    parser.add_argument("--name", default="", help="scene or figure name")
    parser.add_argument("--spec", type=json.loads, default={}, help="the config slice, as JSON")
    parser.add_argument("--inputs", nargs="*", default=[], help="input netCDF files")
    parser.add_argument("--out", nargs="+", required=True, help="output file(s)")
    parser.add_argument("--experiment", default="", help="experiment of a claim group (check-experiment)")
    parser.add_argument("--shard", type=int, default=0, help="sweep shard index (0-based)")
    parser.add_argument("--workers", type=int, default=1, help="worker processes (the job's cores)")
    args = parser.parse_args(argv)
    TASKS[args.task](args)
    # the job's exact CPU, last line of its log: Snakemake's benchmark file samples it (every 30 s after ~15 s of
    # wall time, keeping the last sample) and undercounts long jobs
    own, workers = (resource.getrusage(who) for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))
    figures = sys.modules.get("bounce.figures.common")  # imported by a job that draws (or by the task server)
    print(f"cpu: {own.ru_utime + own.ru_stime:.2f} s in this process{STARTED_BY}, {workers.ru_utime + workers.ru_stime:.2f} "
          f"s in its worker processes; {figures.saving_cpu if figures else 0.0:.2f} s of it saving figures",
          file=sys.stderr)
    return 0


if __name__ == "__main__":  # the guard also keeps spawned sweep workers from re-running the task
    status = main()
    # every output is written, closed and renamed in place by now (bounce.io's atomic writes, figures' savefig, the
    # workers joined): end without the interpreter's teardown, which frees every module and compiled kernel one by
    # one and cost ~0.4 s of CPU per job (a check job: 4.0 s -> 3.6 s), ~40 s over the pipeline's jobs
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)
