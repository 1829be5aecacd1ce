"""Laser-tracker point exports (SpatialAnalyzer, FARO) → ``tracker/<dir>_f<feed>.csv``.

Both programs export a measured point stream as text: optional comment/metadata lines, a
header row naming the columns, then one point per row with a name, X, Y, Z and — depending on
the export settings — a time stamp. Time stamps are often coarse (printed to the millisecond
or the second, several points sharing one stamp) or absent; the contract needs ``t_s`` at
the tracker rate, so the axis is rebuilt as ``t0 + k/fs`` from the stated ``--fs-hz``
(:func:`robomill.importers._common.time_axis`), checked against the stamps where they exist.
Coordinates are converted to mm from the export's unit (``--units``, or a ``Units`` line /
a unit in the column names / SpatialAnalyzer's ``// AXES = CARTESIAN: X, Y, Z (mm)`` line).

SpatialAnalyzer's own "Export Points to ASCII" writes **no header row** (SA User Manual,
"Exporting ASCII Formatted Points"; a real SA 2024.2 export is described in
``tests/data/real/spatialanalyzer/SOURCE.md``): ``//`` comment lines (version, frame, axes
and unit), then per point the name fields chosen in the export dialog (``Collection, Group,
Target`` by default; ``--name-fields`` 0–3), X, Y, Z and, when selected, a time stamp
(``02/12/25 16:52:45``: to the second), separated by commas or spaces. Such a file is read
by position when no header row is found.
"""

from __future__ import annotations

import argparse
import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from robomill.errors import RawDataError
from robomill.importers._common import (
    is_number,
    read_text,
    row_floats,
    split_fields,
    time_axis,
    to_float,
    write_csv,
)

UNITS_MM = {"mm": 1.0, "millimeters": 1.0, "millimetres": 1.0, "m": 1e3, "meters": 1e3,
            "metres": 1e3, "in": 25.4, "inch": 25.4, "inches": 25.4, "um": 1e-3}
DIRECTIONS = ("px", "mx", "py", "my")
"""Named feed directions of a run (+X, −X, +Y, −Y); any other is ``--direction-deg``."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options shared by the tracker importers."""
    parser.add_argument("--fs-hz", type=float, default=None,
                        help="tracker rate [Hz]; required when the time stamps are coarse or "
                             "absent (they are then rebuilt as t0 + k/fs)")
    parser.add_argument("--direction", choices=DIRECTIONS, default=None,
                        help="feed direction of the run: px (+X), mx (-X), py (+Y), my (-Y) "
                             "(manifest key direction); or --direction-deg")
    parser.add_argument("--direction-deg", type=float, default=None,
                        help="feed direction of the run in the base XY plane [deg], 0 = +X, "
                             "counter-clockwise (manifest key direction_deg; file "
                             "tracker/d<deg>_f<feed>.csv)")
    parser.add_argument("--feed-mm-s", type=float, default=None,
                        help="feed of the record [mm/s] (manifest key feed_mm_s)")
    parser.add_argument("--units", choices=sorted(UNITS_MM), default=None,
                        help="coordinate unit of the export (default: from the file, else mm)")
    parser.add_argument("--time-unit", choices=("s", "ms"), default="s",
                        help="unit of a numeric time column (default s)")
    parser.add_argument("--spatial-only", action="store_true",
                        help="a stream without a usable time base (a distance- or event-"
                             "triggered export: coarse stamps holding uneven point counts): "
                             "kept in acquisition order without a rebuilt time axis, recorded "
                             "as time_base: none and analysed in space only (gear lines per "
                             "mm; its peaks are not classified temporal/spatial)")


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


_AXES_LINE = re.compile(r"(?i)^axes\s*=\s*([A-Za-z]+)\s*:(.*?)(?:\(\s*([A-Za-z]+)\s*\))?\s*$")
_NAME_FIELDS = ("Collection", "Group", "Target")


def _headerless(source: Path, lines: list[str], *, name_fields: int | None, what: str
                ) -> tuple[int, str | None, list[str]]:
    """Layout of an export without a header row (SpatialAnalyzer's ASCII point export):
    ``(first data line index, separator, column names)``."""
    first = next((i for i, ln in enumerate(lines)
                  if ln.strip() and not ln.lstrip().startswith(("//", "#"))), None)
    if first is None:
        raise RawDataError(source, "no point rows after the comment lines", where="file",
                           expected=what)
    line = lines[first]
    sep = "," if "," in line else ("\t" if "\t" in line else None)
    f = split_fields(line, sep)
    k = 3 if name_fields is None else name_fields
    coords = f[k:k + 3]
    if len(coords) < 3 or not all(is_number(c) for c in coords):
        raise RawDataError(source, "no header row naming X, Y, Z, and the first row has no "
                           f"X, Y, Z after {k} name field(s) ({line.strip()[:80]!r})",
                           where=f"line {first + 1}",
                           expected=what + "; or, for an export without a header row, "
                                    "--name-fields N (the name fields before X, Y, Z)")
    names = list(_NAME_FIELDS[3 - k:]) + ["X", "Y", "Z"]
    if len(f) > k + 3:
        names.append("Time")
    return first, sep, names


def _one_group(source: Path, rows: list, nk: int, group: str | None) -> list:
    """The rows of one point group (``Collection::Group`` from the name fields)."""
    keys = ["::".join(f[:nk - 1]) for _, f in rows]
    order = list(dict.fromkeys(keys))
    if group is not None:
        keep = [r for r, k in zip(rows, keys, strict=True)
                if group in (k, k.split("::")[-1])]
        if not keep:
            raise RawDataError(source, f"no rows of point group {group!r}",
                               where="option --group", expected="one of " + ", ".join(order[:8]))
        return keep
    if len(order) > 1:
        counts = {k: keys.count(k) for k in order}
        first_other = next(r[0] for r, k in zip(rows, keys, strict=True) if k != order[0])
        raise RawDataError(source, f"rows of {len(order)} point groups ("
                           + ", ".join(f"{k}: {n} rows" for k, n in list(counts.items())[:5])
                           + ")", where=f"line {first_other}",
                           expected="one point stream per export, or --group GROUP")
    return rows


def read_points(source: Path, *, fmt: str, what: str,
                time_names: Sequence[str], units: str | None, time_unit: str = "s",
                headerless: bool = False, name_fields: int | None = None,
                group: str | None = None) -> tuple[np.ndarray, np.ndarray | None, dict]:
    """Read a point export: ``(points_mm (n, 3), times_s (n,) or None, info)``.

    With ``headerless`` (SpatialAnalyzer), a file without a header row is read by position:
    ``name_fields`` name fields (default 3), X, Y, Z, then an optional time stamp (the
    fields after Z joined, so that a space-separated ``date time`` stays one stamp). An SA
    export can hold several point groups; the stream must be one: ``group`` (``Group`` or
    ``Collection::Group``) picks it, else a file with rows of several groups is refused.

    Raises
    ------
    RawDataError
        Missing/empty/binary file; no header row with X, Y, Z (nor, with ``headerless``, a
        first row with numbers where X, Y, Z should be); an unknown unit or non-Cartesian
        axes; text in a coordinate; a short (truncated) row; unreadable time stamps; rows
        of several point groups without ``group``, or a ``group`` that has no rows.
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
        m = _AXES_LINE.match(stripped) if line.lstrip().startswith("//") else None
        if m:
            if m[1].lower() != "cartesian":
                raise RawDataError(source, f"coordinates are {m[1].upper()}",
                                   where=f"line {i + 1}",
                                   expected="a Cartesian export (AXES = CARTESIAN: X, Y, Z)")
            if m[3]:
                file_unit = m[3].lower()
            continue
        for s in ("\t", ";", ",", None):
            names = [_base(f) for f in split_fields(stripped, s)]
            if {"x", "y", "z"} <= set(names):
                header_i, sep = i, s
                break
        if header_i is not None:
            break
    if header_i is None and not headerless:
        raise RawDataError(source, "no header row naming X, Y, Z", where="header (first 200 lines)",
                           expected=what)
    if header_i is None:
        data_i, sep, fields = _headerless(source, lines, name_fields=name_fields, what=what)
        header_i = data_i - 1
        joined = True
    else:
        fields = split_fields(lines[header_i].strip().lstrip("/").lstrip("#").strip(), sep)
        joined = False
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
        f = split_fields(line, sep)
        if joined and len(f) > len(fields):  # "date time" split by a space separator
            f = f[:len(fields) - 1] + [" ".join(f[len(fields) - 1:])]
        rows.append((k, f))
    nk = len(fields) - 3 - (1 if fields[-1] == "Time" else 0) if joined else 0
    if joined and nk >= 2:
        rows = _one_group(source, rows, nk, group)
    decimal_comma = sep not in (",", None) and any("," in f[ix[0]] for _, f in rows[:20]
                                                     if len(f) > ix[0])
    ncol = len(fields)
    pts = np.empty((len(rows), 3))
    times = []
    for r, (lineno, f) in enumerate(rows):
        pts[r] = row_floats(source, f, ix, fields, lineno=lineno, ncol=ncol,
                            last=r == len(rows) - 1, decimal_comma=decimal_comma,
                            header="first row" if joined else "header", expected="a coordinate")
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


def event_triggered(t: np.ndarray | None, *, min_stamps: int = 3,
                    spread: float = 1.5) -> str | None:
    """Why a stream has no time base, or None: coarse stamps (several points each) whose inner
    stamps (between the first and the last, which are partial) hold point counts differing
    by more than ``spread`` times (at least ``min_stamps`` of them) — a tracker triggered by
    distance or by an event, whose rate is not uniform (a real SpatialAnalyzer stream: whole
    seconds holding 98–444 points, median 159)."""
    if t is None or len(t) < 3 or np.any(np.diff(t) < 0):
        return None
    _, counts = np.unique(t, return_counts=True)
    inner = counts[1:-1]
    if inner.size < min_stamps or inner.min() < 2 or inner.max() < spread * inner.min():
        return None
    return (f"{len(t)} points on {counts.size} time stamps holding {int(inner.min())}–"
            f"{int(inner.max())} points each (median {float(np.median(inner)):g}): no uniform "
            "rate (a distance- or event-triggered export)")


def convert_points(sources: list[Path], staging: Path, args: argparse.Namespace, *, fmt: str,
                   what: str, time_names: Sequence[str], headerless: bool = False
                   ) -> list[dict]:
    """Write ``staging/tracker/<dir>_f<feed>.csv`` per source (``d<deg>_f<feed>.csv`` with
    ``--direction-deg``); return the manifest entries ``{"path", "kind": "tracker",
    "direction" or "direction_deg", "feed_mm_s", "fs_hz"}`` (``headerless``: see
    :func:`read_points`). With ``args.spatial_only`` no time axis is rebuilt: ``t_s`` holds
    the export's stamps from the first (or the sample number without stamps) and the entry
    has ``time_base: none`` instead of ``fs_hz``. A stream refused for its stamps that looks
    distance- or event-triggered (:func:`event_triggered`) is refused with one line
    suggesting ``--spatial-only``."""
    from robomill.experiment import tracker_direction

    entries = []
    direction = getattr(args, "direction", None)
    deg = getattr(args, "direction_deg", None)
    feed = getattr(args, "feed_mm_s", None)
    for src in sources:
        src = Path(src)
        if (direction is None) == (deg is None):
            raise RawDataError(src, "no feed direction" if direction is None else
                               "both --direction and --direction-deg",
                               where="option --direction",
                               expected="--direction px, mx, py or my, or --direction-deg DEG")
        if not feed or feed <= 0:
            raise RawDataError(src, "no feed", where="option --feed-mm-s",
                               expected="--feed-mm-s FEED (> 0)")
        if len(sources) > 1:
            raise RawDataError(src, f"{len(sources)} sources for one direction and feed",
                               where="sources", expected="one tracker export per import")
        pts, t, info = read_points(src, fmt=fmt, what=what,
                                   time_names=time_names, units=getattr(args, "units", None),
                                   time_unit=getattr(args, "time_unit", "s"),
                                   headerless=headerless,
                                   name_fields=getattr(args, "name_fields", None),
                                   group=getattr(args, "group", None))
        if pts.shape[0] < 2:
            raise RawDataError(src, f"only {pts.shape[0]} points", where="data rows",
                               expected="a point stream")
        column = info["time_column"] or "time"
        where = {"direction": direction} if deg is None else {"direction_deg": float(deg)}
        rel = f"tracker/{tracker_direction(where)}_f{float(feed):g}.csv"
        if getattr(args, "spatial_only", False):
            # no time base: the export's own stamps (or the sample number) kept as they are
            t_s = np.arange(pts.shape[0], dtype=float) if t is None else t - t[0]
            entry = {"time_base": "none"}
        else:
            try:
                t_s, fs, _jitter = time_axis(src, t, pts.shape[0],
                                             getattr(args, "fs_hz", None), column=column)
            except RawDataError:
                untimed = event_triggered(t)
                if untimed is None:
                    raise
                raise RawDataError(src, untimed, where=f"column {column}",
                                   expected="--spatial-only to import it for a spatial "
                                            "analysis (gear lines per mm), or a "
                                            "time-triggered export") from None
            entry = {"fs_hz": fs}
        write_csv(staging / rel, ("t_s", "x_mm", "y_mm", "z_mm"), (t_s - t_s[0], *pts.T),
                  ("%.9f", "%.6f", "%.6f", "%.6f"))
        entries.append({"path": rel, "kind": "tracker", **where,
                        "feed_mm_s": float(feed), **entry})
    return entries
