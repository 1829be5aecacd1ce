"""Reader for dynamometer records ``forces/<cut>.csv`` or ``forces/<cut>.h5``.

Contract (``docs/data-contract.md``, section Forces): columns / datasets ``t_s, Fx_N, Fy_N,
Fz_N`` — time [s] and the cutting force on the tool [N] in the block frame R0 (axes parallel
to the robot base). CSV has a header row; HDF5 holds four 1-D datasets of equal length at the
file root (forces may be float32). The sampling rate is given by the manifest (``fs_hz``); the
time column must be strictly increasing with step ``1/fs_hz``.

Records can be long (a 40 s cut at 25 kHz is 10⁶ samples per axis), so the HDF5 reader
streams: :meth:`ForceRecord.chunks` yields validated blocks and never loads the whole file.
Every problem raises :class:`~robomill.io.RawDataError` naming the file, the field (and row)
and what was expected.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from robomill.errors import RawDataError
from robomill.settings import schema_default

COLUMNS = ("t_s", "Fx_N", "Fy_N", "Fz_N")
"""Required columns (CSV) or datasets (HDF5), in this order."""

RTOL = 1e-3
"""Relative tolerance on the time step versus ``1/fs_hz``."""


@dataclass
class ForceRecord:
    """An opened, structurally checked dynamometer record; data are checked as they stream."""

    path: Path
    fs_hz: float
    n_samples: int
    _csv: np.ndarray | None = None  # CSV files are small: kept as read
    time_jitter_s: float = 0.0
    """Largest distance of a CSV time stamp from the grid ``t0 + k/fs_hz`` when ``t_s`` was
    printed with limited precision (0 when every step is exact to :data:`RTOL`)."""

    def chunks(self,
               chunk_samples: int = schema_default("forces", "chunk_samples")
               ) -> Iterator[tuple[np.ndarray, np.ndarray]]:
        """Yield ``(t_s (n,), force_N (n, 3))`` blocks in order, each validated: finite values,
        strictly increasing time with step ``1/fs_hz`` (across block boundaries too)."""
        step = 1.0 / self.fs_hz
        prev_t: float | None = None
        if self._csv is not None:
            blocks = ((i, self._csv[i:i + chunk_samples])
                      for i in range(0, self.n_samples, chunk_samples))
            for i0, block in blocks:
                prev_t = _check_block(self.path, i0, block, step, prev_t, csv=True,
                                      check_step=self.time_jitter_s == 0.0)
                yield block[:, 0], block[:, 1:]
            return
        import h5py

        try:
            with h5py.File(self.path, "r") as f:
                for i0 in range(0, self.n_samples, chunk_samples):
                    i1 = min(i0 + chunk_samples, self.n_samples)
                    cols = []
                    for name in COLUMNS:
                        try:
                            cols.append(np.asarray(f[name][i0:i1], dtype=float))
                        except (OSError, RuntimeError) as exc:
                            raise RawDataError(self.path, f"cannot read samples {i0}–{i1 - 1} "
                                               f"({exc}); the file is truncated or corrupt",
                                               where=f"dataset {name}",
                                               expected="a complete HDF5 file") from None
                    block = np.column_stack(cols)
                    prev_t = _check_block(self.path, i0, block, step, prev_t, csv=False)
                    yield block[:, 0], block[:, 1:]
        except OSError as exc:
            raise RawDataError(self.path, f"HDF5 read failed ({exc})",
                               where="file", expected="a complete HDF5 file") from None


def _check_block(path: Path, i0: int, block: np.ndarray, step: float, prev_t: float | None,
                 *, csv: bool, check_step: bool = True) -> float:
    """Validate one block (rows ``i0…``) and return its last time.

    ``check_step=False`` (a CSV whose whole ``t_s`` already fits the grid ``t0 + k/fs``
    within a quarter step, :func:`robomill.io.tables.fit_time_grid`) skips the per-step
    tolerance; finiteness and strict increase are still checked."""
    def where(i: int, col: str) -> str:
        return f"row {i0 + i + 2}, column {col}" if csv else f"dataset {col}, sample {i0 + i}"

    bad = ~np.isfinite(block)
    if bad.any():
        i, j = np.argwhere(bad)[0]
        raise RawDataError(path, f"value {float(block[i, j])!r} is not finite",
                           where=where(i, COLUMNS[j]), expected="finite numbers")
    t = block[:, 0]
    if prev_t is not None:
        t = np.concatenate([[prev_t], t])
        off = -1
    else:
        off = 0
    d = np.diff(t)
    nonmono = np.flatnonzero(d <= 0)
    if nonmono.size:
        k = int(nonmono[0])
        raise RawDataError(path, "t_s is not strictly increasing "
                           f"({float(t[k])!r} then {float(t[k + 1])!r})",
                           where=where(k + 1 + off, "t_s"), expected="strictly increasing time")
    if not check_step:
        return float(block[-1, 0])
    if prev_t is None and d.size:
        med = float(np.median(d))
        if abs(med - step) > RTOL * step:
            raise RawDataError(path, f"sampling rate is {1 / med:.6g} Hz (time step {med:.6g} s)",
                               where="column t_s" if csv else "dataset t_s",
                               expected=f"fs_hz = {1 / step:.6g} Hz as the manifest says "
                                        f"(step {step:.6g} s within {RTOL:g})")
    off_step = np.flatnonzero(np.abs(d - step) > RTOL * step)
    if off_step.size:
        k = int(off_step[0])
        raise RawDataError(path, f"t_s step is {d[k]:.6g} s instead of {step:.6g} s "
                           "(missing or repeated samples?)", where=where(k + 1 + off, "t_s"),
                           expected=f"uniform sampling at {1 / step:.6g} Hz")
    return float(block[-1, 0])


def _csv_time_jitter(path: Path, t: np.ndarray, step: float) -> float:
    """0 when every CSV time step is ``step`` within :data:`RTOL`; otherwise, if ``t`` was
    printed with limited precision but every sample fits ``t0 + k·step'`` (``step'`` within
    RTOL of ``step``) within a quarter step, that largest distance (logged); a fitted
    ``step'`` that disagrees with the manifest raises; otherwise 0, and
    :meth:`ForceRecord.chunks` reports the offending row."""
    import logging

    from robomill.io.tables import fit_time_grid

    d = np.diff(t)
    if d.size == 0 or (np.all(np.abs(d - step) <= RTOL * step)):
        return 0.0
    if np.any(d <= 0):
        return 0.0
    grid = fit_time_grid(t)
    if grid is None:
        return 0.0
    if abs(grid.step - step) > RTOL * step:
        raise RawDataError(path, f"sampling rate is {1 / grid.step:.6g} Hz (time step "
                           f"{grid.step:.6g} s, fitted to t_s printed with limited precision)",
                           where="column t_s",
                           expected=f"fs_hz = {1 / step:.6g} Hz as the manifest says "
                                    f"(step {step:.6g} s within {RTOL:g})")
    logging.getLogger("robomill.io").info(
        "%s: t_s printed with limited precision: every sample fits t0 + k/%.6g Hz within "
        "%.3g s (%.3g of a step)", path, 1.0 / grid.step, grid.jitter, grid.jitter / grid.step)
    return max(grid.jitter, np.finfo(float).tiny)


def open_force_record(path: str | Path, fs_hz: float) -> ForceRecord:
    """Open a dynamometer record (``.csv`` or ``.h5``) sampled at ``fs_hz`` (manifest).

    Checks the structure at once (columns/datasets present, 1-D, equal lengths, at least two
    samples; an HDF5 ``fs_hz`` attribute, if present, must agree with the manifest); the data
    themselves are checked while :meth:`ForceRecord.chunks` streams them.

    Raises
    ------
    RawDataError
        Missing/unreadable/truncated file, missing field, unequal lengths, a sampling rate that
        differs from the manifest, non-monotonic time, non-finite values.
    """
    path = Path(path)
    if not path.exists():
        raise RawDataError(path, "file does not exist")
    if fs_hz <= 0:
        raise RawDataError(path, f"manifest fs_hz is {fs_hz!r}", expected="a positive rate")
    if path.suffix.lower() == ".csv":
        from robomill.io.tables import read_numeric_csv

        df = read_numeric_csv(path, COLUMNS, min_rows=2)
        data = df[list(COLUMNS)].to_numpy(float)
        return ForceRecord(path, float(fs_hz), len(df), data,
                           time_jitter_s=_csv_time_jitter(path, data[:, 0], 1.0 / fs_hz))
    if path.suffix.lower() not in (".h5", ".hdf5"):
        from robomill.io.tables import native_format_hint

        native = native_format_hint(path)
        raise RawDataError(path, f"unknown file type {path.suffix!r}"
                           + (f"; {native}" if native else ""),
                           expected="forces/<cut>.csv or forces/<cut>.h5")
    import h5py

    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        from robomill.io.tables import native_format_hint

        size = path.stat().st_size
        native = native_format_hint(path)
        raise RawDataError(path, f"not a readable HDF5 file ({exc}; {size} bytes on disk)"
                           + (f"; {native}" if native else ""),
                           where="file structure (superblock; fields t_s, Fx_N, Fy_N, Fz_N "
                                 "unreachable)",
                           expected="a complete HDF5 file (truncated copy?)") from None
    with f:
        lengths = {}
        for name in COLUMNS:
            if name not in f:
                raise RawDataError(path, f"dataset '{name}' is missing", where="file root",
                                   expected="datasets " + ", ".join(COLUMNS))
            ds = f[name]
            if not isinstance(ds, h5py.Dataset) or ds.ndim != 1:
                raise RawDataError(path, f"'{name}' is not a 1-D dataset",
                                   where=f"dataset {name}", expected="a 1-D numeric dataset")
            if ds.dtype.kind not in "fiu":
                raise RawDataError(path, f"'{name}' has dtype {ds.dtype}",
                                   where=f"dataset {name}", expected="numbers")
            lengths[name] = ds.shape[0]
        n = lengths["t_s"]
        for name, m in lengths.items():
            if m != n:
                raise RawDataError(path, f"dataset {name} has {m} samples, t_s has {n} "
                                   "(truncated record?)", where=f"dataset {name}",
                                   expected="equal lengths for " + ", ".join(COLUMNS))
        if n < 2:
            raise RawDataError(path, f"only {n} samples", where="dataset t_s",
                               expected="at least 2 samples")
        attr = f.attrs.get("fs_hz")
        if attr is not None and abs(float(attr) - fs_hz) > RTOL * fs_hz:
            raise RawDataError(path, f"file attribute fs_hz = {float(attr):g} Hz",
                               where="attribute fs_hz",
                               expected=f"fs_hz = {fs_hz:g} Hz as the manifest says")
    return ForceRecord(path, float(fs_hz), int(n))


def read_forces(path: str | Path, fs_hz: float) -> tuple[np.ndarray, np.ndarray]:
    """Whole record ``(t_s (n,), force_N (n, 3))`` (small files and tests only)."""
    rec = open_force_record(path, fs_hz)
    parts = list(rec.chunks())
    return (np.concatenate([p[0] for p in parts]),
            np.concatenate([p[1] for p in parts], axis=0))


def write_forces_h5(path: str | Path, n_samples: int, fs_hz: float, blocks, *,
                    dtype: str = schema_default("synth.dynamometer", "dtype")) -> Path:
    """Write a record in the contract's HDF5 layout from an iterator of ``(t_s, force_N)``
    blocks, never holding more than one block (used by the simulator)."""
    import h5py

    path = Path(path)
    with h5py.File(path, "w") as f:
        f.attrs["fs_hz"] = float(fs_hz)
        chunk = min(65536, int(n_samples))
        t_ds = f.create_dataset("t_s", (n_samples,), dtype="float64", chunks=(chunk,))
        t_ds.attrs["units"] = "s"
        fds = []
        for name in COLUMNS[1:]:
            d = f.create_dataset(name, (n_samples,), dtype=dtype, chunks=(chunk,))
            d.attrs["units"] = "N"
            fds.append(d)
        i = 0
        for t, F in blocks:
            n = len(t)
            t_ds[i:i + n] = t
            for k, d in enumerate(fds):
                d[i:i + n] = F[:, k]
            i += n
        if i != n_samples:
            raise ValueError(f"wrote {i} samples, expected {n_samples}")
    return path


def write_forces_csv(path: str | Path, blocks) -> Path:
    """Write a record as CSV (header ``t_s,Fx_N,Fy_N,Fz_N``) block by block."""
    path = Path(path)
    with open(path, "w") as fh:
        fh.write(",".join(COLUMNS) + "\n")
        for t, F in blocks:
            np.savetxt(fh, np.column_stack([t, F]), fmt=["%.9f", "%.6g", "%.6g", "%.6g"],
                       delimiter=",")
    return path
