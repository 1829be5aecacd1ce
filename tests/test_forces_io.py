"""Dynamometer reader: streaming, and clear errors for bad records."""

import h5py
import numpy as np
import pytest

from robomill.io import RawDataError
from robomill.io.forces import (
    open_force_record,
    read_forces,
    write_forces_csv,
    write_forces_h5,
)

FS = 25000.0


def _blocks(n=5000, fs=FS, block=1000):
    t = np.arange(n) / fs
    F = np.column_stack([np.sin(t), np.cos(t), t])
    for i in range(0, n, block):
        yield t[i:i + block], F[i:i + block]


def test_h5_and_csv_round_trip_in_chunks(tmp_path):
    h5 = write_forces_h5(tmp_path / "a.h5", 5000, FS, _blocks(), dtype="float64")
    csv = write_forces_csv(tmp_path / "a.csv", _blocks())
    for p in (h5, csv):
        rec = open_force_record(p, FS)
        assert rec.n_samples == 5000
        parts = list(rec.chunks(777))
        assert len(parts) == 7
        t, F = read_forces(p, FS)
        np.testing.assert_allclose(F[:, 2], t, rtol=1e-6)


def test_non_monotonic_time_is_named(tmp_path):
    p = write_forces_h5(tmp_path / "bad.h5", 5000, FS, _blocks(), dtype="float64")
    with h5py.File(p, "r+") as f:
        f["t_s"][3000] = f["t_s"][2990]
    rec = open_force_record(p, FS)
    with pytest.raises(RawDataError, match=r"bad\.h5.*dataset t_s, sample 3000.*not strictly "
                                           r"increasing"):
        list(rec.chunks(1024))
    csv = tmp_path / "bad.csv"
    write_forces_csv(csv, _blocks())
    lines = csv.read_text().splitlines()
    lines[10], lines[11] = lines[11], lines[10]
    csv.write_text("\n".join(lines) + "\n")
    with pytest.raises(RawDataError, match=r"bad\.csv.*row 12, column t_s"):
        read_forces(csv, FS)


def test_sampling_rate_differing_from_manifest(tmp_path):
    p = write_forces_h5(tmp_path / "slow.h5", 2000, 20000.0, _blocks(2000, fs=20000.0))
    with pytest.raises(RawDataError, match=r"slow\.h5.*attribute fs_hz.*25000"):
        open_force_record(p, FS)
    with h5py.File(p, "r+") as f:
        del f.attrs["fs_hz"]
    with pytest.raises(RawDataError, match=r"dataset t_s.*sampling rate is 20000 Hz.*25000"):
        list(open_force_record(p, FS).chunks())


def test_truncated_hdf5(tmp_path):
    p = write_forces_h5(tmp_path / "cut.h5", 50_000, FS, _blocks(50_000))
    data = p.read_bytes()
    p.write_bytes(data[: len(data) // 2])
    with pytest.raises(RawDataError, match=r"cut\.h5.*fields t_s, Fx_N, Fy_N, Fz_N.*"
                                           r"not a readable HDF5"):
        open_force_record(p, FS)


def test_truncated_field_and_missing_field(tmp_path):
    p = write_forces_h5(tmp_path / "short.h5", 5000, FS, _blocks())
    with h5py.File(p, "r+") as f:
        d = f["Fy_N"][:4000]
        del f["Fy_N"]
        f["Fy_N"] = d
    with pytest.raises(RawDataError, match=r"short\.h5: dataset Fy_N: .*4000 samples"):
        open_force_record(p, FS)
    with h5py.File(p, "r+") as f:
        del f["Fy_N"]
    with pytest.raises(RawDataError, match=r"dataset 'Fy_N' is missing"):
        open_force_record(p, FS)


def test_non_finite_force(tmp_path):
    p = write_forces_h5(tmp_path / "nan.h5", 5000, FS, _blocks())
    with h5py.File(p, "r+") as f:
        f["Fz_N"][4321] = np.nan
    with pytest.raises(RawDataError, match=r"dataset Fz_N, sample 4321"):
        list(open_force_record(p, FS).chunks(1000))
