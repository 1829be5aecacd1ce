"""Compare two ``results/`` trees by value: every CSV and netCDF artefact at a relative tolerance.

Run after a change to see which artefacts of the default study moved::

    .venv/bin/python benchmarks/compare_results.py OLD/results NEW/results --rtol 1e-9

CSV tables are compared column by column (numbers with ``numpy.isclose`` at ``rtol``, text
exactly); netCDF artefacts variable by variable (provenance attributes such as the git commit
and the input digests are left out, since they change with every commit). Chapters, logs,
benchmarks and figures are not artefacts and are skipped. Prints one line per file that differs
or exists on one side only, then a count; exits 1 when anything differs.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr

SKIP_PARTS = {"chapters", "logs", "benchmarks", "figures", "thesis"}


def _artefacts(root: Path) -> set[str]:
    out = set()
    for path in root.rglob("*"):
        if path.suffix not in (".csv", ".nc") or not path.is_file():
            continue
        rel = path.relative_to(root)
        if SKIP_PARTS.intersection(rel.parts[:-1]):
            continue
        out.add(str(rel))
    return out


def _close(a: np.ndarray, b: np.ndarray, rtol: float) -> bool:
    if a.shape != b.shape:
        return False
    if a.dtype.kind in "fciub" and b.dtype.kind in "fciub":
        return bool(np.allclose(a, b, rtol=rtol, atol=0.0, equal_nan=True))
    return bool(np.array_equal(a.astype(str), b.astype(str)))


def compare_csv(old: Path, new: Path, rtol: float) -> str | None:
    a, b = pd.read_csv(old), pd.read_csv(new)
    if list(a.columns) != list(b.columns):
        return f"columns {sorted(set(a.columns) ^ set(b.columns))} differ"
    if len(a) != len(b):
        return f"{len(a)} rows against {len(b)}"
    bad = [c for c in a.columns if not _close(a[c].to_numpy(), b[c].to_numpy(), rtol)]
    return f"columns {bad} differ" if bad else None


def compare_nc(old: Path, new: Path, rtol: float) -> str | None:
    with xr.open_dataset(old, engine="h5netcdf") as a, xr.open_dataset(new, engine="h5netcdf") as b:
        names_a = set(a.variables)
        names_b = set(b.variables)
        if names_a != names_b:
            return f"variables {sorted(names_a ^ names_b)} differ"
        bad = [n for n in sorted(names_a) if not _close(a[n].values, b[n].values, rtol)]
        return f"variables {bad} differ" if bad else None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("old", type=Path)
    parser.add_argument("new", type=Path)
    parser.add_argument("--rtol", type=float, default=1e-9)
    args = parser.parse_args(argv)
    old, new = _artefacts(args.old), _artefacts(args.new)
    n_diff = 0
    for rel in sorted(old | new):
        if rel not in new or rel not in old:
            print(f"{rel}: only in {'old' if rel in old else 'new'}")
            n_diff += 1
            continue
        compare = compare_csv if rel.endswith(".csv") else compare_nc
        try:
            why = compare(args.old / rel, args.new / rel, args.rtol)
        except Exception as exc:  # an unreadable artefact is a difference, named in one line
            why = f"cannot compare ({type(exc).__name__}: {exc})"
        if why:
            print(f"{rel}: {why}")
            n_diff += 1
    print(f"{n_diff} of {len(old | new)} artefacts differ at rtol {args.rtol:g}")
    return 1 if n_diff else 0


if __name__ == "__main__":
    sys.exit(main())
