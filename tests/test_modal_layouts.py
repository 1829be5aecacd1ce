"""Modal testing on every layout: a 4-node structure with planted modes and shapes, hit by a
simulated hammer (roving hammer, roving accelerometer, tri-axial responses, SISO), plus the
sanity flags (negative modal constants, no driving point, low coherence)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from robomill import modal
from robomill.io.impact import HitRecord
from robomill.modal.layout import _point_key
from robomill.synth import impact as synth_impact
from robomill.synth.cell import Mode

FS = 1024
N = 4096  # 4 s records: 0.25 Hz lines
BAND = [10.0, 120.0]
NODES = (1, 2, 3, 4)
DOFS = [(n, a) for n in NODES for a in (1, 2, 3)]
F_HZ = np.array([30.0, 55.0, 85.0])
ZETA = np.array([0.02, 0.03, 0.025])
M_KG = np.array([2.0, 3.0, 1.5])


def _shapes() -> np.ndarray:
    """Planted unit shapes over the 12 DOFs: smooth bending-like patterns along the nodes."""
    x = np.array([n for n, _ in DOFS], float)
    a = np.array([a for _, a in DOFS], float)
    phi = np.array([np.cos(0.6 * x) + 0.3 * a,
                    np.sin(1.1 * x) * (1 + 0.2 * a),
                    np.cos(2.0 * x + 0.3 * a) + 0.1])
    return phi / np.linalg.norm(phi, axis=1, keepdims=True)


PHI = _shapes()
MODES = [Mode(float(f), float(z), float(m * (2 * np.pi * f) ** 2), tuple(s))
         for f, z, m, s in zip(F_HZ, ZETA, M_KG, PHI, strict=True)]


def _truth_at(points) -> np.ndarray:
    """Planted shapes ``(n_modes, n_points)`` at signed points."""
    return np.array([[np.sign(d) * PHI[r, DOFS.index((n, abs(d)))] for n, d in points]
                     for r in range(len(MODES))])


def _hits(reference, responses, n_hits=3, seed=0, **kw):
    rng = np.random.default_rng([seed, reference[0], reference[1] + 5])
    out = []
    for k in range(n_hits):
        force, acc = synth_impact.structure_hit(MODES, DOFS, reference, responses, fs_hz=FS,
                                                n=N, rng=rng, force_noise_N=0.02,
                                                accel_noise_ms2=0.002, **kw)
        rec = HitRecord(float(FS), force, acc, tuple(reference), tuple(responses),
                        f"hit{reference}_{k}")
        out.append((rec, {"path": f"impact/{reference}_{k}", "hit": k + 1}))
    return out


def _identify(hit_list):
    table, groups = modal.check_and_group(hit_list)
    assert table["accepted"].all(), table["reason"].tolist()
    ds = modal.frf_from_groups(groups, FS, force_window_s=0.01, exponential_end=0.05)
    idn = modal.identify(ds, band_hz=BAND, max_order=20)
    return ds, idn


def _check_modes(idn, points):
    t = idn.modes
    assert len(t) == len(MODES), t
    assert np.all(np.abs(t["f_n_hz"].to_numpy() / F_HZ - 1) < 0.005)
    assert np.all(np.abs(t["zeta"].to_numpy() / ZETA - 1) < 0.10)
    assert [tuple(p) for p in idn.shapes.points] == [tuple(p) for p in points]
    truth = _truth_at(points)
    for r in range(len(MODES)):
        mac = modal.mac_matrix(np.vstack([idn.shapes.shapes[r], truth[r]]))[0, 1]
        assert mac >= 0.99, (r, mac)


def test_roving_hammer_one_response_many_references():
    """Accelerometer fixed at node 1 +X; the hammer roves over nodes 1-4 along X."""
    refs = [(n, 1) for n in NODES]
    hit_list = [h for ref in refs for h in _hits(ref, [(1, 1)])]
    ds, idn = _identify(hit_list)
    assert ds.sizes["output"] == 1 and ds.sizes["input"] == 4
    assert list(ds["input"].values) == ["X", "2X", "3X", "4X"]
    assert (ds["n_hits"].values == 3).all()
    _check_modes(idn, refs)
    # driving point 1X: modal mass of the unit shape over the measured points
    # m = m_r / sum_i phi_i^2 (the planted shapes are unit over all 12 DOFs)
    expected = M_KG / np.sum(_truth_at(refs) ** 2, axis=1)
    np.testing.assert_allclose(idn.modes["m_modal_kg"], expected, rtol=0.03)
    assert (idn.modes["driving_point"] == "X").all() and idn.modes["physical"].all()
    assert np.diag(idn.mac) == pytest.approx(1.0)


def test_roving_accelerometer_one_reference_many_responses_and_no_driving_point():
    """Hammer fixed at node 1 +Y; a single-axis accelerometer roves over nodes 1-4 (Y)."""
    resp = [(n, 2) for n in NODES]
    hit_list = [h for node in NODES for h in _hits((1, 2), [(node, 2)], seed=node)]
    ds, idn = _identify(hit_list)
    assert ds.sizes["output"] == 4 and ds.sizes["input"] == 1
    _check_modes(idn, resp)
    expected = M_KG / np.sum(_truth_at(resp) ** 2, axis=1)
    np.testing.assert_allclose(idn.modes["m_modal_kg"], expected, rtol=0.03)
    # the same test without the driving point: shapes, but no modal mass, and said so
    no_dp = [h for h in hit_list if h[0].responses != ((1, 2),)]
    ds2, idn2 = _identify(no_dp)
    _check_modes(idn2, [p for p in resp if p != (1, 2)])
    assert idn2.modes["m_modal_kg"].isna().all() and idn2.modes["k_modal_N_m"].isna().all()
    assert idn2.modes["flags"].str.contains("no driving point").all()


def test_triaxial_responses_with_a_negative_axis():
    """Hammer at node 2 +Z; a tri-axial accelerometer at every node, at node 3 mounted with
    its Y axis along −Y."""
    resp_by_node = {n: [(n, 1), (n, -2 if n == 3 else 2), (n, 3)] for n in NODES}
    hit_list = [h for n in NODES for h in _hits((2, 3), resp_by_node[n], seed=10 + n)]
    ds, idn = _identify(hit_list)
    assert ds.sizes["output"] == 12
    assert "3-Y" in ds["output"].values.tolist()
    assert int(ds["output_dir"].sel(output="3-Y")) == -2
    points = sorted([p for n in NODES for p in resp_by_node[n]], key=_point_key)
    _check_modes(idn, points)
    assert (idn.modes["driving_point"] == "2Z").all() and idn.modes["physical"].all()


def test_siso_driving_point():
    """One hammer direction, one accelerometer channel: a hit CSV with only ax_ms2."""
    ds, idn = _identify(_hits((1, 1), [(1, 1)], n_hits=4))
    assert ds["H"].shape[:2] == (1, 1)
    _check_modes(idn, [(1, 1)])
    expected = M_KG / _truth_at([(1, 1)])[:, 0] ** 2
    np.testing.assert_allclose(idn.modes["m_modal_kg"], expected, rtol=0.03)


def _analytic(outputs, inputs, df=0.25, fmax=150.0):
    f = np.arange(0.0, fmax + df / 2, df)
    k = M_KG * (2 * np.pi * F_HZ) ** 2
    poles, res = modal.modal_residues(F_HZ, ZETA, k, PHI)
    H = modal.synthesize_frf(poles, res, f)  # (12, 12, nf), positive axes
    io = [DOFS.index((n, abs(d))) for n, d in outputs]
    ii = [DOFS.index((n, abs(d))) for n, d in inputs]
    so = np.array([np.sign(d) for _, d in outputs])[:, None, None]
    si = np.array([np.sign(d) for _, d in inputs])[None, :, None]
    Hm = H[np.ix_(io, ii)] * so * si
    Hm[..., 0] = np.nan
    return xr.Dataset({"H": (("output", "input", "frequency"), Hm),
                       "coherence": (("output", "input", "frequency"), np.ones(Hm.shape))},
                      coords=modal.frf_coords(f, outputs, inputs))


def test_negative_modal_constants_are_flagged_not_silently_reported():
    ds = _analytic([(1, 1)], [(1, 1), (2, 1), (3, 1)])
    good = modal.identify(ds, band_hz=BAND, max_order=20)
    assert good.modes["physical"].all() and (good.modes["flags"] == "").all()
    bad = ds.copy(deep=True)
    bad["H"][0, 0] = -bad["H"][0, 0]  # a driving point with its sign mixed up
    idn = modal.identify(bad, band_hz=BAND, max_order=20)
    assert (idn.modes["m_modal_kg"] < 0).all() and (idn.modes["k_modal_N_m"] < 0).all()
    assert (~idn.modes["physical"]).all()
    assert idn.modes["flags"].str.contains("negative modal mass").all()


def test_low_coherence_at_a_mode_is_flagged():
    ds = _analytic([(1, 1)], [(1, 1), (4, 1)])
    f = ds["frequency"].values
    ds["coherence"][..., np.abs(f - 55.0) < 2.0] = 0.4
    idn = modal.identify(ds, band_hz=BAND, max_order=20)
    flagged = idn.modes.set_index("mode")["flags"]
    assert "coherence 0.40" in flagged[2] and "below 0.75" in flagged[2]
    assert flagged[1] == "" and flagged[3] == ""
    assert idn.modes["physical"].all()  # low coherence is a warning, not a non-physical mode


def test_mac_matrix_and_synthesized_frf_per_point():
    outputs = [(n, 2) for n in NODES]
    ds = _analytic(outputs, [(1, 2)])
    idn = modal.identify(ds, band_hz=BAND, max_order=20)
    np.testing.assert_allclose(idn.mac, modal.mac_matrix(_truth_at(outputs)), atol=1e-3)
    f = ds["frequency"].values
    inb = (f >= BAND[0]) & (f <= BAND[1])
    ref = ds["H"].values[..., inb]
    err = np.abs(idn.H_synth[..., inb] - ref).max(axis=-1) / np.abs(ref).max(axis=-1)
    assert err.shape == (4, 1) and np.all(err < 1e-3)
    table = modal.shapes_table(idn.shapes)
    assert set(table["point"]) == {"Y", "2Y", "3Y", "4Y"}
    assert np.allclose(table.groupby("mode")["shape_abs"].apply(lambda a: np.sum(a**2)), 1.0)


def test_band_from_the_hammer_spectrum_and_the_coherence():
    ds = _analytic([(1, 1)], [(1, 1)], fmax=400.0)
    f = ds["frequency"].values
    coh = np.where(f < 8.0, 0.3, 0.98)
    ds["coherence"] = (("output", "input", "frequency"), coh[None, None, :] * np.ones((1, 1, 1)))
    spectrum = 1.0 / (1 + (f / 150.0) ** 6)  # a hammer tip rolling off near 150 Hz
    lo, hi = modal.band_from_data(ds, force_spectrum=spectrum)
    assert 7.0 < lo < 10.0
    # 10 dB down where 1 + (f/150)^6 = 10: f = 150 * 9^(1/6) = 216.3 Hz
    assert hi == pytest.approx(150.0 * 9 ** (1 / 6), abs=0.5)
    ds["coherence"][:] = 0.1
    with pytest.raises(ValueError, match="never reaches 0.75"):
        modal.band_from_data(ds)


def _banded_ds():
    ds = _analytic([(1, 1)], [(1, 1)], fmax=400.0)
    f = ds["frequency"].values
    ds["coherence"] = (("output", "input", "frequency"),
                       np.where(f < 8.0, 0.3, 0.98)[None, None, :])
    return ds, 1.0 / (1 + (f / 150.0) ** 6)  # data band ~8-216 Hz


def test_band_sources_in_order_config_then_manifest_then_data():
    ds, spectrum = _banded_ds()
    data = modal.choose_band(ds, force_spectrum=spectrum)
    assert data.source == "data" and data.coverage == 1.0 and data.flag == ""
    assert data.band_hz == pytest.approx(modal.band_from_data(ds, force_spectrum=spectrum))
    exp = modal.choose_band(ds, experiment_band_hz=[10, 200], force_spectrum=spectrum)
    assert exp.source == "experiment.modal_band_hz" and exp.band_hz == (10.0, 200.0)
    assert exp.data_band_hz == data.band_hz and exp.flag == ""  # covers > 90 %
    cfg = modal.choose_band(ds, band_hz=[20, 60], experiment_band_hz=[10, 200],
                            force_spectrum=spectrum)
    assert cfg.source == "modal.band_hz" and cfg.band_hz == (20.0, 60.0)


def test_a_set_band_covering_a_small_part_of_the_data_band_is_flagged():
    ds, spectrum = _banded_ds()
    lo, hi = modal.band_from_data(ds, force_spectrum=spectrum)
    c = modal.choose_band(ds, experiment_band_hz=[10, 100], force_spectrum=spectrum)
    assert c.coverage == pytest.approx((100 - 10) / (hi - lo))  # about 43 %
    assert c.coverage < modal.BAND_COVERAGE_MIN
    assert "experiment.modal_band_hz 10-100 Hz covers 43 %" in c.flag
    assert modal.band_coverage([300, 400], [10, 200]) == 0.0
    ds["coherence"][:] = 0.1  # the data give no band: a set band is used, and flagged
    c = modal.choose_band(ds, band_hz=[10, 100])
    assert c.band_hz == (10.0, 100.0) and np.isnan(c.coverage) and "no band" in c.flag
    with pytest.raises(ValueError, match="never reaches"):
        modal.choose_band(ds)
    with pytest.raises(ValueError, match="is not a band"):
        modal.choose_band(ds, band_hz=[100, 10])


def test_hits_check_per_file_ranges_and_clipping():
    """Ranges from the manifest entry reject a hit reaching them; without ranges a hit is
    rejected only when it is flat-topped (clipped)."""
    (rec, meta), = _hits((1, 1), [(1, 1), (1, 2)], n_hits=1)
    big = max(np.abs(rec.accel_ms2).max(), 1e-9)
    table, _ = modal.check_and_group([(rec, {**meta, "range_ms2": big})])
    assert not table["accepted"][0] and "reaches its range" in table["reason"][0]
    table, _ = modal.check_and_group([(rec, meta)])
    assert table["accepted"][0]
    clipped = HitRecord(rec.fs_hz, rec.force_N, np.clip(rec.accel_ms2, -0.1 * big, 0.1 * big),
                        rec.reference, rec.responses, rec.source)
    table, _ = modal.check_and_group([(clipped, meta)])
    assert not table["accepted"][0] and "clipped" in table["reason"][0]
    assert table["responses"][0] == "X Y" and table["reference"][0] == "X"
    assert isinstance(table, pd.DataFrame)


def test_measured_directions_of_a_one_direction_test():
    """A test along X only (hammer X at node 1, accelerometers X at nodes 1 and 2) measured X
    and not Y, Z; the tool-tip matrix measured all three; a Y response to an X hit measures
    no axis (hit and measured must meet)."""
    from robomill.modal.layout import TOOLTIP, frf_coords, measured_directions

    f = np.arange(4.0)
    one = xr.Dataset(coords=frf_coords(f, [(1, 1), (2, 1)], [(1, 1)]))
    assert measured_directions(one) == {"hammer": "X", "response": "X", "measured": "X",
                                        "not_measured": "YZ"}
    full = xr.Dataset(coords=frf_coords(f, TOOLTIP, TOOLTIP))
    assert measured_directions(full)["not_measured"] == ""
    cross = xr.Dataset(coords=frf_coords(f, [(1, -2)], [(1, 1)]))
    assert measured_directions(cross) == {"hammer": "X", "response": "Y", "measured": "",
                                          "not_measured": "XYZ"}
