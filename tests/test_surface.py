"""Chapter 2 analysis with exact truth: spectra, Parseval, Gaussian filter, segment RMS,
mechanism attribution, tables, and the profile reader's errors."""

import numpy as np
import pandas as pd
import pytest

from robomill import surface as sf
from robomill.io import RawDataError
from robomill.io.profiles import read_profile
from robomill.spectra import parseval_rms, segment_rms, thesis_spectrum

FS = 800.0  # samples per mm
N = 12000
X = np.arange(N) / FS


def test_planted_sinusoid_amplitude_and_frequency():
    f0 = 40 * FS / N  # on a bin: 2.6667 1/mm
    z = 1.7 * np.sin(2 * np.pi * f0 * X + 0.3)
    s = thesis_spectrum(z, FS)
    k = int(np.argmax(s.amplitude))
    assert s.f[k] == pytest.approx(f0, rel=1e-12)
    assert s.amplitude[k] == pytest.approx(1.7, rel=1e-10)
    assert s.power[k] == pytest.approx(1.7**2 / 2, rel=1e-10)


def test_parseval_equals_time_rms():
    rng = np.random.default_rng(0)
    z = rng.normal(size=N) + 0.4 * np.sin(2 * np.pi * 0.4 * X)
    time_rms = np.sqrt(np.mean(z**2))
    assert parseval_rms(z) == pytest.approx(time_rms, rel=1e-10)
    assert np.sqrt(thesis_spectrum(z, FS).power.sum()) == pytest.approx(time_rms, rel=1e-10)
    ds = sf.analyse_profile(X, z)
    zd = ds["z"].values
    assert float(ds.parseval_rms_um) == pytest.approx(np.sqrt(np.mean(zd**2)), rel=1e-10)


@pytest.mark.parametrize("lambda_c", [0.25, 0.5, 0.8])
def test_gaussian_filter_transmits_half_at_cutoff(lambda_c):
    z = np.sin(2 * np.pi * X / lambda_c)
    w = sf.gaussian_filter(z, 1 / FS, lambda_c)
    mid = slice(N // 4, 3 * N // 4)
    gain = np.sqrt(2 * np.mean(w[mid] ** 2))
    assert gain == pytest.approx(0.5, abs=0.01)


def test_gaussian_waviness_of_a_long_wave_is_the_wave():
    z = 3.0 * np.sin(2 * np.pi * X / 7.5)  # 7.5 mm wave, λc = 0.25 mm: transmission 0.9997
    w, r = sf.split_profile(z, 1 / FS, 0.25)
    inner = slice(200, N - 200)  # beyond λc from the ends
    assert np.max(np.abs(w - z)[inner]) < 0.001 * 3.0
    assert np.max(np.abs(r[inner])) < 0.001 * 3.0
    # at the ends the zero-order correction is exact for a constant, biased by the local
    # slope times the one-sided kernel centroid (documented end effect): a few percent here
    assert np.max(np.abs(w - z)) < 0.05 * 3.0


def test_end_handling_keeps_a_constant():
    z = np.full(2000, 4.0)
    assert np.allclose(sf.gaussian_filter(z, 1 / FS, 0.8), 4.0, atol=1e-12)
    zero = sf.gaussian_filter(z, 1 / FS, 0.8, end="zero")
    assert zero[0] == pytest.approx(2.0, rel=0.01)  # half the kernel outside: falls off


def test_segment_rms_of_a_known_signal():
    # sinusoid with a whole number of periods per 0.25 mm segment: RMS = a/sqrt(2) exactly
    z = 2.0 * np.sin(2 * np.pi * 20.0 * X) + 5.0  # offset removed per segment
    assert segment_rms(z, FS, 0.25) == pytest.approx(2.0 / np.sqrt(2), rel=1e-10)
    # one period per 2.5 mm segment
    z2 = 1.5 * np.cos(2 * np.pi * 0.4 * X)
    assert segment_rms(z2, FS, 2.5) == pytest.approx(1.5 / np.sqrt(2), rel=1e-10)


def test_amplitude_parameters_of_a_sinusoid():
    r = 0.8 * np.sin(2 * np.pi * 40.0 * X)
    p = sf.amplitude_parameters(np.zeros(N), r, 1 / FS, 0.25)
    assert p["Rq_um"] == pytest.approx(0.8 / np.sqrt(2), rel=1e-3)
    assert p["Ra_um"] == pytest.approx(0.8 * 2 / np.pi, rel=1e-2)  # 20 samples per period
    assert p["Rz_um"] == pytest.approx(1.6, rel=1e-3)


def test_analyse_profile_recovers_split_components():
    rng = np.random.default_rng(1)
    wav = 4.0 * np.cos(2 * np.pi * 0.4 * X)  # cosines: orthogonal to the tilt line
    rough = 0.3 * np.cos(2 * np.pi * 60.0 * X)
    z = wav + rough + 2.0 * X + 3.0 + rng.normal(0, 0.005, N)
    ds = sf.analyse_profile(X, z, {"lambda_c_mm": 0.5})
    assert float(ds.tilt_um_per_mm) == pytest.approx(2.0, abs=0.05)
    assert float(ds.waviness_rms_um) == pytest.approx(4.0 / np.sqrt(2), rel=0.06)
    assert float(ds.roughness_rms_um) == pytest.approx(0.3 / np.sqrt(2), rel=0.05)
    pk = sf.profile_peaks(ds, sf.settings({}))
    assert pk.loc[pk.band == "waviness", "f_spatial_per_mm"].iloc[0] == pytest.approx(0.4)
    assert 60.0 in pk.loc[pk.band == "roughness", "f_spatial_per_mm"].round(6).tolist()
    # sanity flags: the resolution of each band's spectrum, nothing flagged here
    L = N / FS
    wv = pk[pk.band == "waviness"].iloc[0]
    assert wv["resolution_per_mm"] == pytest.approx(1 / L)
    assert not pk.loc[pk.band == "roughness", "below_resolution"].any()
    assert bool(wv["below_resolution"]) is (0.4 * L < sf.settings({})["min_peak_cycles"])


@pytest.mark.parametrize(("length_mm", "flagged"), [(4.0, True), (6.0, False), (15.0, False),
                                                     (40.0, False)])
def test_waviness_peak_of_a_short_profile_is_flagged(length_mm, flagged):
    """Known truth: a 0.5 1/mm waviness in profiles of 4–40 mm; fewer than 2.5 periods in the
    profile (L < 5 mm: half a bin beyond the 20 % matching tolerance) is flagged below the
    record's resolution 1/L."""
    x = np.arange(int(length_mm * 200)) / 200.0
    z = 3.0 * np.cos(2 * np.pi * 0.5 * x) + 0.2 * np.cos(2 * np.pi * 60.0 * x)
    ds = sf.analyse_profile(x, z, {"lambda_c_mm": 0.5})
    pk = sf.profile_peaks(ds, sf.settings({}))
    wv = pk[pk.band == "waviness"]
    assert len(wv) >= 1
    assert wv["resolution_per_mm"].iloc[0] == pytest.approx(1 / length_mm, rel=1e-2)
    top = wv.sort_values("power_um2").iloc[-1]
    assert bool(top["below_resolution"]) is flagged


def test_mechanism_attribution():
    feeds = [1.0, 2.0, 4.0, 8.0]
    cuts = pd.DataFrame({"cut": [f"s1_g{i + 1}_px" for i in range(4)], "set": 1,
                         "direction": "px", "feed_mm_s": feeds})
    rows = []
    for c, v in zip(cuts.cut, feeds, strict=True):
        rows.append({"cut": c, "band": "waviness", "f_spatial_per_mm": 0.45,
                     "amplitude_um": 1.0})
        rows.append({"cut": c, "band": "roughness", "f_spatial_per_mm": 60.0 / v,
                     "amplitude_um": 0.1})
        rows.append({"cut": c, "band": "roughness", "f_spatial_per_mm": 3.0 + v * 1.7,
                     "amplitude_um": 0.05})  # neither: wanders
    out = sf.attribute_mechanisms(pd.DataFrame(rows), cuts)
    assert (out.loc[out.band == "waviness", "mechanism"] == "kinematic").all()
    dyn = out[(out.band == "roughness") & np.isclose(out.f_temporal_hz, 60.0)]
    assert len(dyn) == 4 and (dyn.mechanism == "dynamic").all()
    assert (out.loc[out.amplitude_um == 0.05, "mechanism"] == "unclassified").all()


def test_tables_layout_and_thesis_comparison():
    rows = [{"cut": f"s{s}_g{g}_{d}", "set": s, "segment": g, "direction": d,
             "waviness_rms_um": 1.0} for s in (1, 2, 3) for g in range(1, 6)
            for d in ("py", "px", "my")]
    tab = sf.rms_table(pd.DataFrame(rows), "waviness_rms_um")
    assert list(tab.columns[:3]) == ["s1_px", "s1_py", "s1_my"]
    assert list(tab.columns)[-1] == "s3_my" and list(tab.index) == [1, 2, 3, 4, 5]
    thesis = sf.load_thesis_tables()
    t21 = thesis["table_2_1_waviness_rms_um"]
    assert t21.loc[1, "s1_px"] == 0.61 and t21.loc[5, "s3_my"] == 2.41
    assert thesis["table_2_2_roughness_rms_um"].loc[5, "s3_my"] == 1.74
    cmp_ = sf.compare_with_thesis(t21, t21, "t")
    assert cmp_["within_1.5x"].all() and len(cmp_) == 45


# ---- reader -----------------------------------------------------------------------------
def _write(tmp_path, text, name="p.csv"):
    p = tmp_path / name
    p.write_text(text)
    return p


def _good_rows(n=100, dx=0.00125):
    return "".join(f"{i * dx:.6f},{np.sin(i / 5):.5f}\n" for i in range(n))


def test_reader_reads_a_good_file(tmp_path):
    x, z, fs = read_profile(_write(tmp_path, "x_mm,z_um\n" + _good_rows()))
    assert x.size == 100 and fs == pytest.approx(800.0)


def test_reader_rejects_nan(tmp_path):
    rows = _good_rows().splitlines()
    rows[10] = "0.012500,nan"
    with pytest.raises(RawDataError, match=r"row 12, column z_um"):
        read_profile(_write(tmp_path, "x_mm,z_um\n" + "\n".join(rows) + "\n"))


def test_reader_rejects_non_uniform_x(tmp_path):
    rows = _good_rows().splitlines()
    rows[50] = "0.063000,0.1"
    with pytest.raises(RawDataError, match="not uniformly spaced"):
        read_profile(_write(tmp_path, "x_mm,z_um\n" + "\n".join(rows) + "\n"))


def test_reader_rejects_missing_column(tmp_path):
    with pytest.raises(RawDataError, match="column 'z_um' is missing.*z_mm"):
        read_profile(_write(tmp_path, "x_mm,z_mm\n" + _good_rows()))


def test_gather_surface_puts_planted_cuts_in_plan_order():
    """Two planted profiles, handed over in reverse: metrics, tables and profiles follow the
    plan, the planted waviness is the larger one where it was planted, and a cut outside the
    plan is refused."""
    opts = sf.settings(None)
    x = np.arange(0, 15, 0.002)
    rng = np.random.default_rng(3)
    cuts = pd.DataFrame({"cut": ["s1_g1_py", "s1_g1_px"], "set": [1, 1], "segment": [1, 1],
                         "direction": ["py", "px"], "feed_mm_s": [1.0, 1.0],
                         "depth_mm": [0.25, 0.25]})
    per_cut, peaks = [], []
    for cut, amp in (("s1_g1_px", 1.0), ("s1_g1_py", 3.0)):  # reverse of the plan
        z = amp * np.sin(2 * np.pi * 0.4 * x) + 0.2 * np.sin(2 * np.pi * 20 * x) \
            + 0.01 * rng.standard_normal(x.size)
        ds = sf.analyse_profile(x, z, opts)
        ds.attrs.update({"cut": cut, "feed_mm_s": 1.0})
        per_cut.append(ds)
        pk = sf.profile_peaks(ds, opts)
        pk.insert(0, "cut", cut)
        peaks.append(pk)
    out = sf.gather_surface(per_cut, cuts, peaks, opts)
    assert out["metrics"]["cut"].tolist() == ["s1_g1_py", "s1_g1_px"]
    w = out["metrics"].set_index("cut")["waviness_rms_um"]
    assert w["s1_g1_py"] / w["s1_g1_px"] == pytest.approx(3.0, rel=0.05)
    assert out["profiles"]["cut"].values.tolist() == ["s1_g1_py", "s1_g1_px"]
    assert out["profiles"]["direction"].values.tolist() == ["py", "px"]
    assert list(out["peaks"].columns) == sf.PEAK_TABLE_COLUMNS
    assert set(out["comparison"]["table"]) == {"table_2_1_waviness_rms_um",
                                               "table_2_2_roughness_rms_um"}
    assert out["spectra"].sizes["cut"] == 2
    stray = per_cut[0].copy()
    stray.attrs = {**stray.attrs, "cut": "s9_g9_px"}
    with pytest.raises(ValueError, match="s9_g9_px"):
        sf.gather_surface([*per_cut, stray], cuts, peaks, opts)


def test_a_profile_shorter_than_the_thesis_segments_is_one_segment_and_flagged():
    """A 2.3 mm scan (the real X3P land, 2.58 µm spacing) is shorter than the 2.5 mm waviness
    segment: analysed as one segment, with a flag; a 40 mm profile is not flagged."""
    x = np.arange(879) * 2.58e-3
    z = 0.5 * np.sin(2 * np.pi * x / 0.5)
    ds = sf.analyse_profile(x, z)
    assert "waviness_segment_mm 2.5 mm" in ds.attrs["segment_flag"]
    assert "roughness_segment_mm" not in ds.attrs["segment_flag"]
    assert np.isfinite(float(ds["waviness_rms_um"]))
    seg, capped = sf.segment_lengths_mm(x.size * 2.58e-3, sf.settings(None))
    assert "waviness_segment_mm" in capped and seg["roughness_segment_mm"] == 0.25
    x = np.arange(32000) * 1.25e-3
    assert "segment_flag" not in sf.analyse_profile(x, np.sin(2 * np.pi * x / 0.5)).attrs


def test_gather_surface_of_a_free_design_groups_by_what_varies():
    """A spindle-speed series along -X and a 45 deg pair, no sets or segments: no thesis
    tables, one per-cut table sorted by what varies, the cut's own tooth passing on its
    peaks, and a planted kinematic (fixed spatial frequency) peak found kinematic among the
    cuts of the same path direction."""
    opts = sf.settings(None)
    x = np.arange(0, 15, 0.002)
    rng = np.random.default_rng(5)
    rows = [("n18k_mx_v2", "mx", None, 18000, 2.0), ("n12k_mx_v1", "mx", None, 12000, 1.0),
            ("n12k_mx_v4", "mx", None, 12000, 4.0), ("d45_v1", None, 45.0, 24000, 1.0),
            ("d45_v4", None, 45.0, 24000, 4.0)]
    cuts = pd.DataFrame({"cut": [r[0] for r in rows], "direction": [r[1] for r in rows],
                         "direction_deg": [r[2] for r in rows],
                         "feed_mm_s": [r[4] for r in rows], "depth_mm": 0.25})
    processes = {r[0]: {"spindle_rpm": float(r[3]), "flutes": 3, "tool_diameter_mm": 6.0,
                        "radial_immersion": 0.5, "milling": "down",
                        "direction_deg": 180.0 if r[2] is None else r[2],
                        "feed_per_tooth_mm": r[4] / (3 * r[3] / 60),
                        "tooth_passing_hz": 3 * r[3] / 60} for r in rows}
    per_cut, peaks = [], []
    for cid, *_ in rows:
        z = 2.0 * np.sin(2 * np.pi * 0.4 * x) + 0.01 * rng.standard_normal(x.size)
        ds = sf.analyse_profile(x, z, opts)
        ds.attrs.update({"cut": cid})
        per_cut.append(ds)
        pk = sf.profile_peaks(ds, opts)
        pk.insert(0, "cut", cid)
        peaks.append(pk)
    out = sf.gather_surface(per_cut, cuts, peaks, opts, processes=processes)
    assert "waviness" not in out and "comparison" not in out
    tab = out["by_design"]
    assert list(tab.columns[:3]) == ["path_direction", "spindle_rpm", "feed_mm_s"]
    assert tab["cut"].tolist() == ["d45_v1", "d45_v4", "n12k_mx_v1", "n12k_mx_v4",
                                   "n18k_mx_v2"]
    assert "set" not in out["metrics"] and "milling" in out["metrics"]
    assert out["profiles"]["path_direction"].values.tolist()[3:] == ["45 deg", "45 deg"]
    wav = out["peaks"][out["peaks"]["band"] == "waviness"].set_index("cut")
    assert wav.loc["n12k_mx_v1", "f_spatial_per_mm"] == pytest.approx(0.4, rel=0.05)
    assert set(wav["mechanism"]) == {"kinematic"}
    assert wav.loc["d45_v4", "tooth_passing_hz"] == pytest.approx(1200.0)
    assert wav.loc["d45_v4", "tooth_passing_order"] == pytest.approx(0.4 * 4.0 / 1200.0,
                                                                     rel=0.05)
