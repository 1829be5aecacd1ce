"""Chapter 3.2's findings (robomill.straightness.findings) from planted runs and peaks, and
the chapter's sentences following them (src/robomill/data/templates/ch3_straightness.yaml)."""

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from robomill.findings import Findings
from robomill.pipeline.prose import Prose, load_templates
from robomill.straightness.findings import quiet_band, straightness_findings

KW = dict(surface_band_per_mm=(7.0, 9.0), fmax_store_per_mm=20.0, threshold=25.0)


def _profiles(line_at_8=True):
    """Two runs, +Y at 2 and 10 mm/s: a flat floor of 1 µm², run a with a 400 µm² line at
    8 mm⁻¹ (inside the surface band) when ``line_at_8``."""
    f = np.arange(0.0, 20.0 + 1e-9, 0.01)
    power = np.ones((2, f.size))
    if line_at_8:
        power[0, np.argmin(np.abs(f - 8.0))] = 400.0
    return xr.Dataset({"power_um2": (("run", "f"), power)},
                      coords={"run": ["a", "b"], "f": f, "direction": ("run", ["py", "py"]),
                              "feed_mm_s": ("run", [2.0, 10.0])})


def _peaks(line_at_8=True):
    rows = [("py", 2.0, 0.50, 1.0, 2.0, "gear"), ("py", 2.0, 0.45, 0.9, 0.5, "gear"),
            ("py", 10.0, 0.45, 4.5, 3.0, "gear"),
            ("py", 2.0, 6.5, 13.0, 1.5, "temporal"), ("py", 10.0, 1.3, 13.0, 1.7, "temporal")]
    if line_at_8:
        rows.append(("py", 2.0, 8.0, 16.0, 28.0, "unclassified"))
    out = pd.DataFrame(rows, columns=["direction", "feed_mm_s", "f_spatial_per_mm",
                                      "f_temporal_hz", "amplitude_um", "mechanism"])
    return out.assign(run=np.where(out["feed_mm_s"] == 2.0, "a", "b"))


def test_findings_from_planted_runs():
    """By hand: gear peaks 0.45–0.50 mm⁻¹; the largest gear peak of each run at 0.50 (run a,
    2 µm) and 0.45 mm⁻¹ (run b): wavelengths 2.0 and 2.22 mm; two temporal peaks at 13 Hz
    (wavelengths 1/6.5 and 1/1.3 mm); one peak in the 7–9 mm⁻¹ band: the motion has a
    component there; the quiet band is 18–20 mm⁻¹."""
    f = straightness_findings(_profiles(), _peaks(), **KW).values()
    assert (f["n_runs"], f["feeds_mm_s"]) == (2, [2.0, 10.0])
    assert f["n_gear_peaks"] == 3 and f["gear_f_range_per_mm"] == [0.45, 0.5]
    assert f["gear_main_wavelength_mm_range"] == pytest.approx([2.0, 1 / 0.45])
    assert (f["n_temporal"], f["temporal_hz_mean"], f["temporal_hz_std"]) == (2, 13.0, 0.0)
    assert f["temporal_wavelength_mm_range"] == pytest.approx([1 / 6.5, 1 / 1.3])
    assert f["quiet_band_per_mm"] == [18.0, 20.0] == list(quiet_band((7.0, 9.0), 20.0))
    assert f["n_surface_band_peaks"] == 1 and f["verdict_motion_in_surface_band"] == "peaks"
    assert f["threshold_motion_in_surface_band"] == 25.0
    assert f["surface_band_peak_to_floor_max"] == pytest.approx(400.0)
    assert f["quiet_band_peak_to_floor_range"] == pytest.approx([1.0, 1.0])


def test_a_quiet_surface_band_gives_the_verdict_none():
    f = straightness_findings(_profiles(False), _peaks(False), **KW).values()
    assert f["n_surface_band_peaks"] == 0 and f["verdict_motion_in_surface_band"] == "none"


def test_chapter_3_2_prose_follows_its_findings():
    say = Prose(load_templates("ch3_straightness"),
                straightness_findings(_profiles(), _peaks(), **KW))
    text = " ".join(say("gear_peaks", "surface_band", "surface_band_verdict", "temporal",
                        ref_band_floor="[T]").split())
    assert "3 peaks are attributed to a gear element" in text
    assert "between 0.450 and 0.500 mm⁻¹" in text and "2.00–2.22 mm" in text
    assert "the 2 runs have 1 peak(s)" in text and "400.0× the noise floor" in text
    assert "needs 25× its band median" in text and "has components there" in text
    assert "13.00 ± 0.00 Hz" in text
    quiet = Prose(load_templates("ch3_straightness"), straightness_findings(_profiles(False),
                                                                 _peaks(False), **KW))
    assert "no component there" in quiet("surface_band_verdict")
    none = Prose(load_templates("ch3_straightness"), Findings("straightness"))
    assert "No peak is attributed" in none("gear_peaks") and "not compared" in none("against")


def _rich_profiles():
    """Three runs by hand: +X at 2 mm/s, +Y at 2 and 10 mm/s; lengths 40, 40, 10 mm
    (1/L 0.025, 0.025, 0.1 mm⁻¹); measured speeds 2.02, 2.0, 9.9 mm/s; run c has no time
    base; lateral deviation ±1 µm (RMS 1), vertical ±2, ±3, ±4 µm (RMS 2, 3, 4)."""
    f = np.arange(0.0, 20.0 + 1e-9, 0.01)
    dev = np.empty((3, 2, 4))
    dev[:, 0] = [1.0, -1.0, 1.0, -1.0]
    for k, a in enumerate((2.0, 3.0, 4.0)):
        dev[k, 1] = [a, -a, a, -a]
    return xr.Dataset(
        {"power_um2": (("run", "f"), np.ones((3, f.size))),
         "deviation_um": (("run", "component", "s"), dev)},
        coords={"run": ["a", "b", "c"], "f": f, "component": ["lateral", "vertical"],
                "s": [0.0, 1.0, 2.0, 3.0], "direction": ("run", ["px", "py", "py"]),
                "feed_mm_s": ("run", [2.0, 2.0, 10.0]),
                "length_mm": ("run", [40.0, 40.0, 10.0]),
                "resolution_per_mm": ("run", [0.025, 0.025, 0.1]),
                "speed_mm_s": ("run", [2.02, 2.0, 9.9]),
                "time_base": ("run", ["time", "time", "none"])})


def _rich_peaks():
    """Five peaks: two gear peaks of run a (0.5 mm⁻¹; 0.3 mm⁻¹, merged: two candidates),
    one gear peak of run b (0.7 mm⁻¹), a spatial and an unclassified peak."""
    return pd.DataFrame({
        "run": ["a", "a", "b", "b", "c"], "direction": ["px", "px", "py", "py", "py"],
        "feed_mm_s": [2.0, 2.0, 2.0, 2.0, 10.0], "cut": ["k1", "k1", "k2", "k2", "k3"],
        "f_spatial_per_mm": [0.5, 0.3, 0.7, 1.5, 2.5], "f_temporal_hz": [1.0, 0.6, 1.4, 3, 25],
        "amplitude_um": [1.0, 0.5, 2.0, 0.4, 0.3],
        "mechanism": ["gear", "gear", "gear", "spatial", "unclassified"],
        "merged": [False, True, False, False, False],
        "candidates": ["", "2:motor:mesh;3:reducer_input:mesh", "", "", ""]})


def _truth_check():
    """Six planted elements: 3 above the noise (2 found, 1 merged into 2:motor:mesh), one
    marginal found, one below the noise attributed (a false attribution), one out of band."""
    return pd.DataFrame({
        "direction": ["px"] * 6, "feed_mm_s": [2.0] * 6, "joint": [1, 2, 3, 4, 5, 6],
        "stage": ["motor", "motor", "reducer_input", "motor", "motor", "motor"],
        "order": ["mesh"] * 6,
        "class": ["above_noise", "above_noise", "above_noise", "marginal", "below_noise",
                  "out_of_band"],
        "found": [True, True, False, True, True, False],
        "merged": [False, False, True, False, False, False],
        "merged_into": ["", "", "2:motor:mesh", "", "", ""],
        "false_attribution": [False, False, False, False, True, False]})


RICH = dict(KW, tol_bins=0.5, fmin_cycles=2.5, truth_margin=3.0)


def test_findings_of_the_runs_surface_runs_and_truth():
    """By hand: feeds 2 and 10 mm/s; not the thesis' design: directions sorted (px, py), all
    in the deviation section; mean length 30 mm, mean 1/L 0.05 mm⁻¹; the largest speed error
    1 % (2.02 against 2); 5 peaks: 3 gear, 1 spatial, 1 unclassified; run c untimed. Surface
    peaks of resolution 0.0667 mm⁻¹ (coarser than every run's 1/L but c's 0.1): tolerance
    0.5 × 0.1 = 0.05 mm⁻¹; surface peaks of cut k1 at 0.52 and of k2 at 0.8 mm⁻¹: the 0.5
    gear peak is on the surface, 0.3 and 0.7 are not. RMS lateral 1–1 µm, vertical 2–4 µm.
    Truth: 6 elements, 3 above noise, 2 found, 1 merged, 0 missed, 1 marginal found, 1 false
    attribution."""
    surface = pd.DataFrame({"cut": ["k1", "k2"], "f_spatial_per_mm": [0.52, 0.8],
                            "resolution_per_mm": [1 / 15, 1 / 15]})
    f = straightness_findings(_rich_profiles(), _rich_peaks(), surface_peaks=surface,
                              truth_check=_truth_check(), thesis_design=False,
                              **RICH).values()
    assert f["feed_range_mm_s"] == [2.0, 10.0] and not f["thesis_layout"]
    assert f["directions"] == ["px", "py"] and f["direction_labels"] == ["+X", "+Y"]
    assert f["main_directions"] == ["px", "py"] and f["extra_directions"] == []
    assert f["high_band_direction"] == "px"
    assert f["length_mm_mean"] == pytest.approx(30.0)
    assert f["resolution_per_mm_mean"] == pytest.approx(0.05)
    assert f["speed_error_pct_max"] == pytest.approx(1.0)
    assert (f["n_peaks"], f["n_gear_peaks"], f["n_spatial"], f["n_unclassified"]) == (5, 3, 1, 1)
    assert f["untimed_runs"] == ["c"] and "time base" in f["untimed_reason"]
    assert f["has_surface_peaks"] and f["n_surface_peaks"] == 2
    assert f["surface_match_tol_per_mm"] == pytest.approx(0.05)
    assert f["n_gear_on_surface"] == 1
    assert f["n_merged"] == 1 and len(f["merged_peaks"]) == 1
    assert "0.300" in f["merged_peaks"][0] and "3:reducer_input:mesh" in f["merged_peaks"][0]
    assert f["rms_lateral_um_range"] == pytest.approx([1.0, 1.0])
    assert f["rms_vertical_um_range"] == pytest.approx([2.0, 4.0])
    assert f["has_truth"] and (f["truth_margin"], f["fmin_cycles"]) == (3.0, 2.5)
    assert (f["truth_planted_elements"], f["truth_above_noise"], f["truth_found"],
            f["truth_merged"], f["truth_missed"], f["truth_marginal"],
            f["truth_marginal_found"], f["truth_false_attributions"]) == (6, 3, 2, 1, 0, 1, 1, 1)
    assert len(f["truth_merged_elements"]) == 1
    assert f["truth_merged_elements"][0].endswith("→ 2:motor:mesh")
    assert f["ref_dominant_below_per_mm"] == 0.5 and f["ref_dominant_wavelength_min_mm"] == 2.0
    assert f["ref_surface_marks_feeds_mm_s"] == [8.0, 10.0]


def test_thesis_layout_orders_the_directions_as_the_thesis():
    """The thesis' layout: +Y, −Y, then +X after its figures; −Y for the high band."""
    prof = _rich_profiles().assign_coords(direction=("run", ["px", "my", "py"]))
    f = straightness_findings(prof, _rich_peaks(), thesis_design=None, **RICH).values()
    assert f["thesis_layout"] and f["directions"] == ["py", "my", "px"]
    assert f["main_directions"] == ["py", "my"] and f["extra_directions"] == ["px"]
    assert f["high_band_direction"] == "my"


def test_a_partial_study_says_what_is_missing():
    """No surface profiled, no truth, no time base column: the findings say so."""
    prof = _rich_profiles().drop_vars("time_base")
    f = straightness_findings(prof, _rich_peaks().drop(columns=["merged", "candidates"]),
                              **KW).values()
    assert not f["has_surface_peaks"] and "n_gear_on_surface" not in f
    assert "n_merged" not in f and not f["has_truth"] and "truth_found" not in f
    assert f["untimed_runs"] == []


def test_chapter_3_2_prose_follows_altered_findings():
    """Every statement of chapter 3.2 follows its findings: the figures ask only for
    references, and with altered values the prose changes with them."""
    found = straightness_findings(_rich_profiles(), _rich_peaks(), thesis_design=False,
                                  truth_check=_truth_check(),
                                  surface_peaks=pd.DataFrame({"cut": ["k1"],
                                                              "f_spatial_per_mm": [0.5]}),
                                  **RICH)
    found.items["n_runs"].value = 17
    found.items["speed_error_pct_max"].value = 3.25
    found.items["n_gear_on_surface"].value = 7
    found.items["truth_missed"].value = 5
    found.items["rms_vertical_um_range"].value = [0.125, 9.5]
    found.items["ref_surface_marks_per_mm"].value = 6.5
    found.comparisons = [{"verdict": "pass"}, {"verdict": "miss"}]
    say = Prose(load_templates("ch3_straightness"), found)
    refs = {f"ref_{k}": f"[{k}]" for k in (
        "deviation", "psd", "more", "psd_high", "band_floor", "temporal_vs_spatial", "mesh",
        "attribution", "runs_by_design", "truth")}
    text = " ".join(say(*(t for t in say.templates if not t.startswith("cap_")),
                        **refs).split())
    assert "**17 tracker runs** (+X, +Y; feeds 2, 10 mm/s)" in text
    assert "by at most 3.25 %" in text and "1/L = 0.0500 mm⁻¹" in text
    assert "5 spectral peaks: 3 attributed to a gear" in text and "1 unclassified" in text
    assert "Run(s) c:" in text and "at 2–10 mm/s ([deviation])" in text
    assert "analysed the same way" not in text  # no extra direction outside the thesis
    assert "7 of 3 gear peaks are also surface-waviness peaks (tolerance 0.050" in text
    assert "1 gear peak(s) are **merged**" in text
    assert "vertical 0.12–9.50 µm" in text
    assert "≥ 3 × the detection threshold" in text and "fewer than 2.5 cycles" in text
    assert "missed **5**" in text
    assert "near the 6.5 mm⁻¹ marks" in text and "1 of 2 reproduced" in text
    assert "{" not in text
    assert say("cap_psd", direction="45°").startswith("Power spectrum of the motion along 45°")
    # the thesis' layout: the other directions get their sentence, no per-run grouping
    found.items["thesis_layout"].value = True
    found.items["extra_directions"].value = ["px"]
    found.items["extra_direction_labels"].value = ["+X"]
    found.items["has_truth"].value = False
    again = " ".join(say("more", "runs_by_design", "truth", **refs).split())
    assert "The runs along +X are analysed the same way: [more]." in again
    assert "RMS deviation" not in again and "Real data: no planted truth" in again


def test_chapter_3_2_overview_without_the_run_geometry():
    """A profiles file without lengths and speeds: the overview still counts the peaks."""
    say = Prose(load_templates("ch3_straightness"),
                straightness_findings(_profiles(), _peaks(), **KW))
    text = " ".join(say("overview").split())
    assert text.startswith("**2 tracker runs** (+Y; feeds 2, 10 mm/s); 6 spectral peaks")
