"""New River Kinematics / Hexagon SpatialAnalyzer point exports → ``tracker/<dir>_f<feed>.csv``.

SpatialAnalyzer's "Export Points to ASCII" writes ``//`` comment lines (the SA version, the
frame, ``AXES = CARTESIAN: X, Y, Z (mm)``), then one point per row: the name fields chosen
in the dialog (``Collection, Group, Target`` by default, ``--name-fields``), ``X, Y, Z`` in
the job's length unit and — with "Time Stamps" ticked — a date and time printed to the
second (``02/12/25 16:52:45``); commas or spaces separate the fields and there is **no**
header row (SA User Manual; a real SA 2024.2 export, ``tests/data/real/spatialanalyzer/
SOURCE.md``). Files re-saved with a header row (``Collection,Group,Target,X,Y,Z,Timestamp``,
``Units:`` line) are read by the header. The stamps are far coarser than the tracker rate:
give ``--fs-hz`` and the time axis is rebuilt (see :mod:`robomill.importers._tracker`). A
stream triggered by distance or by events (whole-second stamps holding uneven point counts)
has no time base to rebuild: ``--spatial-only`` imports it for a spatial analysis alone.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from robomill.importers import _tracker

FORMAT = "spatialanalyzer"
KIND = "tracker"
DESCRIPTION = "SpatialAnalyzer (SA) tracker point export, ASCII/CSV"

WHAT = ("a SpatialAnalyzer point export: '//' comment lines, then one point per row (name "
        "fields, X, Y, Z, time stamp), or a header row with X, Y, Z (and Time)")
TIME_NAMES = ("time", "timestamp", "time stamp", "timestamps", "t")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """``--fs-hz``, ``--direction`` (or ``--direction-deg``), ``--feed-mm-s``, ``--units``,
    ``--time-unit``, ``--spatial-only``, ``--name-fields``, ``--group``."""
    _tracker.add_arguments(parser)
    parser.add_argument("--name-fields", type=int, choices=(0, 1, 2, 3), default=None,
                        help="export without a header row (SA's own ASCII export): how many "
                             "name fields come before X, Y, Z (3: Collection, Group, Target, "
                             "SA's default; 2: Group, Target; 1: Target; 0: none)")
    parser.add_argument("--group", default=None,
                        help="the point group of the stream (GROUP or COLLECTION::GROUP) when "
                             "the export holds several")


def convert(sources: list[Path], staging: Path, args: argparse.Namespace) -> list[dict]:
    """Write the tracker record; return its manifest entry."""
    return _tracker.convert_points(sources, staging, args, fmt=FORMAT, what=WHAT,
                                   time_names=TIME_NAMES, headerless=True)
