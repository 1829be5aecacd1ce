"""Shared pieces of the importers: reading text exports, the axis/sign mapping, the rebuilt time
axis, and writing contract CSV files.

Every importer raises :class:`robomill.errors.RawDataError` naming the *source* file, where
in it the problem is and what was expected; nothing is written for a source that fails.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from robomill.errors import RawDataError

AXES = ("x", "y", "z")

_NUMBER = re.compile(r"^[+-]?(\d+([.,]\d*)?|[.,]\d+)([eE][+-]?\d+)?$")


def read_text(path: Path, what: str) -> str:
    """The text of an export (UTF-8, else Windows-1252 as Windows instruments write it).

    Raises
    ------
    RawDataError
        Missing, empty or binary file.
    """
    path = Path(path)
    if not path.is_file():
        raise RawDataError(path, "file does not exist", expected=what)
    raw = path.read_bytes()
    if not raw.strip():
        raise RawDataError(path, "file is empty", expected=what)
    if b"\x00" in raw[:4096]:
        raise RawDataError(path, "binary file, not a text export", where="file",
                           expected=what)
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        return raw.decode("cp1252", errors="replace")


def split_fields(line: str, sep: str | None) -> list[str]:
    """Split one line by ``sep`` (None: runs of whitespace), fields stripped."""
    parts = line.split() if sep is None else line.split(sep)
    return [p.strip().strip('"').strip() for p in parts]


def is_number(text: str) -> bool:
    """Whether ``text`` is a decimal number (dot or comma as decimal mark)."""
    return bool(_NUMBER.match(text.strip()))


def to_float(text: str, decimal_comma: bool) -> float:
    """Parse one number; ``decimal_comma`` reads ``1,5`` as 1.5."""
    t = text.strip()
    if decimal_comma:
        t = t.replace(",", ".")
    return float(t)


def row_floats(source: Path, f: Sequence[str], columns: Sequence[int], names: Sequence[str], *,
               lineno: int, ncol: int, last: bool, decimal_comma: bool, header: str,
               expected: str) -> list[float]:
    """The numbers of one data row at ``columns``: a RawDataError naming the line and the column
    for a short (truncated?) row or a field that is not a number. ``header`` names the row the
    field count comes from ("header", "channel row"); ``expected`` what a value should be."""
    if len(f) < ncol:
        raise RawDataError(source, f"row has {len(f)} fields, the {header} has {ncol}"
                           + (" (truncated last row?)" if last else ""),
                           where=f"line {lineno}", expected=f"{ncol} fields")
    out = []
    for c in columns:
        try:
            out.append(to_float(f[c], decimal_comma))
        except ValueError:
            raise RawDataError(source, f"value {f[c]!r} is not a number",
                               where=f"line {lineno}, column {names[c]}",
                               expected=expected) from None
    return out


def parse_axes(spec: str, source: Path, option: str = "--axes") -> list[tuple[int, float]]:
    """Parse an axis/sign mapping such as ``-x,-y,-z`` or ``y,-x,z``.

    Entry ``i`` says which instrument axis (and sign) gives contract axis ``i`` (X, Y, Z of
    the block frame R0): ``Fx_N = sign · reading[axis]``. Each axis must appear once.

    Returns
    -------
    list of (axis index, sign)
    """
    parts = [p.strip().lower() for p in spec.split(",")]
    out: list[tuple[int, float]] = []
    for p in parts:
        m = re.fullmatch(r"([+-]?)([xyz])", p)
        if not m:
            raise RawDataError(source, f"{option} entry {p!r} is not an axis",
                               where=f"option {option}",
                               expected="three of x, y, z, each with an optional sign, "
                                        "e.g. -x,-y,-z")
        out.append((AXES.index(m[2]), -1.0 if m[1] == "-" else 1.0))
    if len(out) != 3 or len({a for a, _ in out}) != 3:
        raise RawDataError(source, f"{option} {spec!r} does not name each axis once",
                           where=f"option {option}", expected="e.g. -x,-y,-z")
    return out


def map_axes(readings: np.ndarray, mapping: list[tuple[int, float]]) -> np.ndarray:
    """Apply :func:`parse_axes`'s mapping to ``readings`` (n, 3) → (n, 3)."""
    return np.column_stack([sign * readings[:, axis] for axis, sign in mapping])


def cut_id(args, source: Path, n_sources: int) -> str:
    """The cut id: the one ``--cut-pattern`` read from the source's name (``args.cut_ids``,
    filled by :mod:`robomill.cli.importing`), else ``--cut`` (one source only), else the
    source's file stem."""
    named = (getattr(args, "cut_ids", None) or {}).get(Path(source))
    if named:
        return named
    cut = getattr(args, "cut", None)
    if cut and n_sources > 1:
        raise RawDataError(source, f"--cut {cut} given for {n_sources} source files",
                           where="option --cut",
                           expected="one source per --cut, or no --cut (the file stems "
                                    "become the cut ids)")
    return cut or source.stem


def nice_rate(fs_hz: float) -> float:
    """A rate computed as 1/step, rounded to 9 significant digits (9999.999999999996 → 1e4)."""
    return float(f"{fs_hz:.9g}")


def time_axis(source: Path, t: np.ndarray | None, n: int, fs_hz: float | None, *,
              column: str) -> tuple[np.ndarray, float, float]:
    """Check or rebuild a time axis; return ``(t_s, fs_hz, jitter_s)``.

    * With time stamps ``t`` that fit ``t0 + k/fs`` within a quarter step
      (:func:`robomill.io.tables.fit_time_grid`), the grid is kept (its rate must agree with
      ``fs_hz`` to 0.1 % when that is given).
    * With coarse or repeated time stamps (resolution coarser than the sampling step, as
      tracker software prints them to the millisecond or the second) and a stated ``fs_hz``,
      the axis is rebuilt as ``t0 + k/fs_hz`` provided the stamps span the same duration to
      within their resolution plus one step and every inner stamp holds the samples its
      interval holds at ``fs_hz`` (±1.5; :func:`_check_stamp_counts`).
    * Without time stamps the axis is ``k/fs_hz``.

    Raises
    ------
    RawDataError
        No rate at all, stamps going backwards, a gap, stamps that disagree with ``fs_hz``,
        or a count per coarse stamp that is not the rate's.
    """
    from robomill.io.tables import fit_time_grid

    if t is None:
        if not fs_hz:
            raise RawDataError(source, "no time stamps and no sampling rate",
                               where=f"column {column}", expected="--fs-hz RATE")
        return np.arange(n) / fs_hz, float(fs_hz), 0.0
    t = np.asarray(t, dtype=float)
    d = np.diff(t)
    back = np.flatnonzero(d < 0)
    if back.size:
        raise RawDataError(source, f"time goes backwards ({float(t[back[0]]):g} then "
                           f"{float(t[back[0] + 1]):g})",
                           where=f"sample {back[0] + 1}, column {column}",
                           expected="non-decreasing time stamps")
    grid = fit_time_grid(t) if np.all(d > 0) else None
    if grid is not None:
        fs_data = nice_rate(1.0 / grid.step)
        if fs_hz and abs(fs_data - fs_hz) > 1e-3 * fs_hz:
            raise RawDataError(source, f"time stamps give {fs_data:.6g} Hz",
                               where=f"column {column}",
                               expected=f"--fs-hz {fs_hz:g} within 0.1 %, or no --fs-hz")
        return grid.t0 + np.arange(n) / fs_data, float(fs_data), grid.jitter
    if not fs_hz:
        pos = d[d > 0]
        res = float(pos.min()) if pos.size else 0.0
        span = float(t[-1] - t[0])
        hint = (f"; {n} samples over {span:.6g} s of stamps suggest about "
                f"{n / (span + res):.4g} Hz" if span + res > 0 else "")
        raise RawDataError(source, "time stamps are coarse or uneven "
                           f"(finest step {res:.3g} s) and no rate was stated" + hint,
                           where=f"column {column}",
                           expected="--fs-hz RATE to rebuild t0 + k/fs")
    pos = d[d > 0]
    res = float(pos.min()) if pos.size else 0.0
    step = 1.0 / fs_hz
    span = float(t[-1] - t[0])
    want = (n - 1) * step
    # consecutive stamps rounded to ``res`` differ by at most step + res; more is a gap
    if np.any(d > 1.5 * step + res):
        i = int(np.flatnonzero(d > 1.5 * step + res)[0])
        raise RawDataError(source, f"gap of {d[i]:.6g} s between two samples",
                           where=f"sample {i + 1}, column {column}",
                           expected=f"samples every {step:.6g} s (--fs-hz {fs_hz:g})")
    if abs(span - want) > res + step:
        raise RawDataError(source, f"time stamps span {span:.6g} s, {n} samples at "
                           f"{fs_hz:g} Hz span {want:.6g} s", where=f"column {column}",
                           expected=f"the stated --fs-hz (stamps resolved to {res:.3g} s)")
    _check_stamp_counts(source, t, fs_hz, column=column)
    return t[0] + step * np.arange(n), float(fs_hz), float(np.max(np.abs(
        t - (t[0] + step * np.arange(n)))))


def _check_stamp_counts(source: Path, t: np.ndarray, fs_hz: float, *, column: str) -> None:
    """With repeated (coarse) stamps, every stamp between the first and the last must hold
    the samples its interval holds at ``fs_hz`` (Δt·fs ± 1.5): a stream whose count per stamp
    drifts (a tracker triggered by distance, not time, or dropping points) has no uniform
    rate to rebuild."""
    values, start, counts = np.unique(t, return_index=True, return_counts=True)
    if values.size < 3 or counts.max() < 2:
        return
    expect = np.diff(values)[:-1] * fs_hz  # inner stamps: up to the next stamp
    got = counts[1:-1]
    bad = np.flatnonzero(np.abs(got - expect) > 1.5)
    if bad.size:
        i = int(bad[0]) + 1
        raise RawDataError(source, f"the stamp at {values[i] - values[0]:.6g} s holds "
                           f"{int(counts[i])} samples, {fs_hz:g} Hz gives {expect[i - 1]:.4g} "
                           f"({bad.size} of {got.size} inner stamps differ: not a uniform "
                           "stream, or samples dropped)",
                           where=f"sample {int(start[i])}, column {column}",
                           expected=f"about {expect[i - 1]:.4g} samples per stamp "
                                    f"(--fs-hz {fs_hz:g}); a time-triggered export")


def write_csv(path: Path, header: Sequence[str], columns: Sequence[np.ndarray],
              fmts: Sequence[str]) -> Path:
    """Write a contract CSV (one header row, comma-separated)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    data = np.column_stack([np.asarray(c, dtype=float) for c in columns])
    with open(path, "w", newline="\n") as fh:
        fh.write(",".join(header) + "\n")
        np.savetxt(fh, data, fmt=list(fmts), delimiter=",")
    return path


def valid_run(source: Path, ok: np.ndarray, *, where: str, bad: str, option: str,
              crop: bool, dropouts: str, empty_where: str | None = None) -> slice:
    """The points of a profile to keep, given its validity mask ``ok`` (profile importers).

    Invalid points at the ends are dropped (refused with ``crop`` false); invalid points
    inside are refused, or with ``dropouts == "longest"`` the longest run of valid points is
    kept. ``where`` names the profile in messages (``profile 1``, ``row 2``), ``bad`` what an
    invalid point is called (``'BAD'``, ``invalid``), ``option`` the option that picks another
    profile (``--profile``, ``--row``); ``empty_where`` the place named when fewer than two
    points are valid (default ``where``).
    """
    ok = np.asarray(ok, bool)
    idx = np.flatnonzero(ok)
    if idx.size < 2:
        raise RawDataError(source, f"{where} has {idx.size} valid points",
                           where=empty_where or where,
                           expected=f"a profile of valid points (choose another {option})")
    i0, i1 = int(idx[0]), int(idx[-1]) + 1
    n = ok.size
    if not crop and (i0 > 0 or i1 < n):
        ends = ([f"points 0…{i0 - 1}"] if i0 > 0 else []) + (
            [f"points {i1}…{n - 1}"] if i1 < n else [])
        raise RawDataError(source, f"{bad} points at the ends of the profile",
                           where=f"{where}, " + " and ".join(ends),
                           expected="valid points only (or drop --no-crop)")
    inner = np.flatnonzero(~ok[i0:i1])
    if inner.size and dropouts == "longest":
        edges = np.flatnonzero(np.diff(np.r_[0, ok.astype(np.int8), 0]))
        starts, stops = edges[::2], edges[1::2]
        j = int(np.argmax(stops - starts))
        return slice(int(starts[j]), int(stops[j]))
    if inner.size:
        raise RawDataError(source, f"{inner.size} {bad} point(s) inside the profile",
                           where=f"{where}, point {i0 + int(inner[0])}",
                           expected=f"a profile without dropouts (choose another {option}, or "
                                    "--dropouts longest)")
    return slice(i0, i1)
