"""Text columns of an impact test (CSV, tab- or space-separated; a NumPy ``savetxt``, a
spreadsheet export, an acquisition program's ASCII) → ``impact/<stem>_h<k>.csv``.

Lines starting with ``#`` or ``%`` are comments; with a semicolon, tab or space separator a
decimal comma (``0,25``) is read as a decimal mark. An optional header row names the columns,
each possibly with its unit: ``force [N]``, ``acc_x (g)``, ``Force_N`` is not parsed for a
unit. Channels are chosen by header name or 1-based column number. The rate is ``--fs-hz``,
else the column named by ``--time`` (or a column named ``t``, ``time``, ``t_s``, ``Time``), in
seconds (``--time-unit ms`` for milliseconds), uniform within 1 % of its step. Units: the
command line's, else the header's; hits are found and split as for every impact importer
(:mod:`robomill.importers._impact`).
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import numpy as np

from robomill.errors import RawDataError
from robomill.importers._common import is_number, nice_rate, read_text, split_fields
from robomill.importers._impact import (
    ChannelSpec,
    add_hit_arguments,
    finish_hits,
    parse_hammer,
    parse_response,
    pick_channel,
    safe_stem,
    scale_to_si,
    write_hits,
)

FORMAT = "text"
KIND = "impact"
DESCRIPTION = ("text columns (CSV, tab or space separated; or a NumPy .npy array) of an "
               "impact test: time, hammer and accelerometer columns by header name or "
               "number, hits found and split → impact/<stem>_h<k>.csv")
WHAT = "text columns of an impact test (optional header row, then numbers)"
_UNIT = re.compile(r"^(.*?)\s*[\[(]\s*([^\])]+?)\s*[\])]\s*$")
TIME_NAMES = ("t", "time", "t_s", "time_s", "zeit")
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Impact options, the time column and its unit."""
    add_hit_arguments(parser)
    parser.add_argument("--time", default=None, metavar="CH",
                        help="the time column (name or number; default a column named t, "
                             "time or t_s, else --fs-hz)")
    parser.add_argument("--time-unit", choices=tuple(TIME_UNITS), default="s",
                        help="unit of the time column (default s)")


def read_columns(source: Path) -> tuple[list[str], list[str | None], np.ndarray]:
    """``(names, units, data (n, k))``; names ``1 … k`` without a header row. A NumPy
    ``.npy`` array (2-D, channels along its short side) is read as columns ``1 … k``.

    Raises
    ------
    RawDataError
        Missing/empty/binary file, a row of another width, a field that is not a number,
        fewer than two rows.
    """
    if Path(source).suffix.lower() == ".npy":
        return _read_npy(Path(source))
    text = read_text(source, WHAT)
    lines = [(i, ln) for i, ln in enumerate(text.splitlines(), start=1)
             if ln.strip() and not ln.lstrip().startswith(("#", "%"))]
    if not lines:
        raise RawDataError(source, "no data rows", where="file", expected=WHAT)
    first = lines[0][1]
    sep = next((c for c in ("\t", ";", ",") if c in first), None)
    fields = split_fields(first, sep)
    header = not all(is_number(f) for f in fields if f)
    names = fields if header else [str(i + 1) for i in range(len(fields))]
    units: list[str | None] = [None] * len(names)
    for i, n in enumerate(names):
        if m := _UNIT.match(n):
            names[i], units[i] = m[1].strip(), m[2].strip()
    rows = lines[1:] if header else lines
    # a decimal comma (a European spreadsheet's export) where the comma does not separate
    decimal_comma = sep != "," and bool(rows) and any(
        "," in f for f in split_fields(rows[0][1], sep))
    data = np.empty((len(rows), len(names)))
    for r, (lineno, ln) in enumerate(rows):
        f = split_fields(ln, sep)
        if f and f[-1] == "" and len(f) == len(names) + 1:
            f = f[:-1]
        if len(f) != len(names):
            raise RawDataError(source, f"row has {len(f)} fields, the "
                               f"{'header' if header else 'first row'} has {len(names)}"
                               + (" (truncated last row?)" if r == len(rows) - 1 else ""),
                               where=f"line {lineno}", expected=f"{len(names)} fields")
        for c, v in enumerate(f):
            try:
                data[r, c] = float(v.replace(",", ".") if decimal_comma else v)
            except ValueError:
                raise RawDataError(source, f"value {v!r} is not a number",
                                   where=f"line {lineno}, column {names[c]}",
                                   expected="numbers") from None
    if data.shape[0] < 2:
        raise RawDataError(source, f"only {data.shape[0]} data rows", where="file",
                           expected="time records")
    return names, units, data


def _read_npy(source: Path) -> tuple[list[str], list[str | None], np.ndarray]:
    if not source.is_file():
        raise RawDataError(source, "file does not exist", expected=WHAT)
    try:
        a = np.load(source, allow_pickle=False)
    except (ValueError, OSError) as exc:
        raise RawDataError(source, f"not a readable NumPy array ({exc})", where="file",
                           expected="a 2-D numeric .npy array") from None
    if a.ndim != 2 or a.dtype.kind not in "fiu" or min(a.shape) < 2:
        raise RawDataError(source, f"array of shape {a.shape} and type {a.dtype}",
                           where="file", expected="a 2-D numeric array (channels x samples)")
    data = a.T if a.shape[0] < a.shape[1] else a
    return [str(i + 1) for i in range(data.shape[1])], [None] * data.shape[1], data.astype(float)


def convert(sources: list[Path], staging: Path, args: argparse.Namespace) -> list[dict]:
    """Write the hit CSVs of every source; return their manifest entries."""
    entries: list[dict] = []
    for src in map(Path, sources):
        names, units, data = read_columns(src)
        hammer = parse_hammer(getattr(args, "hammer", None), src)
        specs = [parse_response(r, src) for r in getattr(args, "response", []) or []]
        if not specs:
            raise RawDataError(src, "no response channel given", where="option --response",
                               expected="--response CHANNEL:DIRECTION[:unit] (repeatable)")
        fs = getattr(args, "fs_hz", None)
        t_spec = getattr(args, "time", None)
        if t_spec is None and not fs:
            t_spec = next((n for n in names if n.lower() in TIME_NAMES), None)
        if t_spec is not None and not fs:
            i_t = pick_channel(src, names, ChannelSpec(t_spec, None, "--time"))
            t = data[:, i_t] * TIME_UNITS[getattr(args, "time_unit", "s")]
            d = np.diff(t)
            bad = np.flatnonzero((d <= 0) | (np.abs(d - np.median(d)) > 0.01 * np.median(d)))
            if bad.size:
                raise RawDataError(src, "time is not strictly increasing and uniform",
                                   where=f"row {int(bad[0]) + 2}, column {names[i_t]}",
                                   expected="a uniform time column (within 1 % of its step)")
            fs = nice_rate(1.0 / float(np.mean(d)))
        if not fs:
            raise RawDataError(src, "no time column and no sampling rate", where="header",
                               expected="--time COLUMN or --fs-hz RATE")
        i_f = pick_channel(src, names, hammer)
        f_scale, f_origin = scale_to_si(src, hammer, units[i_f], force=True)
        resp, used = [], {names[i_f]: f_origin}
        for s in specs:
            i = pick_channel(src, names, s)
            scale, origin = scale_to_si(src, s, units[i], force=False)
            resp.append((s, data[:, i] * scale))
            used[names[i]] = origin
        entries.extend(write_hits(src, staging, safe_stem(src), float(fs),
                                  data[:, i_f] * f_scale, resp, args,
                                  {"source_file": src.name, "source_format": "text",
                                   "units": used}))
    return finish_hits(staging, entries)
