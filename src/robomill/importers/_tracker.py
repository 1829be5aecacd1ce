"""Laser-tracker point exports (SpatialAnalyzer, FARO) → ``tracker/<dir>_f<feed>.csv``.

Both programs export a measured point stream as text: optional comment/metadata lines, a
header row naming the columns, then one point per row with a name, X, Y, Z and — depending on
the export settings — a time stamp. Time stamps are often coarse (printed to the millisecond
or the second, several points sharing one stamp) or absent; the contract needs ``t_s`` at
the tracker rate, so the axis is rebuilt as ``t0 + k/fs`` from the stated ``--fs-hz``
(:func:`robomill.importers._common.time_axis`), checked against the stamps where they exist.
Coordinates are converted to mm from the export's unit (``--units``, or a ``Units`` line /
a unit in the column names).
"""

from __future__ import annotations

import argparse
import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from robomill.importers._common import (
    is_number,
    read_text,
    row_floats,
    split_fields,
    time_axis,
    to_float,
    write_csv,
)
from robomill.io.errors import RawDataError

UNITS_MM = {"mm": 1.0, "millimeters": 1.0, "millimetres": 1.0, "m": 1e3, "meters": 1e3,
            "metres": 1e3, "in": 25.4, "inch": 25.4, "inches": 25.4, "um": 1e-3}
DIRECTIONS = ("px", "py", "my")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options shared by the tracker importers."""
    parser.add_argument("--fs-hz", type=float, default=None,
                        help="tracker rate [Hz]; required when the time stamps are coarse or "
                             "absent (they are then rebuilt as t0 + k/fs)")
    parser.add_argument("--direction", choices=DIRECTIONS, default=None,
                        help="cut direction of the record (manifest key direction)")
    parser.add_argument("--feed-mm-s", type=float, default=None,
                        help="feed of the record [mm/s] (manifest key feed_mm_s)")
    parser.add_argument("--units", choices=sorted(UNITS_MM), default=None,
                        help="coordinate unit of the export (default: from the file, else mm)")
    parser.add_argument("--time-unit", choices=("s", "ms"), default="s",
                        help="unit of a numeric time column (default s)")


def _unit_in(name: str) -> str | None:
    m = re.search(r"[\[\(]\s*([A-Za-z]+)\s*[\]\)]", name)
    return m[1].lower() if m else None


def _base(name: str) -> str:
    return re.sub(r"\s*[\[\(].*?[\]\)]\s*", "", name).strip().lower()


def _parse_times(source: Path, texts: Sequence[str], start_line: int, column: str,
                 time_unit: str) -> np.ndarray:
    if all(is_number(t) for t in texts):
        scale = 1e-3 if time_unit == "ms" else 1.0
        return np.array([to_float(t, False) for t in texts]) * scale
    import pandas as pd

    try:
        stamps = pd.to_datetime(pd.Series(list(texts)), format="mixed")
    except (ValueError, TypeError) as exc:
        bad = next((i for i, t in enumerate(texts) if not t.strip()), 0)
        raise RawDataError(source, f"time stamp cannot be read ({exc})",
                           where=f"line {start_line + bad}, column {column}",
                           expected="seconds, or a date/time such as 2021-03-04 10:15:23.125"
                           ) from None
    return (stamps - stamps.iloc[0]).dt.total_seconds().to_numpy(dtype=float)


def read_points(source: Path, *, fmt: str, what: str,
                time_names: Sequence[str], units: str | None, time_unit: str = "s"
                ) -> tuple[np.ndarray, np.ndarray | None, dict]:
    """Read a point export: ``(points_mm (n, 3), times_s (n,) or None, info)``.

    Raises
    ------
    RawDataError
        Missing/empty/binary file; no header row with X, Y, Z; an unknown unit; text in a
        coordinate; a short (truncated) row; unreadable time stamps.
    """
    text = read_text(source, what)
    lines = text.splitlines()
    file_unit = None
    header_i = None
    sep = None
    for i, line in enumerate(lines[:200]):
        stripped = line.strip().lstrip("/").lstrip("#").strip()
        m = re.match(r"(?i)^(units?|length\s+units?|einheit)\s*[:=,\t]\s*([A-Za-z]+)", stripped)
        if m and m[2].lower() in UNITS_MM:
            file_unit = m[2].lower()
            continue
        for s in ("\t", ";", ",", None):
            names = [_base(f) for f in split_fields(stripped, s)]
            if {"x", "y", "z"} <= set(names):
                header_i, sep = i, s
                break
        if header_i is not None:
            break
    if header_i is None:
        raise RawDataError(source, "no header row naming X, Y, Z", where="header (first 200 lines)",
                           expected=what)
    head_line = lines[header_i].strip().lstrip("/").lstrip("#").strip()
    fields = split_fields(head_line, sep)
    names = [_base(f) for f in fields]
    col_units = {_unit_in(f) for f in fields if _base(f) in ("x", "y", "z")} - {None}
    unit = units or (col_units.pop() if len(col_units) == 1 else None) or file_unit or "mm"
    if unit not in UNITS_MM:
        raise RawDataError(source, f"coordinate unit {unit!r}", where=f"line {header_i + 1}",
                           expected="one of " + ", ".join(sorted(UNITS_MM)))
    ix = [names.index(a) for a in ("x", "y", "z")]
    it = next((i for i, n in enumerate(names) if n in time_names), None)
    rows = []
    for k, line in enumerate(lines[header_i + 1:], start=header_i + 2):
        if not line.strip() or line.lstrip().startswith(("//", "#")):
            continue
        rows.append((k, split_fields(line, sep)))
    decimal_comma = sep not in (",", None) and any("," in f[ix[0]] for _, f in rows[:20]
                                                     if len(f) > ix[0])
    ncol = len(fields)
    pts = np.empty((len(rows), 3))
    times = []
    for r, (lineno, f) in enumerate(rows):
        pts[r] = row_floats(source, f, ix, fields, lineno=lineno, ncol=ncol,
                            last=r == len(rows) - 1, decimal_comma=decimal_comma,
                            header="header", expected="a coordinate")
        if it is not None:
            times.append(f[it])
    if not np.all(np.isfinite(pts)):
        r, j = np.argwhere(~np.isfinite(pts))[0]
        raise RawDataError(source, "value is not finite",
                           where=f"line {rows[r][0]}, column {fields[ix[j]]}",
                           expected="a finite coordinate")
    t = None
    if it is not None and rows:
        t = _parse_times(source, times, rows[0][0], fields[it], time_unit)
    info = {"format": fmt, "unit": unit, "time_column": fields[it] if it is not None else None,
            "n": len(rows)}
    return pts * UNITS_MM[unit], t, info


def convert_points(sources: list[Path], staging: Path, args: argparse.Namespace, *, fmt: str,
                   what: str, time_names: Sequence[str]) -> list[dict]:
    """Write ``staging/tracker/<dir>_f<feed>.csv`` per source; return the manifest entries
    ``{"path", "kind": "tracker", "direction", "feed_mm_s", "fs_hz"}``."""
    entries = []
    direction = getattr(args, "direction", None)
    feed = getattr(args, "feed_mm_s", None)
    for src in sources:
        src = Path(src)
        if direction not in DIRECTIONS:
            raise RawDataError(src, "no cut direction", where="option --direction",
                               expected="--direction px, py or my")
        if not feed or feed <= 0:
            raise RawDataError(src, "no feed", where="option --feed-mm-s",
                               expected="--feed-mm-s FEED (> 0)")
        if len(sources) > 1:
            raise RawDataError(src, f"{len(sources)} sources for one direction and feed",
                               where="sources", expected="one tracker export per import")
        pts, t, info = read_points(src, fmt=fmt, what=what,
                                   time_names=time_names, units=getattr(args, "units", None),
                                   time_unit=getattr(args, "time_unit", "s"))
        if pts.shape[0] < 2:
            raise RawDataError(src, f"only {pts.shape[0]} points", where="data rows",
                               expected="a point stream")
        t_s, fs, _jitter = time_axis(src, t, pts.shape[0], getattr(args, "fs_hz", None),
                                     column=info["time_column"] or "time")
        rel = f"tracker/{direction}_f{float(feed):g}.csv"
        write_csv(staging / rel, ("t_s", "x_mm", "y_mm", "z_mm"), (t_s - t_s[0], *pts.T),
                  ("%.9f", "%.6f", "%.6f", "%.6f"))
        entries.append({"path": rel, "kind": "tracker", "direction": direction,
                        "feed_mm_s": float(feed), "fs_hz": fs})
    return entries
