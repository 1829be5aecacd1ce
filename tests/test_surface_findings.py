"""Chapter 2's findings (robomill.surface.findings) from planted artefacts: every value below
is written by hand from the planted tables, not computed with the library's code."""

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from robomill.findings import read_findings, write_findings
from robomill.surface.findings import surface_findings
from robomill.surface.options import settings

SETTINGS = settings({"temporal_quantiles": [0.25, 0.75]})


def _metrics():
    """Five cuts, set 2 first in the plan; waviness 8 − feed and roughness 0.1 × feed
    exactly (correlation −1 and +1)."""
    return pd.DataFrame({
        "cut": ["s2_g1_px", "s1_g1_py", "s1_g1_px", "s1_g2_py", "s1_g2_px"],
        "set": [2, 1, 1, 1, 1], "segment": [1, 1, 1, 2, 2],
        "direction": ["px", "py", "px", "py", "px"],
        "feed_mm_s": [6.0, 2.0, 2.0, 4.0, 4.0],
        "tilt_um_per_mm": [0.3, -0.5, 1.0, 0.1, 0.2],
        "waviness_rms_um": [2.0, 6.0, 6.0, 4.0, 4.0],
        "roughness_rms_um": [0.6, 0.2, 0.2, 0.4, 0.4],
        "Ra_um": [0.5, 0.45, 0.15, 0.7, 0.25]})


def _peaks(below=True):
    """Waviness: 3 kinematic (0.4, 0.5, 0.45 mm⁻¹ at 2, 4, 6 mm/s), 1 unclassified;
    roughness: 5 dynamic (50 … 90 Hz), 1 kinematic; one roughness peak below resolution."""
    rows = [("s1_g1_px", "waviness", "kinematic", 0.4, 2.0),
            ("s1_g2_px", "waviness", "kinematic", 0.5, 4.0),
            ("s2_g1_px", "waviness", "kinematic", 0.45, 6.0),
            ("s1_g1_py", "waviness", "unclassified", 0.7, 2.0)]
    rows += [("s1_g1_py", "roughness", "dynamic", f / 2.0, 2.0) for f in (50.0, 70.0, 90.0)]
    rows += [("s1_g2_py", "roughness", "dynamic", f / 4.0, 4.0) for f in (60.0, 80.0)]
    rows += [("s1_g2_px", "roughness", "kinematic", 8.0, 4.0)]
    df = pd.DataFrame(rows, columns=["cut", "band", "mechanism", "f_spatial_per_mm",
                                     "feed_mm_s"])
    df["f_temporal_hz"] = df["f_spatial_per_mm"] * df["feed_mm_s"]
    df["resolution_per_mm"] = np.where(df["band"] == "waviness", 0.1, 4.0)
    if below:
        df["below_resolution"] = [False] * 4 + [True] + [False] * 5
    return df


PROFILES = xr.Dataset(coords={"x": np.linspace(0.0, 10.0, 2001)})  # 0.005 mm: 200 mm⁻¹


def _recovery():
    return pd.DataFrame({"waviness_ratio": [0.9, 0.95, 1.02],
                         "roughness_ratio": [1.0, 1.05, 0.98]})


def _comparison():
    return pd.DataFrame({
        "table": ["table_2_1_waviness_rms_um"] * 3 + ["table_2_2_roughness_rms_um"] * 2,
        "ratio": [1.0, 1.2, 2.0, 0.8, 0.5], "within_1.5x": [True, True, False, True, False]})


def _thesis(**kw):
    args = dict(settings=SETTINGS, thesis_layout=True, synthetic=True, design="5 cuts",
                comparison=_comparison(), recovery=_recovery())
    return surface_findings(_metrics(), _peaks(), PROFILES, **{**args, **kw})


def test_measured_and_the_example_cuts():
    v = _thesis().values()
    assert (v["n_profiles"], v["n_samples"]) == (5, 2001)
    assert v["sampling_per_mm"] == pytest.approx(200.0)
    assert v["profile_length_mm"] == pytest.approx(10.0)
    assert v["lambda_c_mm"] == 0.5 and v["filter_end"] == "renormalize"
    assert v["synthetic"] and v["thesis_layout"] and v["design"] == "5 cuts"
    assert v["example_cut"] == "s1_g1_py" and v["example_tilt_um_per_mm"] == -0.5
    # the first cut's direction (+X): lowest feed 2 mm/s, highest 6 mm/s
    assert (v["low_feed_cut"], v["high_feed_cut"]) == ("s1_g1_px", "s2_g1_px")
    assert (v["low_feed_mm_s"], v["high_feed_mm_s"]) == (2.0, 6.0)
    assert v["directions"] == ["px", "py"] and v["direction_labels"] == ["+X", "+Y"]
    assert v["profiles_set"] == 1 and v["sets"] == [1, 2]


def test_rms_by_direction_and_against_feed():
    v = _thesis().values()
    assert v["waviness_rms_um_range"] == [2.0, 6.0]
    assert v["roughness_rms_um_range"] == [0.2, 0.6]
    assert v["Ra_um_range"] == [0.15, 0.7]
    # +X: (2 + 6 + 4) / 3 = 4, +Y: (6 + 4) / 2 = 5; roughness +X 0.4, +Y 0.3
    assert v["waviness_by_direction_labels"] == ["+X", "+Y"]
    assert v["waviness_by_direction_um"] == pytest.approx([4.0, 5.0])
    assert (v["smallest_waviness_direction"], v["largest_waviness_direction"]) == ("+X", "+Y")
    assert v["roughness_by_direction_labels"] == ["+Y", "+X"]
    assert v["roughness_by_direction_um"] == pytest.approx([0.3, 0.4])
    assert v["feed_correlation_waviness"] == pytest.approx(-1.0)
    assert v["feed_correlation_roughness"] == pytest.approx(1.0)


def test_peaks_their_mechanism_and_the_threshold_that_decides_it():
    f = _thesis()
    v = f.values()
    assert (v["n_peaks"], v["n_waviness_peaks"], v["n_roughness_peaks"]) == (10, 4, 6)
    assert v["n_kinematic_waviness"] == 3 and v["n_dynamic_roughness"] == 5
    assert v["kinematic_wavelength_mm"] == pytest.approx(1 / 0.45)
    assert v["kinematic_f_range_per_mm"] == [0.4, 0.5]
    assert v["kinematic_feed_range_mm_s"] == [2.0, 6.0]
    assert v["dynamic_hz_spread"] == pytest.approx([60.0, 80.0])  # quartiles of 50 … 90
    assert v["temporal_quantiles_pct"] == [25.0, 75.0]
    assert v["waviness_kinematic_share"] == 0.75 and v["waviness_dynamic_share"] == 0.0
    # the peak below resolution (a dynamic one) is no evidence: 4 dynamic of 5 resolved
    assert v["roughness_dynamic_share"] == pytest.approx(4 / 5)
    assert v["roughness_kinematic_share"] == pytest.approx(1 / 5)
    assert v["verdict_waviness_mechanism"] == "kinematic"
    assert v["verdict_roughness_mechanism"] == "dynamic"
    assert v["threshold_waviness_mechanism"] == 0.5
    assert f["waviness_mechanism"].config_key == "surface.mechanism_share_min"
    strict = _thesis(settings={**SETTINGS, "mechanism_share_min": 0.8}).values()
    assert strict["verdict_waviness_mechanism"] == "mixed"  # 0.75 < 0.8
    assert strict["verdict_roughness_mechanism"] == "dynamic"  # 4/5 ≥ 0.8
    stricter = _thesis(settings={**SETTINGS, "mechanism_share_min": 0.85}).values()
    assert stricter["verdict_roughness_mechanism"] == "mixed"
    assert (v["match_tolerance"], v["min_feed_ratio"]) == (0.2, 1.5)


def test_peaks_below_resolution_are_no_evidence_of_a_mechanism():
    """Every waviness peak below resolution: the waviness has no mechanism ('none'), as in a
    study of 5 mm profiles whose 2.5 mm waviness has two periods."""
    peaks = _peaks()
    peaks["below_resolution"] = peaks["band"] == "waviness"
    v = surface_findings(_metrics(), peaks, PROFILES, settings=SETTINGS, thesis_layout=True,
                         synthetic=True).values()
    assert v["verdict_waviness_mechanism"] == "none"
    assert v["waviness_kinematic_share"] is None
    assert v["n_kinematic_waviness"] == 3  # still counted, and flagged
    assert v["n_below_resolution_waviness"] == 4
    assert v["roughness_dynamic_share"] == pytest.approx(5 / 6)


def test_resolution_flag_fails_with_its_threshold():
    f = _thesis()
    v = f.values()
    assert v["n_below_resolution"] == 1 and v["n_below_resolution_roughness"] == 1
    assert v["n_below_resolution_waviness"] == 0
    assert v["below_resolution_example_cut"] == "s1_g1_py"
    assert v["below_resolution_example_per_mm"] == 25.0  # 50 Hz at 2 mm/s
    assert v["below_resolution_example_resolution_per_mm"] == 4.0
    assert v["verdict_peaks_resolved"] == "fail" and v["threshold_peaks_resolved"] == 2.5
    assert f["peaks_resolved"].config_key == "surface.min_peak_cycles"
    assert v["below_resolution_precision_pct"] == 20.0  # 50 % of a bin / 2.5 periods
    ok = surface_findings(_metrics(), _peaks().assign(below_resolution=False), PROFILES,
                          settings=SETTINGS, thesis_layout=True, synthetic=True).values()
    assert ok["verdict_peaks_resolved"] == "pass" and ok["n_below_resolution"] == 0


def test_recovery_and_the_thesis_tables():
    v = _thesis().values()
    assert v["has_recovery"] and v["recovery_waviness_ratio_range"] == [0.9, 1.02]
    assert v["recovery_roughness_ratio_range"] == [0.98, 1.05]
    assert v["recovery_waviness_worst_pct"] == pytest.approx(10.0)
    assert v["recovery_roughness_worst_pct"] == pytest.approx(5.0)
    assert v["recovery_waviness_below_planted"] == 2
    assert v["has_thesis_tables"] and v["thesis_factor"] == 1.5
    assert (v["waviness_cells_within"], v["waviness_cells"]) == (2, 3)
    assert (v["roughness_cells_within"], v["roughness_cells"]) == (1, 2)
    assert v["waviness_median_ratio"] == 1.2 and v["roughness_median_ratio"] == 0.65


def test_a_free_design_and_missing_optional_inputs():
    """A free design (path_direction, no set): every cut per direction; no recovery, no
    comparison, no sanity flag, no peaks and one feed: said, not failed."""
    m = _metrics().drop(columns=["set", "segment", "direction"]).assign(
        path_direction=["45 deg", "px", "45 deg", "px", "px"], feed_mm_s=3.0)
    peaks = _peaks(below=False).iloc[:0]
    v = surface_findings(m, peaks, PROFILES, settings=SETTINGS, thesis_layout=False,
                         synthetic=False).values()
    assert v["directions"] == ["45 deg", "px"] and v["direction_labels"] == ["45°", "+X"]
    assert v["profiles_set"] is None and v["sets"] is None
    assert v["example_cut"] == "s2_g1_px"  # the plan's first
    assert v["feed_correlation_waviness"] is None and v["feed_correlation_roughness"] is None
    assert v["n_peaks"] == 0 and v["kinematic_wavelength_mm"] is None
    assert v["dynamic_hz_spread"] is None
    assert v["verdict_waviness_mechanism"] == "none"
    assert not v["has_resolution_flag"] and "verdict_peaks_resolved" not in v
    assert not v["has_recovery"] and not v["has_thesis_tables"]
    assert not v["synthetic"] and v["design"] is None


def test_findings_survive_their_yaml(tmp_path):
    f = _thesis()
    write_findings(f, tmp_path / "findings.yaml")
    back = read_findings(tmp_path / "findings.yaml")
    assert back.values().keys() == f.values().keys()
    assert back["waviness_mechanism"].verdict == "kinematic"
    assert back.values()["kinematic_f_range_per_mm"] == [0.4, 0.5]
    assert back["example_tilt_um_per_mm"].artefact == "results/surface/metrics.csv"
