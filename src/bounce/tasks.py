"""Entry points of the Snakemake rules: ``python -m bounce.tasks <task> --spec JSON ...``.

Each task takes the config slice it uses as JSON (so a config edit reruns only
what depends on it), reads/writes files, and delegates to the package.
"""

from __future__ import annotations

import argparse
import json
import sys

from .io import read_dataset, write_netcdf


def _scene(args) -> None:
    from .scenes import scene_dataset

    write_netcdf(scene_dataset(args.spec, name=args.name), args.out[0])


def _sticky_inference(args) -> None:
    from .sticky_study import t_c_map

    write_netcdf(t_c_map(args.spec), args.out[0])


def _sticky_convergence(args) -> None:
    from .sticky_study import convergence

    reference, *runs = (read_dataset(p) for p in args.inputs)
    write_netcdf(convergence(reference, runs, args.spec["samples"]), args.out[0])


def _figure(args) -> None:
    from .figures import FIGURES

    FIGURES[args.name]([read_dataset(p) for p in args.inputs], args.spec, args.out)


def _thumbnails(args) -> None:
    from .figures.common import thumbnail

    for src, dst in zip(args.inputs, args.out, strict=True):
        thumbnail(src, dst)


TASKS = {
    "scene": _scene,
    "sticky-inference": _sticky_inference,
    "sticky-convergence": _sticky_convergence,
    "figure": _figure,
    "thumbnails": _thumbnails,
}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bounce.tasks", description=__doc__.splitlines()[0])
    parser.add_argument("task", choices=sorted(TASKS))
    parser.add_argument("--name", default="", help="scene or figure name")
    parser.add_argument("--spec", type=json.loads, default={}, help="the config slice, as JSON")
    parser.add_argument("--inputs", nargs="*", default=[], help="input netCDF files")
    parser.add_argument("--out", nargs="+", required=True, help="output file(s)")
    args = parser.parse_args(argv)
    TASKS[args.task](args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
