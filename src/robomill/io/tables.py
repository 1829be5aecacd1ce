"""Validated reading of the contract's CSV files.

Every instrument reader (profiles, forces, tracker, impact, C-Track, load tests) goes through
:func:`read_numeric_csv` and the checks below, so that every malformed file gets the same kind
of message: file, row/column, what was found, what was expected.
"""

from __future__ import annotations

import csv
import io
import logging
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from robomill.errors import RawDataError

_log = logging.getLogger("robomill.io")

_UNIT_SUFFIX = re.compile(r"^(?P<stem>.+?)_(?P<unit>[A-Za-z0-9]+)$")


def _column_hint(expected: str, found: Sequence[str]) -> str | None:
    """Explain a missing column: same quantity in another unit, or a likely misspelling."""
    m = _UNIT_SUFFIX.match(expected)
    if m:
        for col in found:
            mc = _UNIT_SUFFIX.match(col)
            if mc and mc["stem"] == m["stem"] and mc["unit"] != m["unit"]:
                return (f"column '{col}' is in unit '{mc['unit']}', the contract requires "
                        f"'{expected}' (unit '{m['unit']}'): convert the values and rename it")
    if len(found) == 1:
        for sep, name in ((";", "semicolons"), ("\t", "tabs"), ("|", "bars")):
            if sep in found[0] and expected in [c.strip() for c in found[0].split(sep)]:
                return (f"the header is separated by {name}; the contract requires commas "
                        "(export as CSV with ',' as separator and '.' as decimal mark)")
    import difflib

    close = difflib.get_close_matches(expected, list(found), n=1, cutoff=0.7)
    if close:
        return f"found '{close[0]}': is it a misspelling of '{expected}'?"
    return None


def native_format_hint(path: str | Path) -> str | None:
    """If ``path`` is a native instrument export (DynoWare, TDMS, X3P, …), the sentence naming
    it and its import command (:func:`robomill.importers.sniff.hint`); None otherwise."""
    try:
        from robomill.importers.sniff import hint
    except ImportError:  # pragma: no cover - the importers are part of the package
        return None
    return hint(path)


def read_numeric_csv(
    path: str | Path,
    columns: Sequence[str],
    *,
    min_rows: int = 1,
    optional: Sequence[str] = (),
    allow_extra: bool = True,
    text_columns: Sequence[str] = (),
) -> pd.DataFrame:
    """Read a CSV with a header row whose ``columns`` must all be present and numeric.

    Parameters
    ----------
    path
        The file.
    columns
        Required numeric columns, named with their unit (``x_mm``, ``z_um``).
    min_rows
        Fewest data rows accepted.
    optional
        Numeric columns read when present.
    allow_extra
        Accept further columns (they are kept as read).
    text_columns
        Required non-numeric columns (e.g. ``pose``, ``role``).

    Raises
    ------
    RawDataError
        On a missing, empty or header-only file, a missing column (with a unit or spelling
        hint), text in a numeric field, NaN/inf, a short (truncated) row, or too few rows.
    """
    path = Path(path)
    if not path.exists():
        raise RawDataError(path, "file does not exist")
    raw = path.read_bytes()
    if not raw.strip():
        raise RawDataError(path, "file is empty", expected="a header row and data rows")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        native = native_format_hint(path)
        raise RawDataError(path, f"not UTF-8 text ({exc.reason} at byte {exc.start})"
                           + (f"; {native}" if native else ""),
                           expected="a UTF-8 CSV file") from None
    lines = text.splitlines()
    header = next(csv.reader([lines[0]]))
    header = [h.strip() for h in header]
    required = list(columns) + list(text_columns)
    for col in required:
        if col not in header:
            native = native_format_hint(path)
            if native:
                raise RawDataError(path, f"column '{col}' is missing; {native}",
                                   where="header (row 1)",
                                   expected="columns " + ", ".join(required))
            hint = _column_hint(col, header)
            raise RawDataError(
                path,
                f"column '{col}' is missing" + (f"; {hint}" if hint else ""),
                where="header (row 1)",
                expected="columns " + ", ".join(required),
            )
    if not allow_extra:
        extra = [h for h in header if h not in required and h not in optional]
        if extra:
            raise RawDataError(path, f"unexpected column(s) {', '.join(extra)}",
                               where="header (row 1)", expected="columns " + ", ".join(required))
    if len(lines) - 1 < min_rows:
        raise RawDataError(
            path,
            "header only, no data rows" if len(lines) == 1 else f"only {len(lines) - 1} data rows",
            expected=f"at least {min_rows} data rows",
        )
    ncol = len(header)
    # a truncated last row (interrupted export) has fewer fields than the header
    for i, line in enumerate(lines[1:], start=2):
        if not line.strip():
            continue
        n = line.count(",") + 1
        if n != ncol:
            raise RawDataError(path, f"row has {n} fields, the header has {ncol}"
                               + (" (truncated last row?)" if i == len(lines) else ""),
                               where=f"row {i}", expected=f"{ncol} comma-separated fields")
    df = pd.read_csv(io.StringIO(text), skipinitialspace=True, dtype=str, keep_default_na=False)
    df.columns = [c.strip() for c in df.columns]
    numeric = list(columns) + [c for c in optional if c in df.columns]
    for col in numeric:
        values = pd.to_numeric(df[col].str.strip(), errors="coerce")
        bad = values.isna().to_numpy()
        if bad.any():
            i = int(np.argmax(bad))
            raise RawDataError(path, f"value {df[col].iloc[i]!r} is not a number",
                               where=f"row {i + 2}, column {col}", expected="a finite number")
        arr = values.to_numpy(dtype=float)
        nonfinite = ~np.isfinite(arr)
        if nonfinite.any():
            i = int(np.argmax(nonfinite))
            raise RawDataError(path, f"value {df[col].iloc[i]!r} is not finite",
                               where=f"row {i + 2}, column {col}", expected="a finite number")
        df[col] = arr
    for col in text_columns:
        empty = (df[col].str.strip() == "").to_numpy()
        if empty.any():
            i = int(np.argmax(empty))
            raise RawDataError(path, "empty value", where=f"row {i + 2}, column {col}",
                               expected="a non-empty text value")
        df[col] = df[col].str.strip()
    if len(df) < min_rows:
        raise RawDataError(path, f"only {len(df)} data rows", expected=f"at least {min_rows}")
    return df


def check_increasing(path: str | Path, values: np.ndarray, column: str) -> None:
    """Raise unless ``values`` strictly increase (time or position axis)."""
    d = np.diff(values)
    bad = np.flatnonzero(d <= 0)
    if bad.size:
        i = int(bad[0]) + 1
        raise RawDataError(path, f"{column} is not strictly increasing "
                           f"({float(values[i - 1])!r} then {float(values[i])!r})",
                           where=f"row {i + 2}, column {column}",
                           expected=f"strictly increasing {column}")


@dataclass(frozen=True)
class TimeGrid:
    """A sampled axis fitted to the grid ``t0 + k·step`` (see :func:`fit_time_grid`)."""

    t0: float
    step: float
    jitter: float
    """Largest distance of a sample from its grid point (axis units)."""


def fit_time_grid(values: np.ndarray) -> TimeGrid | None:
    """Fit an axis printed with limited precision to the uniform grid ``t0 + k·step``.

    Each difference is rounded to a whole number of median steps; the axis is on a grid only
    if every difference is exactly one step (no gap, no repeated sample). The grid is then
    the least-squares line ``t_k = t0 + k·step`` (k = 0…n−1), and it is accepted when every
    sample lies within a quarter step of it — the tolerance that still assigns every sample
    its one index unambiguously (a sample off by half a step could belong to either); every
    single step must also be within a quarter step of the fitted one (a jump of 1.4 steps
    followed by exact steps is a shifted record, not rounding).

    Returns
    -------
    TimeGrid or None
        The fitted grid, or None when a gap, a repeat or an excursion beyond a quarter step
        rules out a uniform grid.
    """
    v = np.asarray(values, dtype=float)
    if v.size < 3:
        return None
    d = np.diff(v)
    med = float(np.median(d))
    if not med > 0:
        return None
    m = np.rint(d / med)
    if np.any(m != 1):
        return None
    k = np.arange(v.size, dtype=float)
    step, t0 = np.polyfit(k, v, 1)
    res = v - (t0 + step * k)
    jitter = float(np.max(np.abs(res)))
    if not step > 0 or jitter > 0.25 * step or np.any(np.abs(d - step) > 0.25 * step):
        return None
    return TimeGrid(float(t0), float(step), jitter)


def check_uniform(path: str | Path, values: np.ndarray, column: str, *,
                  step: float | None = None, rtol: float = 1e-3) -> float:
    """Raise unless ``values`` are uniformly spaced (to ``rtol`` of the step); return the step.

    If ``step`` is given (e.g. ``1/fs`` from the manifest) the spacing must equal it.
    An axis printed with limited precision (e.g. 7 significant digits, so that single steps
    read 0.000488 or 0.000489 s at 2048 Hz) is accepted when every sample fits
    ``t0 + k·step`` within a quarter step (:func:`fit_time_grid`); the jitter is logged
    (logger ``robomill.io``) and the step returned. Gaps and repeated samples are still
    refused, at the row where they occur.
    """
    check_increasing(path, values, column)
    d = np.diff(values)
    actual = float(np.median(d))
    ref = step if step is not None else actual
    rate_ok = step is None or abs(actual - step) <= rtol * abs(step)
    off = np.flatnonzero(np.abs(d - ref) > rtol * abs(ref))
    if rate_ok and not off.size:
        return ref
    grid = fit_time_grid(values)
    if grid is not None and (step is None or abs(grid.step - step) <= rtol * abs(step)):
        _log.info("%s: %s printed with limited precision: every sample fits t0 + k*%.9g "
                  "within %.3g (%.3g of a step)", path, column, grid.step, grid.jitter,
                  grid.jitter / grid.step)
        return step if step is not None else grid.step
    gaps = np.flatnonzero(np.rint(d / ref) != 1)
    if grid is None and gaps.size:
        off = gaps
    elif not rate_ok:
        raise RawDataError(path, f"{column} spacing is {actual:.6g}",
                           where=f"column {column}",
                           expected=f"spacing {step:.6g} (from the manifest), within {rtol:g}")
    i = int(off[0]) + 1
    raise RawDataError(path, f"{column} is not uniformly spaced: step {d[i - 1]:.6g} "
                       f"instead of {ref:.6g}", where=f"row {i + 2}, column {column}",
                       expected=f"uniform spacing within {rtol:g} relative, or every "
                                f"sample within a quarter step of t0 + k·step "
                                f"(no gap, no repeat)")
