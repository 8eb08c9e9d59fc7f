"""Shared figure style and atomic saving (PNG + PDF).  Figures read netCDF only."""

from __future__ import annotations

import os
import time
import uuid
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

#: the paper's text width is ~6.3 in (A4 amsart); figures are drawn at that size.
WIDTH = 6.3

plt.rcParams.update({
    "font.size": 9,
    "axes.labelsize": 9,
    "axes.titlesize": 9,
    "legend.fontsize": 8,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "figure.dpi": 150,
    "savefig.dpi": 200,
    "lines.linewidth": 0.9,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "pdf.fonttype": 42,
    "svg.hashsalt": "bounce",
})

#: PDF metadata without timestamps, so reruns give identical files.
PDF_METADATA = {"CreationDate": None, "ModDate": None, "Producer": "bounce / matplotlib"}


#: CPU seconds this process has spent in :func:`save` (layout, drawing, font subsetting, writing): a pipeline job
#: reports it on its ``cpu:`` line (:func:`bounce.pipeline.tasks.main`)
saving_cpu = 0.0


def save(fig, outputs) -> None:
    """Save ``fig`` to every path in ``outputs`` (format from the suffix), each atomically.

    The temporary file is created by matplotlib like any other file (mode 0666 less the umask,
    as the netCDF files), not by ``mkstemp`` (0600), so figures are readable like the rest."""
    global saving_cpu
    start = time.process_time()
    try:
        for out in outputs:
            out = Path(out)
            out.parent.mkdir(parents=True, exist_ok=True)
            tmp = out.parent / f".{out.name}.{os.getpid()}.{uuid.uuid4().hex[:12]}{out.suffix}"
            try:
                meta = PDF_METADATA if out.suffix == ".pdf" else {"Software": "bounce / matplotlib"}
                fig.savefig(tmp, metadata=meta, bbox_inches="tight")
                os.replace(tmp, out)
            except BaseException:
                Path(tmp).unlink(missing_ok=True)
                raise
        plt.close(fig)
    finally:
        saving_cpu += time.process_time() - start


def log_binned(x: np.ndarray, v: np.ndarray, stat, per_decade: int = 5, least: int = 1):
    """(centres, stat(v) per bin) over log-spaced bins of x > 0 (``per_decade`` a decade; bins with fewer than ``least``
    finite values left out), the centres geometric: a long or oscillating sequence drawn as one smooth line."""
    ok = np.isfinite(x) & np.isfinite(v) & (x > 0)
    x, v = x[ok], v[ok]
    if not x.size:
        return np.array([]), np.array([])
    edges = np.geomspace(x.min(), x.max() * (1 + 1e-12), max(2, int(np.log10(x.max() / x.min()) * per_decade) + 1))
    idx = np.digitize(x, edges) - 1
    bins = [k for k in range(edges.size - 1) if np.count_nonzero(idx == k) >= least]
    return (np.sqrt(edges[bins] * edges[np.array(bins, dtype=int) + 1]),
            np.array([stat(v[idx == k]) for k in bins]))


def legend_below(fig, handles, labels, ncol: int = 3, fontsize: float = 6.5) -> None:
    """One legend for the whole figure, hung under its lowest labels, off every panel (the tight bounding box of
    :func:`save` takes it in).  Call it after ``tight_layout``."""
    fig.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=ncol, fontsize=fontsize,
               frameon=False)


def tex_num(x, digits: int = 3) -> str:
    """``x`` for mathtext (inside ``$...$``), the one number format of every figure text:
    0.01 -> ``0.01``, 1e-05 -> ``10^{-5}``, 2.5e-05 -> ``2.5\\times10^{-5}``, 3e+05 -> ``3\\times10^{5}``
    (``%g`` would print "1e-05", which mathtext renders as "1e - 05")."""
    s = f"{float(x):.{digits}g}"
    if "e" not in s:
        return s
    mantissa, exponent = s.split("e")
    power = f"10^{{{int(exponent)}}}"
    if mantissa in ("1", "-1"):
        return mantissa[:-1] + power
    return f"{mantissa}\\times{power}"


def label_time(ax) -> None:
    ax.set_xlabel(r"$t$  [$\sqrt{m/2k}$]")


def thumbnail(src, dst, width: int = 480) -> None:
    """A ``width``-pixel-wide PNG copy of the figure ``src`` (for the README)."""
    from PIL import Image

    with Image.open(src) as img:
        img = img.convert("RGB")
        img.thumbnail((width, width * img.height // img.width))
        Path(dst).parent.mkdir(parents=True, exist_ok=True)
        img.save(dst, optimize=True)
