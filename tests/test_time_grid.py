"""Time axes printed with limited precision (item 4).

A CSV whose ``t_s`` is printed with 7 significant digits has single steps of 0.000488 and
0.000489 s at 2048 Hz; it is accepted when every sample fits ``t0 + k/fs`` within a quarter
step (the jitter is logged and, for forces, returned), while a gap or a repeated sample is
still refused — in the shared readers ``io.tables``, ``io.forces`` and ``io.tracker``.
"""

from __future__ import annotations

import logging

import numpy as np
import pytest

from robomill.io import RawDataError
from robomill.io.forces import open_force_record, read_forces
from robomill.io.profiles import read_profile
from robomill.io.tables import check_uniform, fit_time_grid
from robomill.io.tracker import read_tracker

FS = 2048.0


def seven_digits(values):
    return [f"{v:.7g}" for v in values]


def forces_csv(path, t_text):
    n = len(t_text)
    f = np.sin(np.arange(n) * 0.1)
    path.write_text("t_s,Fx_N,Fy_N,Fz_N\n" + "".join(
        f"{t},{f[k]:.6g},0,1\n" for k, t in enumerate(t_text)))
    return path


def test_fit_time_grid_recovers_planted_grid():
    t = 0.0123 + np.arange(5000) / FS
    grid = fit_time_grid(np.array([float(s) for s in seven_digits(t)]))
    assert grid is not None
    assert 1 / grid.step == pytest.approx(FS, rel=1e-7)
    assert grid.t0 == pytest.approx(0.0123, abs=1e-6)
    assert 0 < grid.jitter < 6e-7  # half a unit of the 7th digit (5e-7 s at t < 10 s) + fit


def test_fit_time_grid_refuses_gap_repeat_and_drift():
    t = np.arange(1000) / FS
    assert fit_time_grid(np.delete(t, 500)) is None  # gap: one difference is two steps
    assert fit_time_grid(np.insert(t, 500, t[500])) is None  # repeat: a zero step
    wobble = t + 0.3 / FS * np.sin(np.arange(1000) / 50.0)  # 0.3 step off the grid
    assert fit_time_grid(wobble) is None


def test_forces_csv_with_seven_significant_digits(tmp_path, caplog):
    t = np.arange(4096) / FS
    text = seven_digits(t)
    tq = np.array([float(v) for v in text])
    assert set(np.round(np.diff(tq[2500:2600]), 6)) == {0.000488, 0.000489}  # past t = 1 s
    assert np.any(np.abs(np.diff(tq) - 1 / FS) > 1e-3 / FS)  # the strict check refuses it
    path = forces_csv(tmp_path / "f.csv", text)
    with caplog.at_level(logging.INFO, logger="robomill.io"):
        rec = open_force_record(path, FS)
        tt, F = read_forces(path, FS)
    assert 0 < rec.time_jitter_s < 0.25 / FS
    assert tt.size == 4096 and F.shape == (4096, 3)
    assert "printed with limited precision" in caplog.text
    # the manifest's rate must still agree
    with pytest.raises(RawDataError, match=r"sampling rate is 2048 Hz"):
        read_forces(path, 2000.0)


def test_forces_csv_exact_time_has_no_jitter(tmp_path):
    path = forces_csv(tmp_path / "exact.csv", [f"{v:.9f}" for v in np.arange(100) / 1000.0])
    assert open_force_record(path, 1000.0).time_jitter_s == 0.0


def test_forces_csv_gap_and_repeat_still_refused(tmp_path):
    text = seven_digits(np.arange(4096) / FS)
    gap = forces_csv(tmp_path / "gap.csv", text[:2000] + text[2001:])
    with pytest.raises(RawDataError, match=r"row 2002, column t_s: t_s step is 0.00097\d* s "
                                           r"instead of 0.000488281 s \(missing or repeated"):
        read_forces(gap, FS)
    rep = forces_csv(tmp_path / "rep.csv", text[:2000] + [text[1999]] + text[2000:])
    with pytest.raises(RawDataError, match=r"row 2002, column t_s: t_s is not strictly "
                                           r"increasing"):
        read_forces(rep, FS)


def tracker_csv(path, t_text):
    path.write_text("t_s,x_mm,y_mm,z_mm\n" + "".join(
        f"{t},{k * 0.0025:.6f},0,0\n" for k, t in enumerate(t_text)))
    return path


def test_tracker_seven_digits_gap_repeat(tmp_path):
    fs = 815.0
    text = seven_digits(10.0 + np.arange(1000) / fs)  # stamps near 10 s: 1e-6 resolution
    t, _ = read_tracker(tracker_csv(tmp_path / "ok.csv", text), fs_hz=fs)
    assert t.size == 1000
    with pytest.raises(RawDataError, match=r"row 502, column t_s: t_s is not uniformly "
                                           r"spaced: step 0.0024\d* instead of 0.00122\d*"):
        read_tracker(tracker_csv(tmp_path / "gap.csv", text[:500] + text[501:]), fs_hz=fs)
    with pytest.raises(RawDataError, match=r"row 502, column t_s: t_s is not strictly"):
        read_tracker(tracker_csv(tmp_path / "rep.csv", text[:500] + [text[499]] + text[500:]),
                     fs_hz=fs)


def test_profile_x_printed_with_few_digits(tmp_path):
    x = np.arange(300) / 800.0  # 1.25 µm spacing, printed with 4 significant digits
    path = tmp_path / "p.csv"
    path.write_text("x_mm,z_um\n" + "".join(f"{v:.4g},{np.sin(k / 9):.4f}\n"
                                            for k, v in enumerate(x)))
    xr, _, fs = read_profile(path)
    assert fs == pytest.approx(800.0, rel=1e-4)


def test_check_uniform_strict_path_unchanged():
    # exactly uniform: the manifest step is returned as before, no fit involved
    t = np.arange(10) / 815.0
    assert check_uniform("f.csv", t, "t_s", step=1 / 815.0) == 1 / 815.0
    assert check_uniform("f.csv", t, "t_s") == pytest.approx(1 / 815.0)
