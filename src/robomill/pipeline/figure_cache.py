"""Reuse a chapter figure's PNG when the figure is the one an earlier run drew.

A chapter rerun (``snakemake -j2 ch3_modal --forcerun ch3_modal``, or a run after an edit
of the chapter's prose) builds every figure again, and most of them are the figures of the
last run: same data, same code. Drawing them (Matplotlib's tight-bounding-box layout, the
Agg draw, the PNG encoding) is most of a chapter job's processor time: 3.4 s for the 13
figures of chapter 3.3 on the 2-core development machine, against 1.8 s for all its cells.
The figure workers (:mod:`robomill.pipeline.figure_workers`) therefore keep each PNG they
draw in a cache, under a key that covers everything the PNG depends on, and copy it back
instead of drawing when the same key comes again:

* the figure itself, pickled *canonically* (:func:`figure_blob`): Matplotlib's pickle of a
  figure holds ``id()`` values (the keys of each transform's ``_parents``) and sets of axes
  in hash order (the shared-axes groups), which differ between two processes building the
  same figure; :class:`CanonicalPickler` numbers those keys in order and sorts those sets
  by the group's own insertion order, so that the same figure gives the same bytes. Neither
  bears on drawing: the keys are only labels of weak references, the order of a group is
  kept in the group itself. The workers draw from this same pickle;
* the ``rcParams`` the figure is drawn under (:func:`robomill.pipeline.figure_workers.drawing_rc`);
* the drawing environment (:func:`drawing_environment`): the versions of Python, Matplotlib,
  FreeType, Pillow and zlib, the font files Matplotlib knows, and the code that saves a
  figure (``robomill/plotting.py``, ``robomill/pipeline/figure_workers.py``).

A cached PNG is therefore the file a redraw would write, byte for byte (tested); a figure
that changes in any way, by one data point or one label, is drawn. The cache of a chapter
is the folder ``results/.cache/figures/<chapter>`` (``chapters.figure_cache``; ``false``
draws every figure each run); after each successful run it keeps only that run's figures.
Deleting it costs only the time to draw them again.
"""

from __future__ import annotations

import copyreg
import hashlib
import io
import logging
import pickle
from collections.abc import Iterable, Mapping
from functools import cache
from pathlib import Path
from typing import Any

log = logging.getLogger(__name__)

#: the files whose code decides how a pickled figure becomes a PNG (part of every key)
DRAWING_CODE = ("plotting.py", "pipeline/figure_workers.py")


@cache
def _matplotlib_types() -> tuple[type, type, type]:
    from matplotlib.cbook import Grouper
    from matplotlib.figure import Figure
    from matplotlib.transforms import TransformNode

    return TransformNode, Grouper, Figure


class CanonicalPickler(pickle.Pickler):
    """A pickler that writes the same bytes for the same figure in any process.

    Everything is pickled as :mod:`pickle` would, except three pieces of Matplotlib state
    that differ between two builds of the same figure and play no part in drawing it: a
    transform's ``_parents`` (its ``__getstate__`` gives ``{id(parent): parent}``, memory
    addresses; here ``{0: parent, 1: ...}`` in the same order), a
    :class:`matplotlib.cbook.Grouper`'s ``_mapping`` (sets of axes, in address order; here
    lists in the order the grouper itself records, ``_ordering``) and the figure's pyplot
    number ``_number`` (left out: unpickling gives the figure a new number). Each unpickles
    through its class's own ``__setstate__`` as before.
    """

    def reducer_override(self, obj: Any):
        transform_node, grouper, figure = _matplotlib_types()
        if isinstance(obj, transform_node):
            state = obj.__getstate__()
            state["_parents"] = dict(enumerate(state["_parents"].values()))
            return copyreg.__newobj__, (type(obj),), state
        if isinstance(obj, grouper):
            state = obj.__getstate__()
            order = state["_ordering"]
            state["_mapping"] = {k: sorted(v, key=order.__getitem__)
                                 for k, v in state["_mapping"].items()}
            return copyreg.__newobj__, (type(obj),), state
        if isinstance(obj, figure):
            state = obj.__getstate__()
            state.pop("_number", None)
            return copyreg.__newobj__, (type(obj),), state
        return NotImplemented


def figure_blob(fig) -> bytes:
    """``fig`` pickled by :class:`CanonicalPickler` (the highest protocol)."""
    buffer = io.BytesIO()
    CanonicalPickler(buffer, protocol=pickle.HIGHEST_PROTOCOL).dump(fig)
    return buffer.getvalue()


@cache
def drawing_environment() -> bytes:
    """What, besides the figure and its ``rcParams``, decides the PNG's bytes: the versions
    of Python, Matplotlib, FreeType, Pillow and zlib (Matplotlib writes the PNG with Pillow),
    the font files Matplotlib can choose from (their paths), and the source of
    :data:`DRAWING_CODE`."""
    import sys
    import zlib

    import matplotlib
    import PIL
    from matplotlib import font_manager, ft2font

    known = font_manager.fontManager
    fonts = sorted(f.fname for f in known.ttflist + known.afmlist)
    root = Path(__file__).resolve().parents[1]
    code = b"".join((root / name).read_bytes() for name in DRAWING_CODE)
    return pickle.dumps((sys.version, matplotlib.__version__, ft2font.__freetype_version__,
                         PIL.__version__, zlib.ZLIB_RUNTIME_VERSION, fonts,
                         hashlib.sha256(code).hexdigest()), protocol=4)


def figure_key(blob: bytes, rc: Mapping[str, Any]) -> str:
    """The cache key of a figure pickled as ``blob`` drawn under ``rc``: a SHA-256 of the
    pickle, the ``rcParams`` (sorted by name, as ``repr``) and :func:`drawing_environment`."""
    digest = hashlib.sha256(blob)
    digest.update(repr(sorted(rc.items())).encode())
    digest.update(drawing_environment())
    return digest.hexdigest()


class FigureCache:
    """The PNGs of one chapter's figures by key, in ``folder`` (``<key>.png``)."""

    def __init__(self, folder: str | Path) -> None:
        self.folder = Path(folder)

    def _path(self, key: str) -> Path:
        return self.folder / f"{key}.png"

    def __len__(self) -> int:
        return len(list(self.folder.glob("*.png"))) if self.folder.is_dir() else 0

    def fetch(self, key: str, dest: str | Path) -> bool:
        """Copy the PNG of ``key`` to ``dest``; False when there is none, or it could not be
        copied (the figure is then drawn, and ``dest`` written again)."""
        dest = Path(dest)
        try:
            data = self._path(key).read_bytes()
            dest.parent.mkdir(parents=True, exist_ok=True)
            dest.write_bytes(data)
        except OSError as exc:
            if self._path(key).exists():
                log.warning("figure cache: %s not copied to %s (%s): drawn instead",
                            self._path(key), dest, exc)
            return False
        return True

    def store(self, key: str, png: str | Path) -> None:
        """Keep a copy of ``png`` (just drawn) under ``key``; written whole or not at all
        (:func:`robomill.io.atomic.atomic_path`)."""
        from robomill.io.atomic import atomic_path

        with atomic_path(self._path(key)) as tmp:
            tmp.write_bytes(Path(png).read_bytes())

    def keep_only(self, keys: Iterable[str]) -> int:
        """Remove every PNG (and leftover temporary file) but those of ``keys``; returns how
        many were removed. A file that cannot be removed is left, with a warning: the cache
        only saves time, and never fails a chapter."""
        wanted = {f"{k}.png" for k in keys}
        removed = 0
        try:
            entries = list(self.folder.iterdir()) if self.folder.is_dir() else []
        except OSError as exc:
            log.warning("figure cache: %s not read (%s): nothing removed", self.folder, exc)
            return 0
        for path in entries:
            if path.name in wanted or not path.is_file():
                continue
            try:
                path.unlink(missing_ok=True)
            except OSError as exc:
                log.warning("figure cache: %s not removed (%s)", path, exc)
                continue
            removed += 1
        return removed
