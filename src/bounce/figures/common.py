"""Shared figure style and atomic saving (PNG + PDF).  Figures read netCDF only."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import matplotlib

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


def save(fig, outputs) -> None:
    """Save ``fig`` to every path in ``outputs`` (format from the suffix), each atomically."""
    for out in outputs:
        out = Path(out)
        out.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=out.parent, prefix=f".{out.name}.", suffix=out.suffix)
        os.close(fd)
        try:
            meta = PDF_METADATA if out.suffix == ".pdf" else {"Software": "bounce / matplotlib"}
            fig.savefig(tmp, metadata=meta, bbox_inches="tight")
            os.replace(tmp, out)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
    plt.close(fig)


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
