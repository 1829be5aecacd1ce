"""FARO laser-tracker point exports (CAM2 / Tracker Utilities) → ``tracker/<dir>_f<feed>.csv``.

FARO's software exports a measured stream as CSV/TXT: a few metadata lines (device, units),
a header row such as ``Name, X (mm), Y (mm), Z (mm), Time Stamp`` and one point per row; the
time stamp is a date/time or seconds, often to the millisecond only, and may be missing.
Coordinates are converted to mm (unit from the column names, a ``Units`` line or
``--units``); the time axis is kept when it is uniform, else rebuilt from ``--fs-hz``
(see :mod:`robomill.importers._tracker`).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from robomill.importers import _tracker

FORMAT = "faro"
KIND = "tracker"
DESCRIPTION = "FARO laser-tracker point export (CAM2 / Tracker Utilities), CSV/TXT"

WHAT = "a FARO tracker export: metadata lines, a header row with X, Y, Z (and a time stamp)"
TIME_NAMES = ("time", "time stamp", "timestamp", "time (s)", "elapsed time", "t")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """``--fs-hz``, ``--direction`` (or ``--direction-deg``), ``--feed-mm-s``, ``--units``,
    ``--time-unit``."""
    _tracker.add_arguments(parser)


def convert(sources: list[Path], staging: Path, args: argparse.Namespace) -> list[dict]:
    """Write the tracker record; return its manifest entry."""
    return _tracker.convert_points(sources, staging, args, fmt=FORMAT, what=WHAT,
                                   time_names=TIME_NAMES)
