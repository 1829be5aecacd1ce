"""New River Kinematics / Hexagon SpatialAnalyzer point exports → ``tracker/<dir>_f<feed>.csv``.

SpatialAnalyzer's "Export → Points to ASCII/CSV" writes ``//`` comment lines (the job, the
units), then a header row and one point per row: ``Collection, Group, Point`` (or one
``Collection::Group::Point`` name), ``X, Y, Z`` in the job's length unit, and — when the
point stream was recorded with stamps — a ``Time``/``Timestamp`` column (seconds, or a date
and time printed to the millisecond). The stamps are usually coarser than the tracker rate;
give ``--fs-hz`` and the time axis is rebuilt (see :mod:`robomill.importers._tracker`).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from robomill.importers import _tracker

FORMAT = "spatialanalyzer"
KIND = "tracker"
DESCRIPTION = "SpatialAnalyzer (SA) tracker point export, ASCII/CSV"

WHAT = ("a SpatialAnalyzer point export: '//' comment lines, a header row with X, Y, Z "
        "(and Time), one point per row")
TIME_NAMES = ("time", "timestamp", "time stamp", "timestamps", "t")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """``--fs-hz``, ``--direction``, ``--feed-mm-s``, ``--units``, ``--time-unit``."""
    _tracker.add_arguments(parser)


def convert(sources: list[Path], staging: Path, args: argparse.Namespace) -> list[dict]:
    """Write the tracker record; return its manifest entry."""
    return _tracker.convert_points(sources, staging, args, fmt=FORMAT, what=WHAT,
                                   time_names=TIME_NAMES)
