"""Modal identification: known poles/residues, the whole impact chain, rejection, UFF 58."""

from __future__ import annotations

import copy

import numpy as np
import pytest
import xarray as xr

from robomill import modal
from robomill.io import RawDataError
from robomill.io.impact import read_frf_uff, read_hit
from robomill.modal.uff import write_frf_uff
from robomill.synth import impact as synth_impact
from robomill.synth.cell import cell_from_config

BAND = [10.0, 100.0]


def _analytic_ds(cell, df=0.25, fmax=200.0):
    f = np.arange(0.0, fmax + df / 2, df)
    H = cell.receptance_m_per_N(f)
    H[..., 0] = np.nan
    ds = xr.Dataset({"H": (("output", "input", "frequency"), H),
                     "coherence": (("output", "input", "frequency"), np.ones(H.shape))},
                    coords=modal.frf_coords(f))
    ds.attrs["window_sigma_per_s"] = 0.0
    return ds


def _truth(cell):
    return (np.array([m.f_hz for m in cell.modes]), np.array([m.zeta for m in cell.modes]),
            np.array([m.k_N_m for m in cell.modes]), np.array([m.shape for m in cell.modes]))


def test_known_poles_and_residues_give_the_frf_exactly(tiny_config):
    cell = cell_from_config(tiny_config)
    f_n, zeta, k, shapes = _truth(cell)
    poles, residues = modal.modal_residues(f_n, zeta, k, shapes)
    f = np.linspace(1.0, 150.0, 997)
    H = modal.synthesize_frf(poles, residues, f)
    ref = cell.receptance_m_per_N(f)
    assert np.max(np.abs(H - ref)) <= 1e-12 * np.max(np.abs(ref))
    # and back: poles -> f_n, zeta; residues -> shapes, modal stiffness
    table, _ = modal.modes_table(poles, residues)
    np.testing.assert_allclose(table["f_n_hz"], f_n, rtol=1e-12)
    np.testing.assert_allclose(table["zeta"], zeta, rtol=1e-12)
    np.testing.assert_allclose(table["k_modal_N_m"], k, rtol=1e-9)
    np.testing.assert_allclose(np.abs(table[["shape_x", "shape_y", "shape_z"]].to_numpy()),
                               np.abs(shapes), atol=1e-9)


def test_lscf_on_noise_free_frfs_recovers_the_modes(tiny_config):
    cell = cell_from_config(tiny_config)
    f_n, zeta, k, _ = _truth(cell)
    idn = modal.identify(_analytic_ds(cell), band_hz=BAND, max_order=30)
    t = idn.modes
    assert len(t) == len(f_n)
    np.testing.assert_allclose(t["f_n_hz"], f_n, rtol=1e-4)
    np.testing.assert_allclose(t["zeta"], zeta, rtol=1e-2)
    np.testing.assert_allclose(t["k_modal_N_m"], k, rtol=2e-2)
    # the synthesized FRF reproduces the measured one in the band
    f = _analytic_ds(cell)["frequency"].values
    inb = (f >= BAND[0]) & (f <= BAND[1])
    ref = cell.receptance_m_per_N(f[inb])
    assert np.max(np.abs(idn.H_synth[..., inb] - ref)) < 1e-3 * np.max(np.abs(ref))


def _chain(config):
    cell = cell_from_config(config)
    imp = config["synth"]["impact"]
    groups, checks = {d: [] for d in "XYZ"}, {}
    for d in "XYZ":
        for k in range(1, imp["hits_per_direction"] + 1):
            df = synth_impact.simulate_hit(config, cell, d, k)
            force, acc = df["force_N"].to_numpy(), df[["ax_ms2", "ay_ms2", "az_ms2"]].to_numpy()
            c = modal.check_hit(force, acc, imp["fs_hz"])
            checks[(d, k)] = c
            if c.accepted:
                groups[d].append((force, acc, c.trigger_index))
    ds = modal.frf_matrix(groups, imp["fs_hz"], force_window_s=0.01, exponential_end=0.05)
    return cell, ds, checks


def test_whole_chain_with_noise_recovers_f_n_and_zeta(tiny_config):
    cell, ds, checks = _chain(tiny_config)
    f_n, zeta, _, _ = _truth(cell)
    assert ds.attrs["window_sigma_per_s"] > 0
    idn = modal.identify(ds, band_hz=BAND, max_order=30)
    t = idn.modes
    assert len(t) == len(f_n)
    assert np.all(np.abs(t["f_n_hz"].to_numpy() / f_n - 1) < 0.005)
    assert np.all(np.abs(t["zeta"].to_numpy() / zeta - 1) < 0.10)
    # without the exponential-window correction the damping is clearly biased
    assert np.all(t["zeta_windowed"].to_numpy() > t["zeta"].to_numpy())


def test_planted_defects_are_rejected_with_their_reason(tiny_config):
    cfg = copy.deepcopy(tiny_config)
    cfg["synth"]["impact"].update(double_hit_probability=0.5, overload_probability=0.5)
    cell = cell_from_config(cfg)
    seen = set()
    for d in "XYZ":
        for k in (1, 2, 3):
            planted = synth_impact.planted_defect(cfg, d, k)
            df = synth_impact.simulate_hit(cfg, cell, d, k)
            c = modal.check_hit(df["force_N"].to_numpy(),
                                df[["ax_ms2", "ay_ms2", "az_ms2"]].to_numpy(), 1024,
                                accel_range_ms2=cfg["synth"]["impact"]["accel_range_ms2"],
                                force_range_N=cfg["synth"]["impact"]["force_range_N"])
            assert c.accepted == (planted == "none")
            if planted == "double_hit":
                assert c.reason.startswith("double hit")
            if planted == "overload":
                assert c.reason.startswith("overload")
            seen.add(planted)
    assert {"double_hit", "overload"} <= seen


def test_double_hit_is_rejected_and_single_hit_accepted():
    fs = 2048.0
    t = np.arange(4096) / fs
    single = synth_impact.half_sine_pulse(t, 0.05, 0.002, 100.0)
    double = single + synth_impact.half_sine_pulse(t, 0.062, 0.002, 40.0)
    acc = np.zeros((t.size, 3))
    acc[:, 0] = np.sin(2 * np.pi * 35 * t) * np.exp(-5 * t)
    assert modal.check_hit(single, acc, fs).accepted
    c = modal.check_hit(double, acc, fs)
    assert not c.accepted and c.reason.startswith("double hit")
    clipped = acc.copy()
    clipped[:, 1] = np.clip(3 * acc[:, 0], -1.0, 1.0)
    c = modal.check_hit(single, clipped, fs)
    assert not c.accepted and "ay_ms2" in c.reason


def test_exponential_window_correction_restores_damping():
    wn, zeta, sigma = 2 * np.pi * 50, 0.02, 1.5
    p = -zeta * wn + 1j * wn * np.sqrt(1 - zeta**2)
    f, z = modal.pole_f_zeta(modal.correct_window_damping(p - sigma, sigma))
    assert f == pytest.approx(50.0) and z == pytest.approx(zeta)
    n, fs = 4096, 1024.0
    _, w_exp, s = modal.impact_windows(n, fs, 100, force_window_s=0.01, exponential_end=0.05)
    assert s == pytest.approx(np.log(20) / 4.0)
    assert w_exp[:101] == pytest.approx(1.0)
    assert w_exp[100 + 1024] == pytest.approx(np.exp(-s * 1.0), rel=1e-9)


def test_uff58_round_trip_and_broken_file(tmp_path, tiny_config):
    ds = _analytic_ds(cell_from_config(tiny_config), df=0.5, fmax=120.0)
    ds["coherence"] = ds["coherence"] * 0.9
    path = write_frf_uff(ds, tmp_path / "frf.uff")
    back = read_frf_uff(path)
    np.testing.assert_allclose(back["H"].values[..., 1:], ds["H"].values[..., 1:], rtol=1e-9)
    np.testing.assert_allclose(back["coherence"].values[..., 1:], 0.9)
    assert list(back["output"].values) == ["X", "Y", "Z"]
    text = path.read_text()
    broken = tmp_path / "broken.uff"
    # cut inside a data set: refused, naming the file
    broken.write_text(text[: len(text) // 3 + 500])
    with pytest.raises(RawDataError, match="broken.uff.*truncated"):
        read_frf_uff(broken)
    # cut at a set boundary: a complete file of fewer FRFs (here: response X, references
    # X, Y, Z, a roving-hammer layout) is read as such
    part = tmp_path / "part.uff"
    part.write_text(text[: len(text) // 3])
    back = read_frf_uff(part)
    assert list(back["output"].values) == ["X"] and list(back["input"].values) == list("XYZ")
    junk = tmp_path / "junk.uff"
    junk.write_text("    -1\n    58\nnot a data set\n")
    with pytest.raises(RawDataError):
        read_frf_uff(junk)


def test_complex_split_round_trip():
    f = np.arange(5.0)
    ds = xr.Dataset({"H": (("frequency",), f + 1j * f**2, {"units": "m/N", "long_name": "H"})},
                    coords={"frequency": f})
    split = modal.split_complex(ds)
    assert set(split.data_vars) == {"H_real", "H_imag"}
    back = modal.join_complex(split)
    np.testing.assert_array_equal(back["H"].values, ds["H"].values)
    assert back["H"].attrs["units"] == "m/N"


def test_read_hit_rejects_bad_files(tmp_path):
    good = tmp_path / "hitX_1.csv"
    t = np.arange(100) / 1024
    rows = "\n".join(f"{x},{1.0},{0.0},{0.0},{0.0}" for x in t)
    good.write_text("t_s,force_N,ax_ms2,ay_ms2,az_ms2\n" + rows + "\n")
    fs, force, acc = read_hit(good)
    assert fs == pytest.approx(1024.0) and acc.shape == (100, 3)
    bad = tmp_path / "hitX_2.csv"
    bad.write_text("t_s,force_kN,ax_ms2,ay_ms2,az_ms2\n" + rows + "\n")
    with pytest.raises(RawDataError, match="force_N"):
        read_hit(bad)
    uneven = tmp_path / "hitX_3.csv"
    t2 = t.copy()
    t2[50] += 0.0004
    uneven.write_text("t_s,force_N,ax_ms2,ay_ms2,az_ms2\n"
                      + "\n".join(f"{x},1,0,0,0" for x in t2) + "\n")
    with pytest.raises(RawDataError, match="t_s"):
        read_hit(uneven)
