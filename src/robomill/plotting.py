"""Shared figure conventions for the chapters (Agg backend, one style, saved and shown)."""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib


def _inline_in_notebooks() -> bool:
    """Switch a notebook kernel to the inline backend; False outside a kernel.

    Chapters must show their figures inline even where the environment exports
    ``MPLBACKEND=Agg`` (headless CI does): the kernel then starts on Agg and the rendered HTML
    chapter would hold no figure. ``%matplotlib inline`` also registers the PNG formatter.
    """
    if "ipykernel" not in sys.modules:
        return False
    from IPython import get_ipython

    shell = get_ipython()
    if shell is None:
        return False
    shell.run_line_magic("matplotlib", "inline")
    return True


if not _inline_in_notebooks():
    matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {
    "figure.figsize": (7.5, 4.2),
    "figure.dpi": 110,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "savefig.bbox": "tight",
}
plt.rcParams.update(STYLE)

SAVE_DPI = 150
"""Resolution of the saved figure files [dots per inch]."""


def save_figure(fig: plt.Figure, fig_dir: str | Path, name: str) -> Path:
    """Save ``fig`` as ``<fig_dir>/<name>.png`` (150 dpi) and return the path.

    In a notebook the figure is also displayed inline (so the HTML chapter is
    self-contained) by returning it as the cell's last expression or via ``display``.
    """
    path = Path(fig_dir) / f"{name}.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=SAVE_DPI)
    return path


def saved_image(path: str | Path, shown_dpi: float, alt: str = ""):
    """The PNG that :func:`save_figure` wrote, as an IPython image shown at the size the
    inline backend would give it (``shown_dpi``) with alternative text ``alt``: a chapter
    renders each figure once, not a second time for its inline copy."""
    from IPython.display import Image
    from PIL import Image as PILImage

    with PILImage.open(path) as im:
        width_px = im.size[0]
    return Image(filename=str(path), width=round(width_px * shown_dpi / SAVE_DPI), alt=alt)
