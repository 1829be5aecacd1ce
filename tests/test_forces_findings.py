"""Chapter 3.1's findings on the dominant peak (robomill.forces.findings) from planted tables,
and the chapter's sentences following them (src/robomill/data/templates/ch3_forces.yaml)."""

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from robomill.findings import Findings
from robomill.forces.findings import forces_findings
from robomill.pipeline.prose import Prose, load_templates

MODES = pd.DataFrame({"mode": [1, 2, 3], "f_n_hz": [20.0, 60.0, 72.0]})
KW = dict(mode_match_hz=3.0, band_hz=(15.0, 250.0), prominence_db=12.0)


def _peaks(hz):
    return pd.DataFrame({"cut": [f"c{i}" for i in range(len(hz))], "dominant_hz": hz})


def test_every_peak_near_a_mode_passes_with_its_threshold():
    """Peaks 61.0, 59.5, 70.0, 71.0 Hz, one cut without a peak: nearest modes 60, 60, 72, 72
    Hz, offsets 1.0, 0.5, 2.0, 1.0 Hz (max 2.0, median 1.0): all within 3 Hz."""
    f = forces_findings(_peaks([61.0, 59.5, np.nan, 70.0, 71.0]), MODES, **KW).values()
    assert (f["n_cuts"], f["n_dominant"], f["n_dominant_none"]) == (5, 4, 1)
    assert f["dominant_hz_range"] == [59.5, 71.0]
    assert f["mode_offset_max_hz"] == pytest.approx(2.0)
    assert f["mode_offset_median_hz"] == pytest.approx(1.0)
    assert f["modes_hit_hz"] == [60.0, 72.0] and f["modes_hit_cuts"] == [2, 2]
    assert f["verdict_dominant_at_modes"] == "pass" and f["threshold_dominant_at_modes"] == 3.0
    assert f["modes_hz"] == [20.0, 60.0, 72.0]


def test_a_peak_far_from_every_mode_fails_and_the_threshold_decides():
    """A peak at 45 Hz is 15 Hz from the 60 Hz mode: it fails at 3 Hz, passes at 20 Hz."""
    peaks = _peaks([61.0, 45.0])
    f = forces_findings(peaks, MODES, **KW).values()
    assert f["verdict_dominant_at_modes"] == "fail"
    assert f["mode_offset_max_hz"] == pytest.approx(15.0)
    wide = forces_findings(peaks, MODES, **{**KW, "mode_match_hz": 20.0})
    assert wide["dominant_at_modes"].verdict == "pass"
    assert wide["dominant_at_modes"].config_key == "forces.mode_match_hz"


def test_no_modes_or_no_peaks_give_no_verdict():
    f = forces_findings(_peaks([61.0]), None, **KW).values()
    assert f["has_modes"] is False and f["modes_hz"] is None
    assert "verdict_dominant_at_modes" not in f
    f = forces_findings(_peaks([np.nan, np.nan]), MODES, **KW).values()
    assert f["dominant_hz_range"] is None and f["n_dominant"] == 0
    assert "verdict_dominant_at_modes" not in f


def test_chapter_3_1_prose_follows_its_findings():
    """Rendered from altered findings: the numbers and the verdict follow them; no thesis
    explanation is stated as a fact of a study that has no modes or no peaks."""
    say = Prose(load_templates("ch3_forces"), forces_findings(
        _peaks([61.0, 59.5, 70.0]), MODES, **KW))
    text = " ".join(say("dominant", "modes", "verdict", ref_peaks="[T]").split())
    assert "lies between **59.5 and 70.0 Hz**" in text and "15–250 Hz" in text
    assert "within 3 Hz of an identified mode" in text and "20.0, 60.0, 72.0 Hz" in text
    far = " ".join(Prose(load_templates("ch3_forces"), forces_findings(
        _peaks([61.0, 45.0]), MODES, **KW))("verdict").split())
    assert "more than 3 Hz" in far and "up to 15.0 Hz" in far and "chip load" not in far
    bare = Prose(load_templates("ch3_forces"), forces_findings(_peaks([202.8]), None, **KW))
    text = " ".join(bare("dominant", "modes", "verdict", "no_match", "no_modes",
                         ref_peaks="[T]").split())
    assert "202.8" in text and "no impact test" in text and "chip load" not in text
    none = Prose(load_templates("ch3_forces"), forces_findings(_peaks([np.nan]), MODES, **KW))
    text = " ".join(none("dominant", "no_match", ref_peaks="[T]").split())
    assert "**none** in every cut" in text and "none is matched" in text
    assert "not compared" in Prose(load_templates("ch3_forces"), Findings("forces"))("against")


# --- the records, the kinematic peak, the levels and the coefficients ---------

SETTINGS = {"figure_set": 2, "full_band_min_hz": 500.0, "kinematic_band_per_mm": [0.3, 1.0],
            "kinematic_prominence_db": 10.0, "min_peak_cycles": 10.0, "lowband_hz": 250.0,
            "confidence": 0.9}
FREQ = np.arange(0.0, 5001.0, 10.0)  # 10 Hz lines up to 5 kHz


def _spectra(cut_sets=(1, 1, 2, 2), directions=("py", "px", "py", "px")):
    """Four cuts, sets 1, 1, 2, 2; every PSD flat at 1 with a line of 50 at 400 Hz (below
    full_band_min_hz) and, in the first cut of set 2 (c2), a line of 9 at 3000 Hz: three
    times its tooth passing of 1000 Hz; in c0 a line of 6 at 2000 Hz. The spatial axis of c0
    has lines 0.02 mm⁻¹ apart."""
    n = len(cut_sets)
    psd = np.ones((n, 3, FREQ.size))
    psd[:, :, FREQ == 400.0] = 50.0
    psd[2, :, FREQ == 3000.0] = 3.0  # summed over the three axes: 9
    psd[0, :, FREQ == 2000.0] = 2.0
    return xr.Dataset(
        {"psd": (("cut", "axis", "frequency"), psd),
         "n_samples": ("cut", [100, 200, 300, 400]),
         "tooth_passing_hz": ("cut", [1000.0, 1000.0, 1000.0, 1500.0]),
         "f_spatial_low": (("cut", "lf_bin"), np.tile(np.arange(5) * 0.02, (n, 1))),
         "feed_mm_s": ("cut", [2.0, 4.0, 2.0, 4.0]),
         "set": ("cut", list(cut_sets)), "direction": ("cut", list(directions))},
        coords={"cut": [f"c{i}" for i in range(n)], "axis": ["Fx", "Fy", "Fz"],
                "frequency": FREQ, "lf_bin": np.arange(5)})


def _means():
    """Cut c3 is down milling at a_e/D 0.5 with 3 flutes, the others 2-flute slots."""
    return pd.DataFrame({
        "cut": ["c0", "c1", "c2", "c3"], "direction": ["py", "px", "py", "px"],
        "feed_mm_s": [2.0, 4.0, 2.0, 4.0], "depth_mm": [0.5, 0.5, 1.0, 1.0],
        "feed_per_tooth_mm": [0.01, 0.02, 0.01, 0.02],
        "F_feed_N": [-3.0, -1.0, -2.0, -4.5], "F_cross_feed_N": [2.0, 5.0, 3.0, 4.0],
        "F_axial_N": [0.5, 0.7, 0.6, 0.9], "spindle_rpm": [30000.0] * 4,
        "flutes": [2, 2, 2, 3], "radial_immersion": [1.0, 1.0, 1.0, 0.5],
        "milling": ["slot", "slot", "slot", "down"]})


def _coefficients(ktc=105.0, krc=-2.0, residual=(0.1, 0.1)):
    flags = pd.DataFrame({"negative": [ktc < 0, krc < 0],
                          "fit_residual_rms_N": list(residual), "fit_signal_rms_N": [1.0, 1.0]})
    flags["residual_exceeds_signal"] = flags["fit_residual_rms_N"] > flags["fit_signal_rms_N"]
    flags["physical"] = ~(flags["negative"] | flags["residual_exceeds_signal"])
    return pd.concat([pd.DataFrame({"name": ["Ktc", "Krc"], "value": [ktc, krc],
                                    "ci_low": [ktc - 1, krc - 1], "ci_high": [ktc + 1, krc + 1],
                                    "unit": ["N/mm^2", "N/mm^2"]}), flags], axis=1)


def _kin_peaks():
    """Kinematic peaks 0.5, none, 0.4, 0.6 mm⁻¹; c1 (no peak) and c2 (0.4) flagged below the
    resolution: only c2 counts (a flagged empty peak is no peak)."""
    return pd.DataFrame({"cut": ["c0", "c1", "c2", "c3"], "dominant_hz": [70.0] * 4,
                         "kinematic_per_mm": [0.5, np.nan, 0.4, 0.6],
                         "kinematic_resolution_per_mm": [0.02, 0.05, 0.05, 0.02],
                         "kinematic_below_resolution": [False, True, True, False]})


def _all(thesis_design=True, **kw):
    args = dict(spectra=_spectra(), means=_means(), coefficients=_coefficients(),
                design={"design": "4 cuts: 2 depths", "grouping": ["depth_mm"]},
                planted={"Ktc": 100.0, "Krc": -2.04}, experiment={"flutes": 2},
                settings=SETTINGS, thesis_design=thesis_design)
    args.update(kw)
    return forces_findings(_kin_peaks(), MODES, **KW, **args)


def test_records_and_the_full_band_peak_of_the_figures_first_cut():
    """Set 2 is shown (c2, c3): its first cut's largest line above 500 Hz is 3000 Hz, 3.0
    times its tooth passing; the stronger 400 Hz line lies below the threshold."""
    v = _all().values()
    assert v["n_samples_total"] == 1000
    assert v["tooth_passing_hz_values"] == [1000.0, 1500.0]
    assert v["thesis_layout"] is True and v["figure_set"] == 2
    assert v["figure_cuts"] == ["c2", "c3"] and v["figure_directions"] == ["py", "px"]
    assert v["full_band_peak_cut"] == "c2" and v["full_band_peak_hz"] == 3000.0
    assert v["full_band_peak_harmonic"] == pytest.approx(3.0)
    assert v["full_band_min_hz"] == 500.0 and v["lowband_hz"] == 250.0
    assert (v["model_flutes"], v["model_milling"]) == (2, "slot")
    low = _all(settings={**SETTINGS, "full_band_min_hz": 300.0}).values()
    assert low["full_band_peak_hz"] == 400.0  # the threshold decides


def test_figure_cuts_without_the_set_or_for_another_design():
    """A figure_set the study lacks falls back to its largest set; any other design shows
    every cut, directions in order of appearance."""
    v = _all(settings={**SETTINGS, "figure_set": 7}).values()
    assert v["figure_set"] == 2 and v["figure_cuts"] == ["c2", "c3"]
    other = _all(thesis_design=False).values()
    assert other["thesis_layout"] is False and other["figure_set"] is None
    assert other["figure_cuts"] == ["c0", "c1", "c2", "c3"]
    assert other["full_band_peak_cut"] == "c0" and other["full_band_peak_hz"] == 2000.0
    assert other["full_band_peak_harmonic"] == pytest.approx(2.0)


def test_kinematic_peak_and_its_resolution_flag():
    """Median of 0.5, 0.4, 0.6 is 0.5; one cut none; c2 flagged: fail at 10 cycles, with
    ±5 % (half a bin of 10 cycles) and 10 / 0.4 = 25 mm needed."""
    found = _all()
    v = found.values()
    assert (v["n_kinematic"], v["n_kinematic_none"]) == (3, 1)
    assert v["kinematic_per_mm_median"] == pytest.approx(0.5)
    assert v["kinematic_per_mm_range"] == [0.4, 0.6]
    assert v["resolution_per_mm"] == pytest.approx(0.02) and v["resolution_feed_mm_s"] == 2.0
    assert v["n_kinematic_below_resolution"] == 1
    assert v["verdict_n_kinematic_below_resolution"] == "fail"
    assert found["n_kinematic_below_resolution"].config_key == "forces.min_peak_cycles"
    assert v["threshold_n_kinematic_below_resolution"] == 10.0
    assert v["kinematic_below_resolution"][0].startswith("c2 (0.40")
    assert v["kinematic_uncertainty_pct"] == pytest.approx(5.0)
    assert v["kinematic_record_needed_mm"] == pytest.approx(25.0)
    clean = _kin_peaks().assign(kinematic_below_resolution=False)
    ok = forces_findings(clean, MODES, **KW, settings=SETTINGS).values()
    assert ok["verdict_n_kinematic_below_resolution"] == "pass"
    assert ok["kinematic_record_needed_mm"] is None


def test_levels_design_and_engagement():
    v = _all().values()
    assert v["F_feed_N_range"] == [-4.5, -1.0]
    assert v["F_cross_feed_N_range"] == [2.0, 5.0]
    assert v["F_axial_N_range"] == [0.5, 0.9]
    assert v["all_slot"] is False
    assert v["millings"] == ["down milling, a_e/D 0.5", "slot milling, a_e/D 1"]
    assert v["design"] == "4 cuts: 2 depths" and v["grouping"] == ["depth_mm"]
    assert "design" not in _all(design=None).values()


def test_coefficients_their_flags_and_the_planted_error():
    """Ktc 105 against 100 planted: +5 %; Krc −2 against −2.04: −1.96 %; Krc negative is
    not physical."""
    v = _all().values()
    assert v["coefficient_Ktc"] == 105.0 and v["coefficient_Ktc_ci"] == [104.0, 106.0]
    assert v["confidence_pct"] == pytest.approx(90.0)
    assert v["n_coefficients"] == 2 and v["n_not_physical"] == 1
    assert v["not_physical"][0].startswith("Krc is negative")
    assert v["planted_error_pct_max"] == pytest.approx(5.0)
    assert v["planted_error_worst"] == "Ktc"
    loose = _all(coefficients=_coefficients(krc=2.0, residual=(0.1, 3.0)),
                 planted=None).values()
    assert loose["n_not_physical"] == 1 and "not resolved" in loose["not_physical"][0]
    assert "planted_error_pct_max" not in loose
    assert _all(coefficients=_coefficients(krc=2.0)).values()["n_not_physical"] == 0


def test_a_partial_study_gives_the_findings_it_can():
    """Peaks alone (no spectra, means, coefficients): the dominant and kinematic findings, no
    record, level or coefficient finding, and the chapter's sentences render or stay out."""
    found = forces_findings(_kin_peaks(), None, **KW)
    v = found.values()
    assert v["n_kinematic"] == 3 and "full_band_peak_hz" not in v and "design" not in v
    assert "coefficient_Ktc" not in v and "n_kinematic_below_resolution" not in v
    say = Prose(load_templates("ch3_forces"), found)
    text = say(*say.templates, ref_peaks="[T]", ref_record="[R]", ref_full_band_psd="[P]",
               ref_spatial="[S]", ref_time="[t]", ref_model_force_shape="[M]",
               ref_harmonics="[H]", ref_mean_forces_vs_feed="[F]", ref_coefficients="[C]",
               which="set 1", direction="+X", shape="slot")
    assert "{" not in text and "Ktc =" not in text and "10 periods" not in text
