"""Kistler DynoWare ASCII/CSV force exports → ``forces/<cut>.csv``.

A DynoWare export (Kistler Type 2825A, "Export ASCII") is a text file with

1. a metadata header of ``key<sep>value`` lines — among them the sampling rate
   (``Sampling rate``/``Sample rate``/``Abtastrate``, in Hz or kHz, the unit after the number
   or in brackets in the key: ``Sampling rate [Hz]:,10000``) and, often, the number of
   samples;
2. a channel row naming the columns (``Time``, ``Fx``, ``Fy``, ``Fz``, maybe ``Mz``…);
3. a units row (``s``, ``N``, ``N``, ``N``);
4. one row per sample, tab-, semicolon- or comma-separated, decimal point or decimal comma.

A real DynoWare 2.5 "File → Export → Channel" CSV (see ``tests/data/real/dynoware/SOURCE.md``)
has 18 ``Key:,value`` lines (``DynoWare,Version 2.5.1.2``, ``Path:``, ``Filename:``, …,
``Sampling rate [Hz]:,10000``, ``Measuring time [s]:,50``, ``Samples per channel:,500001``,
``Cycle No:,1``), then ``Time,Fx,Fy,Fz`` and ``s,N,N,N``, and the rows of the exported **time
window** (there 8 s to 9 s of the 50 s measurement), times printed with at most four decimals.
``Samples per channel`` is the length of the whole measurement: an export may hold fewer rows
when its time column starts after 0 (a window; its rows then start the contract's ``t_s = 0``),
or with ``--window``. When the Windows list separator and the decimal symbol are both a comma,
the rows are ambiguous and refused.

The dynamometer measures the force on the *plate* (the workpiece) in the plate's axes; the
contract wants the cutting force **on the tool** in the block frame R0 (Altintas 2012,
action = −reaction). ``--axes`` maps plate axes to R0 axes with signs: entry *i* gives R0 axis
*i*, so the default ``-x,-y,-z`` is "plate axes parallel to R0, reading sign inverted"; a
plate mounted turned by 90° about Z would be ``-y,x,-z``.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import numpy as np

from robomill.errors import RawDataError
from robomill.importers._common import (
    cut_id,
    is_number,
    map_axes,
    parse_axes,
    read_text,
    row_floats,
    split_fields,
    time_axis,
    write_csv,
)

FORMAT = "dynoware"
KIND = "force"
DESCRIPTION = "Kistler DynoWare ASCII/CSV force export"

WHAT = "a Kistler DynoWare ASCII export (header, channel row Fx Fy Fz, units row, samples)"

_RATE_KEY = re.compile(r"(sampl\w*\s*(rate|frequency)|abtast\w*|sample\s*rate|rate)", re.I)
_COUNT_KEY = re.compile(r"(number\s+of\s+samples|samples(\s+per\s+channel)?|anzahl\s+werte|"
                        r"messwerte)", re.I)
_KEY_UNIT = re.compile(r"^(.*?)\s*[\[\(]\s*([A-Za-z]+)\s*[\]\)]\s*$")
_TIME_NAMES = {"time", "t", "zeit", "time [s]"}
_UNIT_N = {"n": 1.0, "kn": 1e3}
_UNIT_S = {"s": 1.0, "ms": 1e-3}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """``--axes``, ``--channels``, ``--fs-hz``."""
    parser.add_argument("--axes", default="-x,-y,-z",
                        help="plate axis and sign giving each of the tool-force axes X,Y,Z of "
                             "the block frame (default -x,-y,-z: plate parallel to the block, "
                             "force on the tool = reading with its sign inverted)")
    parser.add_argument("--channels", default="Fx,Fy,Fz",
                        help="names of the plate's x,y,z force channels (default Fx,Fy,Fz)")
    parser.add_argument("--fs-hz", type=float, default=None,
                        help="sampling rate [Hz] when the header has none (checked against "
                             "the header and the time column otherwise)")
    parser.add_argument("--window", action="store_true",
                        help="the export is a time window of the measurement: do not compare "
                             "its rows with the header's number of samples (implied when the "
                             "time column starts after 0)")


def _name(field: str) -> tuple[str, str | None]:
    """``'Fx [N]'`` → ``('fx', 'n')``; ``'Fx'`` → ``('fx', None)``."""
    m = re.match(r"^\s*([^\[\(]+?)\s*(?:[\[\(]\s*([^\]\)]*)\s*[\]\)])?\s*$", field)
    if not m:
        return field.strip().lower(), None
    return m[1].strip().lower(), (m[2].strip().lower() if m[2] else None)


def _key_value(line: str) -> tuple[str, str]:
    """``'Sampling rate: 10000 Hz'`` (or tab/semicolon/= separated) → key, rest."""
    m = re.match(r"^\s*([^:\t;=]+?)\s*[:\t;=]\s*(.*)$", line)
    return (m[1], m[2]) if m else (line.strip(), "")


def _split_key_unit(key: str) -> tuple[str, str | None]:
    """``'Sampling rate [Hz]'`` → ``('Sampling rate', 'hz')``; no bracket → ``(key, None)``."""
    m = _KEY_UNIT.match(key)
    return (m[1], m[2].lower()) if m else (key, None)


def _rate_from_header(source: Path, lines: list[str]) -> float | None:
    for i, line in enumerate(lines, start=1):
        key, rest = _key_value(line)
        key, key_unit = _split_key_unit(key)
        rest = rest.strip().lstrip(",;\t").strip()
        if not rest or not _RATE_KEY.fullmatch(key):
            continue
        m = re.search(r"([0-9]+(?:[.,][0-9]+)?(?:[eE][+-]?[0-9]+)?)\s*(k?hz)?", rest, re.I)
        unit = ((m[2] if m else None) or key_unit or "hz").lower()
        if not m or unit not in ("hz", "khz"):
            raise RawDataError(source, f"sampling rate {rest!r}"
                               + (f" in {key_unit!r}" if key_unit else "") + " is not a rate",
                               where=f"header line {i}",
                               expected="e.g. 'Sampling rate: 10000 Hz' or "
                                        "'Sampling rate [Hz]:,10000'")
        value = float(m[1].replace(",", "."))
        return value * (1e3 if unit == "khz" else 1.0)
    return None


def _count_from_header(lines: list[str]) -> tuple[int, str] | None:
    """The announced number of samples and the header key that announces it."""
    for line in lines:
        key, rest = _key_value(line)
        rest = rest.strip().lstrip(",;\t").strip()
        if _COUNT_KEY.fullmatch(key.strip()) and re.fullmatch(r"\d+", rest):
            return int(rest), key.strip()
    return None


def read_dynoware(source: Path, *, channels: tuple[str, str, str] = ("Fx", "Fy", "Fz"),
                  fs_hz: float | None = None, window: bool = False
                  ) -> tuple[np.ndarray, np.ndarray, float, float]:
    """Read a DynoWare export: ``(t_s (n,), plate_force_N (n, 3), fs_hz, jitter_s)``.

    The forces are the plate's channels named ``channels`` (x, y, z), in N (``kN`` columns
    are converted), not yet mapped to the tool (see :func:`convert`). ``t_s`` starts at 0
    (an exported window's first row).

    Raises
    ------
    RawDataError
        Missing/empty/binary file; no channel row naming the three channels (the message
        lists the columns found); a unit other than N/kN (s/ms for time); no sampling rate
        (header or ``fs_hz``) nor time column; a rate that disagrees; text in a sample row; a
        short (truncated) row; a row with more fields than the channel row (a comma both as
        separator and as decimal mark); more samples than the header announces, or fewer
        when the time column starts at 0 and ``window`` is false (truncated export); fewer
        than 2 samples.
    """
    text = read_text(source, WHAT)
    lines = text.splitlines()
    want = [c.strip().lower() for c in channels]
    head_row = None
    sep = None
    for i, line in enumerate(lines[:400]):
        for s in ("\t", ";", ",", None):
            names = [_name(f)[0] for f in split_fields(line, s)]
            if all(w in names for w in want):
                head_row, sep = i, s
                break
        if head_row is not None:
            break
    if head_row is None:
        for i, line in enumerate(lines[:400]):
            for s in ("\t", ";", ",", None):
                fields = split_fields(line, s)
                names = [_name(f)[0] for f in fields]
                found = [c for c, w in zip(channels, want, strict=True) if w in names]
                if len(found) >= 2 or (found and any(n in _TIME_NAMES for n in names)):
                    missing = [c for c in channels if c not in found]
                    raise RawDataError(source, "channel " + ", ".join(missing) + " is missing"
                                       f" (the channel row has {', '.join(fields)})",
                                       where=f"channel row (line {i + 1})",
                                       expected="channels " + ", ".join(channels)
                                                + " (or name them with --channels)")
        first = next((ln for ln in lines if ln.strip()), "")
        raise RawDataError(source, "no channel row naming " + ", ".join(channels),
                           where="header (first 400 lines)",
                           expected=f"{WHAT}; first line is {first[:60]!r}; "
                                    "name the channels with --channels if they differ")
    fields = split_fields(lines[head_row], sep)
    parsed = [_name(f) for f in fields]
    names = [p[0] for p in parsed]
    units: list[str | None] = [p[1] for p in parsed]
    data_start = head_row + 1
    if data_start < len(lines):
        cand = split_fields(lines[data_start], sep)
        if cand and not all(is_number(c) for c in cand if c):
            units = [u.strip().lower() if u else None for u in cand] + [None] * len(fields)
            data_start += 1
    idx = [names.index(w) for w in want]
    t_idx = next((i for i, n in enumerate(names) if n in _TIME_NAMES), None)
    scale = []
    for name, i in zip(channels, idx, strict=True):
        u = (units[i] or "n").lower()
        if u not in _UNIT_N:
            raise RawDataError(source, f"channel {name} is in unit {units[i]!r}",
                               where=f"units row (line {data_start}), column {name}",
                               expected="N or kN")
        scale.append(_UNIT_N[u])
    t_scale = 1.0
    if t_idx is not None:
        u = (units[t_idx] or "s").lower()
        if u not in _UNIT_S:
            raise RawDataError(source, f"time column in unit {units[t_idx]!r}",
                               where=f"units row (line {data_start}), column {fields[t_idx]}",
                               expected="s or ms")
        t_scale = _UNIT_S[u]
    rows = list(lines[data_start:])
    while rows and not rows[-1].strip():
        rows.pop()
    decimal_comma = sep != "," and any("," in r for r in rows[:20])
    ncol = len(fields)
    values = np.empty((len(rows), ncol))
    for k, line in enumerate(rows):
        lineno = data_start + k + 1
        f = split_fields(line, sep)
        if len(f) > ncol and any(x for x in f[ncol:]):
            raise RawDataError(source, f"row has {len(f)} fields, the channel row has {ncol}"
                               + (": a comma as decimal mark in a comma-separated export is "
                                  "ambiguous" if sep == "," else ""),
                               where=f"line {lineno}",
                               expected=f"{ncol} fields (export again with the value delimiter "
                                        "tab or semicolon, or with a decimal point)")
        values[k] = row_floats(source, f, range(ncol), fields, lineno=lineno, ncol=ncol,
                               last=k == len(rows) - 1, decimal_comma=decimal_comma,
                               header="channel row", expected="a number")
    bad = ~np.isfinite(values)
    if bad.any():
        k, j = np.argwhere(bad)[0]
        raise RawDataError(source, "value is not finite",
                           where=f"line {data_start + k + 1}, column {fields[j]}",
                           expected="a finite number")
    n = len(rows)
    if n < 2:
        raise RawDataError(source, f"only {n} samples", where=f"line {data_start + 1}",
                           expected="at least 2 samples after the units row")
    counted = _count_from_header(lines[:head_row])
    starts_late = t_idx is not None and values[0, t_idx] * t_scale > 0
    if counted is not None:
        announced, count_key = counted
        if n > announced or (n < announced and not (window or starts_late)):
            raise RawDataError(source, f"{n} samples, the header announces {announced}"
                               + (" (truncated export?)" if n < announced else ""),
                               where=f"samples / header {count_key!r}",
                               expected=f"{announced} sample rows" + (
                                   " (or --window for an exported time window)"
                                   if n < announced else ""))
    rate = _rate_from_header(source, lines[:head_row])
    if rate is not None and fs_hz is not None and abs(rate - fs_hz) > 1e-3 * fs_hz:
        raise RawDataError(source, f"header sampling rate {rate:g} Hz", where="header",
                           expected=f"--fs-hz {fs_hz:g} as given")
    rate = fs_hz or rate
    t = values[:, t_idx] * t_scale if t_idx is not None else None
    t_s, rate, jitter = time_axis(source, t, n, rate,
                                  column=fields[t_idx] if t_idx is not None else "Time")
    force = values[:, idx] * np.asarray(scale)
    return t_s - t_s[0], force, rate, jitter


def convert(sources: list[Path], staging: Path, args: argparse.Namespace) -> list[dict]:
    """Write ``staging/forces/<cut>.csv`` per source (force on the tool, R0) and return the
    manifest entries ``{"path", "kind": "force", "cut", "fs_hz"}``."""
    entries = []
    for src in sources:
        src = Path(src)
        mapping = parse_axes(getattr(args, "axes", "-x,-y,-z"), src)
        chans = tuple(c.strip() for c in getattr(args, "channels", "Fx,Fy,Fz").split(","))
        if len(chans) != 3:
            raise RawDataError(src, f"--channels {','.join(chans)!r} names {len(chans)} channels",
                               where="option --channels", expected="three names, e.g. Fx,Fy,Fz")
        t, plate, fs, _jitter = read_dynoware(src, channels=chans,
                                              fs_hz=getattr(args, "fs_hz", None),
                                              window=getattr(args, "window", False))
        tool = map_axes(plate, mapping)
        cut = cut_id(args, src, len(sources))
        rel = f"forces/{cut}.csv"
        write_csv(staging / rel, ("t_s", "Fx_N", "Fy_N", "Fz_N"), (t, *tool.T),
                  ("%.9f", "%.6g", "%.6g", "%.6g"))
        entries.append({"path": rel, "kind": KIND, "cut": cut, "fs_hz": fs})
    return entries
