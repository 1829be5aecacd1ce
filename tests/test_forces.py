"""Force model, chunked spectra, peaks and cutting-coefficient identification (thesis §3.1)."""

import numpy as np
import pandas as pd
import pytest
import scipy.signal

from robomill.forces import (
    FLAG_COLUMNS,
    CuttingCoefficients,
    ForceAnalysisSettings,
    StreamDecimator,
    analyse_force_record,
    auto_decimation,
    decimate_whole,
    dominant_peak,
    engagement_angles_rad,
    feed_per_tooth_mm,
    force_cut_dataset,
    gather_force_study,
    identify_cutting_coefficients,
    identify_cutting_coefficients_general,
    lowpass_fir,
    mean_milling_forces,
    mean_slot_forces,
    slot_force_tables,
    slot_forces,
    slot_forces_band_limited,
)
from robomill.spectra import thesis_spectrum

K = CuttingCoefficients(796.0, 168.0, 222.0, 27.7, 30.8, 6.7)
FS = 25000.0
SPINDLE_HZ = 28000 / 60


def chunks_of(t, F, n):
    for i in range(0, len(t), n):
        yield t[i:i + n], F[i:i + n]


@pytest.mark.parametrize("c_mm", [0.00107, 0.005, 0.0107])
@pytest.mark.parametrize("a_mm", [0.25, 0.5])
def test_mean_slot_forces_match_closed_form(c_mm, a_mm):
    phi = (np.arange(200_000) + 0.5) * 2 * np.pi / 200_000
    numeric = slot_forces(phi, c_mm, a_mm, K).mean(axis=0)
    closed = mean_slot_forces(c_mm, a_mm, K)
    np.testing.assert_allclose(numeric, closed, rtol=1e-6, atol=1e-9)
    # hand-written Altintas (2012) averages for phi_st = 0, phi_ex = pi, N = 2
    na = 2 * a_mm
    np.testing.assert_allclose(closed, [-na * (K.Krc * c_mm / 4 + K.Kre / np.pi),
                                        na * (K.Ktc * c_mm / 4 + K.Kte / np.pi),
                                        na * (K.Kac * c_mm / np.pi + K.Kae / 2)])


def test_band_limited_model_keeps_the_mean_and_the_shape():
    phi = (np.arange(100_000) + 0.5) * 2 * np.pi / 100_000
    tables = slot_force_tables(2, 24)
    bl = slot_forces_band_limited(phi, 0.005, 0.25, K, tables)
    np.testing.assert_allclose(bl.mean(axis=0), mean_slot_forces(0.005, 0.25, K), rtol=1e-9,
                               atol=1e-9)
    # Fz is continuous (no edge jump): band-limiting changes it little
    exact = slot_forces(phi, 0.005, 0.25, K)
    assert np.abs(bl[:, 2] - exact[:, 2]).max() < 0.01 * np.abs(exact[:, 2]).max()
    # spectrum: nothing above harmonic 24 of the spindle (table interpolation: < -100 dB)
    spec = np.abs(np.fft.rfft(bl[:, 0]))
    assert spec[30:].max() < 1e-5 * spec[1:25].max()


def test_fz_shape_has_two_humps_per_revolution():
    """Thesis Fig 3.2: Fz of a 2-flute slot repeats at tooth passing, peak at phi = 90 deg."""
    phi = np.linspace(0, 2 * np.pi, 3601)[:-1]
    fz = slot_forces(phi, 0.005, 0.25, K)[:, 2]
    np.testing.assert_allclose(fz[:1800], fz[1800:], atol=1e-12)
    assert np.argmax(fz[:1800]) == 900


def _record(duration_s, modulation_hz=None, depth_mod=0.05, noise=0.0, seed=0):
    t = np.arange(int(duration_s * FS)) / FS
    a = 0.25 * (1 + (depth_mod * np.sin(2 * np.pi * modulation_hz * t) if modulation_hz else 0))
    tables = slot_force_tables(2, int(0.45 * FS / SPINDLE_HZ))
    F = slot_forces_band_limited(2 * np.pi * SPINDLE_HZ * t, 0.004, a, K, tables)
    if noise:
        F = F + np.random.default_rng(seed).normal(0, noise, F.shape)
    return t, F


def test_planted_85_hz_modulation_is_found_within_one_bin():
    t, F = _record(4.0, modulation_hz=85.0, noise=0.2)
    res = analyse_force_record(chunks_of(t, F, 30_000), FS, len(t))
    bin_hz = FS / len(t)
    f_dom, _ = dominant_peak(res["f_low"], res["power_low"].sum(axis=0), (15.0, 250.0))
    assert abs(f_dom - 85.0) <= bin_hz
    # and not where there is nothing
    t0, F0 = _record(4.0, modulation_hz=None, noise=0.2)
    res0 = analyse_force_record(chunks_of(t0, F0, 30_000), FS, len(t0))
    p85 = res["power_low"].sum(axis=0)[np.argmin(abs(res["f_low"] - 85))]
    p85_0 = res0["power_low"].sum(axis=0)[np.argmin(abs(res0["f_low"] - 85))]
    assert p85 > 100 * p85_0


def test_chunked_spectra_equal_unchunked():
    t, F = _record(1.3, modulation_hz=85.0, noise=0.3)
    s = ForceAnalysisSettings(welch_nperseg=4096)
    results = [analyse_force_record(chunks_of(t, F, n), FS, len(t), s)
               for n in (len(t), 65_536, 12_345, 1_000)]
    for r in results[1:]:
        for key in ("mean", "psd", "power_low", "env_min", "env_max", "excerpt"):
            np.testing.assert_allclose(r[key], results[0][key], rtol=1e-12, atol=1e-15)
    r = results[2]
    # Welch: equal to scipy.signal.welch on the whole record
    f, psd = scipy.signal.welch(F.T, fs=FS, nperseg=4096)
    np.testing.assert_allclose(r["psd"], psd, rtol=1e-10, atol=1e-18)
    np.testing.assert_allclose(r["f_welch"], f)
    # low band: equal to the decimated whole record, and to the full-rate thesis DFT bins
    D = auto_decimation(FS, s.lowband_hz)  # decimation: null (the default) derives it
    assert D == 25 and r["decimation"] == D
    h = lowpass_fir(FS, s.lowband_hz, FS / D - s.lowband_hz, s.fir_atten_db)
    off = F[: 8 * D].mean(axis=0)[:, None]  # steady-state start (see the class)
    ref = thesis_spectrum(decimate_whole(F.T - off, h, D) + off, FS / D)
    keep = ref.f <= s.lowband_hz
    np.testing.assert_allclose(r["power_low"], ref.power[:, keep], rtol=1e-10, atol=1e-18)
    # the same bins k/T as the full-rate thesis DFT, with the same power where it matters
    full = thesis_spectrum(F.T, FS)
    sel = full.f <= 240.0
    n = int(sel.sum())
    np.testing.assert_allclose(r["f_low"][:n], full.f[sel])
    k85 = int(np.argmin(abs(full.f - 85.0)))
    np.testing.assert_allclose(r["power_low"][:, [0, k85]], full.power[:, [0, k85]], rtol=3e-2)
    np.testing.assert_allclose(r["power_low"][:, 1:n].sum(axis=1),
                               full.power[:, 1:n].sum(axis=1), rtol=0.05)
    np.testing.assert_allclose(r["mean"], F.mean(axis=0), rtol=1e-12)


@pytest.mark.parametrize("chunk", [1, 24, 25, 26, 391, 5000])
def test_stream_decimator_matches_whole(chunk):
    x = np.random.default_rng(1).normal(size=(2, 7_777))
    h = lowpass_fir(FS, 250.0, 750.0)
    d = StreamDecimator(h, 25, 2)
    for i in range(0, x.shape[1], chunk):
        d.add(x[:, i:i + chunk])
    np.testing.assert_allclose(d.result(), decimate_whole(x, h, 25), rtol=1e-12, atol=1e-14)


def test_identified_coefficients_recover_planted_within_2_percent():
    feeds = [1, 2, 3, 4, 5, 2, 4, 6, 8, 10]
    depths = [0.25] * 5 + [0.5] * 5
    phi = (np.arange(20_000) + 0.5) * 2 * np.pi / 20_000
    c = np.array([feed_per_tooth_mm(v, 28000, 2) for v in feeds])
    means = np.array([slot_forces(phi, ci, a, K).mean(axis=0)
                      for ci, a in zip(c, depths, strict=True)])
    table = identify_cutting_coefficients(c, depths, means)
    planted = K.as_dict()
    assert list(table["name"]) == ["Ktc", "Krc", "Kac", "Kte", "Kre", "Kae"]
    assert list(table["unit"]) == ["N/mm^2"] * 3 + ["N/mm"] * 3
    for row in table.itertuples():
        assert abs(row.value / planted[row.name] - 1) < 0.02, row
        assert row.ci_low <= row.value <= row.ci_high


def test_identification_intervals_cover_truth_with_noise():
    rng = np.random.default_rng(3)
    c = np.repeat(np.linspace(0.001, 0.0107, 6), 3)
    a = np.full(c.size, 0.25)
    means = mean_slot_forces(c, a, K) + rng.normal(0, 0.02, (c.size, 3))
    table = identify_cutting_coefficients(c, a, means).set_index("name")
    for name, value in K.as_dict().items():
        lo, hi = table.loc[name, ["ci_low", "ci_high"]]
        assert lo < hi
        assert lo - 3 * (hi - lo) < value < hi + 3 * (hi - lo)


def test_identified_coefficients_are_flagged_physical_when_planted_positive():
    c = np.repeat(np.linspace(0.001, 0.0107, 5), 2)
    a = np.full(c.size, 0.25)
    F = mean_slot_forces(c, a, K) + np.random.default_rng(5).normal(0, 0.02, (c.size, 3))
    table = identify_cutting_coefficients(c, a, F)
    assert list(table.columns[5:]) == list(FLAG_COLUMNS)
    assert table["physical"].all() and not table["negative"].any()
    # the 0.02 N noise against a feed effect of 0.07 (radial) to 0.34 N (tangential) rms
    assert (table["fit_residual_rms_N"] < 0.03).all()
    assert (table["fit_signal_rms_N"] > 2 * table["fit_residual_rms_N"]).all()


@pytest.mark.parametrize("general", [False, True])
def test_a_planted_negative_edge_coefficient_is_flagged(general):
    """A record whose radial edge force pulls the tool into the cut (Kre < 0) cannot be
    physical: the identified Kre is negative and flagged, the other five are not."""
    bad = CuttingCoefficients(796.0, 168.0, 222.0, 27.7, -30.8, 6.7)
    c = np.repeat(np.linspace(0.001, 0.0107, 5), 2)
    a = np.full(c.size, 0.25)
    F = mean_slot_forces(c, a, bad) + np.random.default_rng(6).normal(0, 0.02, (c.size, 3))
    table = (identify_cutting_coefficients_general(c, a, F, flutes=2, entry_rad=0.0,
                                                   exit_rad=np.pi) if general
             else identify_cutting_coefficients(c, a, F)).set_index("name")
    assert table.loc["Kre", "value"] == pytest.approx(-30.8, rel=0.01)
    assert bool(table.loc["Kre", "negative"]) and not bool(table.loc["Kre", "physical"])
    others = table.drop(index="Kre")
    assert others["physical"].all() and not others["negative"].any()


def test_a_fit_that_explains_less_than_its_scatter_is_flagged():
    """Mean forces that do not change with the feed (a constant plus 5 N scatter): the axis
    fits leave a residual larger than the feed effect they find."""
    rng = np.random.default_rng(7)
    c = np.repeat(np.linspace(0.001, 0.0107, 6), 2)
    a = np.full(c.size, 0.25)
    F = np.array([10.0, 20.0, 5.0]) + rng.normal(0, 5.0, (c.size, 3))
    table = identify_cutting_coefficients(c, a, F).set_index("name")
    flagged = table[table["residual_exceeds_signal"]]
    assert len(flagged) >= 4 and not flagged["physical"].any()
    for name in flagged.index:
        assert table.loc[name, "fit_residual_rms_N"] > table.loc[name, "fit_signal_rms_N"]
    # the residual is the 5 N scatter
    assert 2.5 < float(table["fit_residual_rms_N"].max()) < 8.0


def test_identification_needs_several_feeds():
    with pytest.raises(ValueError, match="at least 3 cuts"):
        identify_cutting_coefficients([0.001, 0.001], [0.25, 0.25], np.zeros((2, 3)))


# ---- settings from the data -------------------------------------------------------
@pytest.mark.parametrize(("fs_hz", "band_hz", "expected"),
                         [(25_000.0, 250.0, 25), (10_000.0, 250.0, 10), (48_000.0, 250.0, 48),
                          (25_000.0, 100.0, 62), (1_200.0, 250.0, 1), (815.0, 100.0, 2)])
def test_auto_decimation_keeps_four_times_the_band(fs_hz, band_hz, expected):
    D = auto_decimation(fs_hz, band_hz)
    assert D == expected
    assert fs_hz / D >= 4 * band_hz or D == 1
    assert fs_hz / (D + 1) < 4 * band_hz  # the largest such factor


def test_ten_khz_record_with_default_settings_finds_its_peak():
    """A 10 kHz record (Kistler DynoWare at 6000 rpm, 2 teeth) with the default settings: the
    decimation comes from the rate (10), and a planted 85 Hz modulation is found within a
    bin. With the old fixed decimation 25 it was refused (400 Hz left for a 250 Hz band)."""
    fs, spindle_hz = 10_000.0, 6000 / 60
    t = np.arange(int(4.0 * fs)) / fs
    a = 0.25 * (1 + 0.05 * np.sin(2 * np.pi * 85.0 * t))
    F = slot_forces_band_limited(2 * np.pi * spindle_hz * t, 0.004, a, K,
                                 slot_force_tables(2, int(0.45 * fs / spindle_hz)))
    F = F + np.random.default_rng(3).normal(0, 0.2, F.shape)
    res = analyse_force_record(chunks_of(t, F, 7_777), fs, len(t))
    assert res["decimation"] == 10
    assert res["f_low"].max() <= 250.0 and res["lowband_resolution_hz"] == pytest.approx(0.25)
    # the tooth passing (200 Hz) and the spindle (100 Hz) are in the band: left out
    cut = {"id": "s1_g1_py", "set": 1, "segment": 1, "direction": "py", "feed_mm_s": 2.0,
           "depth_mm": 0.25}
    ds = force_cut_dataset(res, cut=cut, fs_hz=fs, n_samples=t.size, spindle_rpm=6000,
                           flutes=2, dominant_band_hz=(15.0, 250.0),
                           kinematic_band_per_mm=(0.3, 1.0), n_harmonics=13)
    assert abs(float(ds["dominant_hz"]) - 85.0) <= fs / len(t)
    assert not bool(ds["dominant_below_resolution"])
    assert float(ds["harmonic_hz"][0]) == 200.0


def test_explicit_decimation_too_high_for_the_record_names_the_fix():
    from robomill.io import ConfigError

    t = np.arange(20_000) / 10_000.0
    F = np.zeros((t.size, 3))
    with pytest.raises(ConfigError, match=r"forces.decimation 25 leaves fs 400 Hz of the 10000 Hz "
                       r"record.*decimation <= 19.*or null"):
        analyse_force_record([(t, F)], 10_000.0, t.size, ForceAnalysisSettings(decimation=25))
    with pytest.raises(ConfigError, match="lowband_hz 250 Hz is not below the Nyquist"):
        analyse_force_record([(t, F)], 400.0, t.size, ForceAnalysisSettings())


@pytest.mark.parametrize(("length_mm", "flagged"),
                         [(5.0, True), (10.0, True), (15.0, True), (25.0, False), (40.0, False)])
def test_kinematic_peak_of_a_short_record_is_flagged(length_mm, flagged):
    """Known truth: a 0.5 1/mm force modulation planted in records of 5–40 mm at 4 mm/s. The
    peak has 0.5 L periods in the record; fewer than min_peak_cycles = 10 (L < 20 mm) is
    flagged below the record's resolution, and the flag and resolution 1/L are in the
    dataset."""
    v, fs = 4.0, 5_000.0
    t = np.arange(int(round(length_mm / v * fs))) / fs
    F = np.column_stack([np.zeros_like(t), 10 + np.sin(2 * np.pi * 0.5 * v * t),
                         np.zeros_like(t)])
    s = ForceAnalysisSettings(welch_nperseg=1024, lowband_hz=100.0)
    res = analyse_force_record([(t, F)], fs, t.size, s)
    cut = {"id": "s1_g1_py", "set": 1, "segment": 1, "direction": "py", "feed_mm_s": v,
           "depth_mm": 0.25}
    ds = force_cut_dataset(res, cut=cut, fs_hz=fs, n_samples=t.size, spindle_rpm=6000,
                           flutes=2, dominant_band_hz=(15.0, 100.0),
                           kinematic_band_per_mm=(0.3, 1.0), n_harmonics=3)
    assert float(ds["kinematic_resolution_per_mm"]) == pytest.approx(1 / length_mm, rel=1e-3)
    if not flagged:
        assert float(ds["kinematic_per_mm"]) == pytest.approx(0.5, abs=1 / length_mm)  # a bin
    assert bool(ds["kinematic_below_resolution"]) is flagged
    assert ds.attrs["decimation"] == 12


def test_nearest_modes_of_planted_peaks():
    import pandas as pd

    from robomill.forces import nearest_modes

    modes = pd.DataFrame({"mode": [1, 2, 3], "f_n_hz": [60.0, 85.0, 110.0]})
    t = nearest_modes(np.array([61.5, 84.0, 120.0, 72.0]), modes)
    assert t["nearest_mode"].tolist() == [1, 2, 3, 1]
    np.testing.assert_allclose(t["offset_hz"], [1.5, -1.0, 10.0, 12.0])
    empty = nearest_modes(np.array([61.5]), modes.iloc[:0])
    assert np.isnan(empty["offset_hz"].iloc[0]) and empty["nearest_mode"].iloc[0] is None


# ---- partial immersion, up/down milling (step 5; Altintas 2012 §2.2) ---------------
@pytest.mark.parametrize(("ae", "mode", "expected_deg"), [
    (1.0, "slot", (0.0, 180.0)), (0.5, "down", (90.0, 180.0)), (0.5, "up", (0.0, 90.0)),
    (0.25, "down", (120.0, 180.0)), (0.25, "up", (0.0, 60.0)), (1.0, "down", (0.0, 180.0))])
def test_engagement_angles_from_immersion_and_mode(ae, mode, expected_deg):
    st, ex = engagement_angles_rad(ae, mode)
    assert np.degrees([st, ex]) == pytest.approx(expected_deg, abs=1e-9)


@pytest.mark.parametrize(("ae", "mode", "message"), [
    (0.0, "down", "radial_immersion must be in"), (1.5, "up", "radial_immersion must be in"),
    (0.5, "slot", "milling 'slot' needs radial_immersion 1"), (0.5, "climb", "milling must be")])
def test_engagement_angles_refuse_bad_input(ae, mode, message):
    with pytest.raises(ValueError, match=message):
        engagement_angles_rad(ae, mode)


@pytest.mark.parametrize(("ae", "mode"), [(0.5, "down"), (0.5, "up"), (0.3, "down"),
                                          (0.7, "up"), (1.0, "slot")])
@pytest.mark.parametrize("flutes", [2, 3])
def test_mean_milling_forces_match_the_numerical_mean(ae, mode, flutes):
    """Closed form (Altintas eq. 2.25) == the mean of eq. 3.1 with the engagement window."""
    st, ex = engagement_angles_rad(ae, mode)
    phi = (np.arange(400_000) + 0.5) * 2 * np.pi / 400_000
    numeric = slot_forces(phi, 0.01, 0.5, K, flutes=flutes, entry_rad=st, exit_rad=ex)
    closed = mean_milling_forces(0.01, 0.5, K, flutes=flutes, entry_rad=st, exit_rad=ex)
    np.testing.assert_allclose(numeric.mean(axis=0), closed, rtol=1e-4, atol=1e-3)
    tables = slot_force_tables(flutes, 60, entry_rad=st, exit_rad=ex)
    band = slot_forces_band_limited(phi, 0.01, 0.5, K, tables)
    np.testing.assert_allclose(band.mean(axis=0), closed, rtol=1e-9, atol=1e-9)


def test_half_immersion_down_milling_has_its_own_force_direction():
    """Down milling at a_e/D = 0.5: the cross-feed force dominates and the feed force nearly
    vanishes; up milling: the feed force dominates (the known signs of Altintas Fig 2.7)."""
    down = mean_milling_forces(0.02, 1.0, K, flutes=3,
                               entry_rad=np.pi / 2, exit_rad=np.pi)
    up = mean_milling_forces(0.02, 1.0, K, flutes=3, entry_rad=0.0, exit_rad=np.pi / 2)
    assert abs(down[1]) > 10 * abs(down[0])
    assert abs(up[0]) > 5 * abs(up[1])
    assert down[2] == pytest.approx(up[2])  # axial: the same chip area either side


def test_slot_band_limited_tables_are_unchanged_by_the_window_arguments():
    a = slot_force_tables(2, 50)
    b = slot_force_tables(2, 50, entry_rad=0.0, exit_rad=np.pi)
    np.testing.assert_array_equal(a.table, b.table)


def _mixed_design():
    """Slots with 2 teeth, half-immersion down milling and up milling with 3 teeth, three
    spindle speeds: per cut c, a, N, φ_st, φ_ex."""
    rows = []
    for rpm, z, ae, mode in ((12000, 3, 0.5, "down"), (18000, 3, 0.5, "down"),
                             (24000, 2, 1.0, "slot"), (18000, 3, 0.3, "up")):
        for v in (1.0, 2.0, 4.0):
            st, ex = engagement_angles_rad(ae, mode)
            rows.append((feed_per_tooth_mm(v, rpm, z), 0.5, z, st, ex))
    return np.array(rows).T


def test_general_identification_recovers_planted_coefficients_of_a_mixed_design():
    c, a, z, st, ex = _mixed_design()
    rng = np.random.default_rng(7)
    F = mean_milling_forces(c, a, K, flutes=z, entry_rad=st, exit_rad=ex)
    table = identify_cutting_coefficients(c, a, F + rng.normal(0, 0.01, F.shape),
                                          flutes=z.astype(int), entry_rad=st, exit_rad=ex)
    planted = K.as_dict()
    for row in table.itertuples():
        assert abs(row.value / planted[row.name] - 1) < 0.05, row
        assert row.ci_low - 3 * (row.ci_high - row.ci_low) < planted[row.name] < (
            row.ci_high + 3 * (row.ci_high - row.ci_low)), row
    # the slot-only regression would be wrong for this design (it assumes φ = 0..π)
    wrong = identify_cutting_coefficients(c, a, F, flutes=3).set_index("name")["value"]
    assert abs(wrong["Ktc"] / K.Ktc - 1) > 0.05


def test_general_identification_of_slots_equals_the_per_axis_regression():
    c = np.repeat(np.linspace(0.001, 0.0107, 5), 2)
    a = np.full(c.size, 0.25)
    F = mean_slot_forces(c, a, K) + np.random.default_rng(1).normal(0, 0.02, (c.size, 3))
    old = identify_cutting_coefficients(c, a, F)
    new = identify_cutting_coefficients_general(c, a, F, flutes=2, entry_rad=0.0,
                                                exit_rad=np.pi)
    np.testing.assert_allclose(new["value"], old["value"], rtol=1e-9)


def test_general_identification_needs_enough_cuts():
    with pytest.raises(ValueError, match="at least 3 cuts"):
        identify_cutting_coefficients_general([0.001, 0.002], 0.25, np.zeros((2, 3)),
                                              flutes=3, entry_rad=0.0, exit_rad=1.0)


def test_gather_of_a_free_design_uses_each_cuts_chip_model():
    """gather_force_study on cuts without set/segment, each with its own speed, flutes and
    milling mode: per-cut columns and the planted coefficients back."""
    import xarray as xr

    c, a, z, st, ex = _mixed_design()
    modes = [("down", 0.5)] * 6 + [("slot", 1.0)] * 3 + [("up", 0.3)] * 3
    F = mean_milling_forces(c, a, K, flutes=z, entry_rad=st, exit_rad=ex)
    datasets, processes = [], {}
    for i in range(c.size):
        cid = f"cut{i:02d}.{modes[i][0]}"
        datasets.append(xr.Dataset(
            {"mean_force_cut": ("component", F[i]), "mean_force": ("axis", F[i]),
             **{n: ((), 0.0, {"units": "1", "long_name": n})
                for n in ("dominant_hz", "dominant_power", "kinematic_per_mm",
                          "kinematic_power")},
             **{n: (d, np.zeros((3,) * len(d))) for n, d in (
                 ("psd", ("axis", "frequency")), ("power_low", ("axis", "lf_bin")),
                 ("f_low", ("lf_bin",)), ("f_spatial_low", ("lf_bin",)),
                 ("envelope_min", ("axis", "block")),
                 ("envelope_max", ("axis", "block")), ("envelope_t", ("block",)),
                 ("excerpt", ("axis", "sample")), ("excerpt_t", ("sample",)))},
             "harmonic_power": (("axis", "harmonic"), np.zeros((3, 3 - (i % 2)))),
             "harmonic_hz": ("harmonic", (1 + i) * np.arange(1.0, 4.0 - (i % 2)))},
            coords={"axis": ["Fx", "Fy", "Fz"], "component": ["feed", "cross_feed", "axial"],
                    "frequency": np.arange(3.0), "harmonic": [1, 2, 3][:3 - (i % 2)]},
            attrs={"cut": cid, "direction": "45 deg", "feed_mm_s": 1.0, "depth_mm": a[i],
                   "feed_per_tooth_mm": c[i], "n_samples": 10, "tooth_passing_hz": 1.0}))
        processes[cid] = {"spindle_rpm": 1.0, "flutes": int(z[i]), "milling": modes[i][0],
                          "radial_immersion": modes[i][1]}
    _, _, means, harmonics, coeffs = gather_force_study(datasets, flutes=2,
                                                        processes=processes)
    assert means["in_fit"].all()
    # a cut judged to chatter, whose mean force is a third of the chip model's (teeth out of
    # the cut): left out, the planted coefficients still come back; kept, they do not
    bad = datasets[4].copy()
    bad["mean_force_cut"] = bad["mean_force_cut"] / 3.0
    spoiled = datasets[:4] + [bad] + datasets[5:]
    for chattered, exact in (([bad.attrs["cut"]], True), ((), False)):
        m2, c2 = (lambda r: (r[2], r[4]))(gather_force_study(spoiled, flutes=2,
                                                              processes=processes,
                                                              chattered=chattered))
        assert list(m2["in_fit"]) == [c not in chattered for c in m2["cut"]]
        err = max(abs(r.value / K.as_dict()[r.name] - 1) for r in c2.itertuples())
        assert (err < 1e-6) == exact, err
    # three cuts at two chip loads, one of them chattering: without it nothing is
    # identified, so all three stay in (the design promised coefficients)
    few = [spoiled[i] for i in (0, 1, 4)]
    m3, c3 = (lambda r: (r[2], r[4]))(gather_force_study(few, flutes=2, processes=processes,
                                                          chattered=[bad.attrs["cut"]]))
    assert m3["in_fit"].all() and np.isfinite(c3["value"]).all()
    from robomill.forces.study import force_record_chatter

    v = pd.DataFrame({"cut": ["a", "a", "b", "c"], "kind": ["force", "sound", "sound", "force"],
                      "verdict": ["stable", "chatter", "chatter", "chatter"]})
    assert force_record_chatter(v) == ["c"]
    h1 = harmonics[harmonics["harmonic"] == 1]
    assert list(h1["f_hz"]) == [1.0 + i for i in range(c.size)]  # each cut's own line
    assert len(harmonics) == sum(3 - (i % 2) for i in range(c.size))  # no padded rows
    assert list(means["cut"]) == list(processes)  # the given order, no set/segment sort
    assert "set" not in means and "segment" not in means
    assert list(means["milling"]) == [m for m, _ in modes]
    assert means["entry_deg"].iloc[0] == pytest.approx(90.0)
    planted = K.as_dict()
    for row in coeffs.itertuples():
        assert row.value == pytest.approx(planted[row.name], rel=1e-6), row
