"""Chapters 3.3 and 4: their findings from planted artefacts (robomill.modal.findings,
robomill.chatter.findings), and their prose rendered from findings with altered values
(the templates of src/robomill/data/templates through robomill.pipeline.prose: no kernel)."""

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from robomill.chatter.findings import chatter_findings
from robomill.findings import Findings
from robomill.modal.findings import modal_findings
from robomill.modal.layout import frf_coords
from robomill.pipeline.prose import Prose, load_templates

F = np.arange(0.0, 101.0)


def _modal_inputs(misfit=0.1):
    H = (1.0 + 1j) * np.ones((3, 3, F.size))
    ds = xr.Dataset({"H": (("output", "input", "frequency"), H)}, coords=frf_coords(F),
                    attrs={"fs_hz": 2048, "record_samples": 8192, "window_sigma_per_s": 0.5})
    synth = xr.Dataset({"H_synth": (("output", "input", "frequency"), H * (1 + misfit))},
                       coords=frf_coords(F), attrs={"band_hz": [10.0, 90.0],
                                                    "band_source": "data"})
    tables = {
        "hits": pd.DataFrame({"reference": list("XXYYZZ"),
                              "accepted": [True, False, True, True, False, True]}),
        "modes": pd.DataFrame({"mode": [1, 2], "f_n_hz": [20.0, 40.0], "zeta": [0.02, 0.04],
                               "zeta_windowed": [0.025, 0.044],
                               "flags": [np.nan, "negative modal mass"]}),
        "peaks": pd.DataFrame({"real_sign_change": [True, True, False],
                               "coherence_ok": [True, False, True],
                               "natural_frequency": [True, False, False]}),
        "stabilization": pd.DataFrame({"status": ["stable", "new", "stable", "f"]}),
        "mac": pd.DataFrame({"mode": [1, 2], "mode_1": [1.0, 0.3], "mode_2": [0.3, 1.0]}),
        "peak_groups": pd.DataFrame({"f_hz": [20.0]}),
        "truth_check": pd.DataFrame({"f_err_pct": [0.1, -0.4], "zeta_err_pct": [1.0, 2.0],
                                     "k_err_pct": [-3.0, 1.0], "shape_mac": [0.99, 0.98]}),
        "coupling": pd.DataFrame({"f_n_hz": [20.0, 40.0], "vibration_hz": [38.0, 38.0],
                                  "close": [False, True]}),
        "coupling_pairs": pd.DataFrame(columns=["mode_a", "mode_b", "shape_angle_deg"]),
    }
    return ds, synth, tables


def test_modal_findings_from_planted_artefacts():
    ds, synth, tables = _modal_inputs()
    v = modal_findings(ds, synth, tables, coherence_min=0.8, coupling_tolerance=0.1).values()
    assert v["tooltip_layout"] and v["n_frf_measured"] == 9 and v["n_outputs"] == 3
    assert v["n_hits"] == 6 and v["n_rejected"] == 2
    assert v["hits_per_reference"] == ["X: 2", "Y: 2", "Z: 2"]
    assert (v["n_peak_candidates"], v["n_real_sign_change"], v["n_coherence_ok"],
            v["n_natural"]) == (3, 2, 2, 1)
    assert v["threshold_n_coherence_ok"] == 0.8
    assert v["n_stable_poles"] == 2 and v["n_modes"] == 2 and v["modes_hz"] == [20.0, 40.0]
    assert v["n_flagged"] == 1 and "negative modal mass" in v["flagged"][0]
    assert v["mac_offdiag_max"] == pytest.approx(0.3)
    assert v["truth_f_err_pct_max"] == pytest.approx(0.4)
    assert v["truth_k_err_pct_max"] == pytest.approx(3.0)
    assert v["window_zeta_bias_pct_max"] == pytest.approx(25.0)  # 0.025/0.02 - 1
    assert v["misfit_median_pct"] == pytest.approx(10.0)
    assert v["n_close"] == 1 and v["close_hz"] == [40.0] and v["vibration_hz"] == 38.0
    assert v["verdict_n_close"] == "not_possible"  # no pair of close modes
    assert v["threshold_n_close"] == 0.1


def _chatter_inputs():
    rpm = np.array([6400.0, 8400.0, 10000.0])
    case = xr.Dataset(
        {"a_crit_mm": (("solver", "spindle_rpm"), [[2.0, 2.0, 3.0], [1.6, 1.7, 1.0]]),
         "a_crit_error_mm": ("spindle_rpm", [0.0016, 0.0034, 0.001]),
         "bifurcation": ("spindle_rpm", ["hopf", "hopf", "flip"]),
         "collocation_order": ("spindle_rpm", [8, 10, 12])},
        coords={"solver": ["zoa", "sem"], "spindle_rpm": rpm},
        attrs={"accuracy": 0.005, "case_name": "insperger2004_down005", "case_teeth": 2,
               "case_Kt_N_m2": 6e8, "case_Kr": 0.3, "case_milling": "down",
               "case_radial_immersion": 0.05, "depth_max_mm": 10.0,
               "case_spindle_rpm": '{"start": 5000, "stop": 25000, "num": 3}',
               "case_modes": '{"x": [], "y": []}'})
    n = np.array([1000.0, 1260.0])
    runs = ["point1", "point2", "point2_adaptive"]
    sim = xr.Dataset(
        {"seed_a_crit_mm": (("solver", "spindle_rpm"), [[0.2, 0.3], [0.1, 0.2]]),
         "seed_a_crit_error_mm": ("spindle_rpm", [0.001, 0.004]),
         "seed_a_crit_sem_mm": ("spindle_rpm", [0.099, 0.198]),
         "indicator_N": (("run", "window_end"), np.ones((3, 2)) * [[0, 0], [1, 5], [0, 0]]),
         "indicator_hz": (("run", "window_end"), np.full((3, 2), 205.0)),
         "onset_check_rpm": ("onset", [1260.0, 1260.0]),
         "onset_depth_fraction": ("onset", [0.9, 1.1]),
         "onset_a_boundary_mm": ("onset", [0.2, 0.2]),
         "onset_unstable": ("onset", [False, False]),
         "onset_indicator_N": ("onset", [0.1, 0.2]),
         "onset_growth_rate_sdm_1_s": ("onset", [-1.0, 1.0]),
         "onset_growth_rate_simulated_1_s": ("onset", [-1.0, 0.9])},
        coords={"solver": ["zoa", "sdm"], "spindle_rpm": n, "run": runs,
                "window_end": [1.0, 2.0]},
        attrs={"a_star_mm": 0.1, "spindle_rpm_seed": 1260.0, "a_boundary_at_n_mm": 0.2,
               "point1_depth_mm": 0.19, "point2_depth_mm": 0.21, "chatter_hz_zoa_at_n": 204.0,
               "sdm_steps_per_period": 60, "sdm_chatter_hz_at_n": 210.0,
               "sdm_bifurcation_at_n": "flip", "tooth_hz": 84.0,
               "growth_rate_sdm_point2_1_s": 3.0, "growth_rate_simulated_point2_1_s": 5.0,
               "growth_window_teeth": 20, "detector_window_s": 1.0, "adapted_depth_mm": 0.18,
               "growth_rate_sdm_adapted_1_s": -2.0, "indicator_final_point1_N": 0.05,
               "indicator_final_point2_N": 4.0, "indicator_final_point2_adaptive_N": 1.0,
               "Kt_noise_fraction": 0.005, "detections_point1_s": np.array([]),
               "detections_adaptive_s": np.array([1.5, 2.5]),
               "adaptation_setpoint_fraction": np.array([0.99, 0.98]),
               "adaptation_lowered_fraction": 0.02,
               "seed_params": '{"m_kg": 2.0, "m_s_kg": 0.2, "c_s_N_m": 220000.0, "teeth": 4, '
                              '"Kt_N_m2": 9e8, "Kr": 0.6, "phi_ex_rad": 1.5707963, '
                              '"feed_m_s": 0.01, "force_setpoint_N": 40.0}'})
    lobes = xr.Dataset(
        {"a_crit_mm": (("direction", "solver", "spindle_rpm"), np.ones((2, 2, 2))),
         "a_crit_error_mm": (("direction", "spindle_rpm"), [[0.001, 0.002], [0.004, 0.001]])},
        coords={"direction": ["px", "py"], "solver": ["zoa", "sem"],
                "spindle_rpm": [27000.0, 28000.0]},
        attrs={"thesis_spindle_rpm": 28000.0, "accuracy": 0.005})
    rec = pd.DataFrame({"direction": ["px", "px", "px"], "kind": ["thesis", "thesis",
                                                                  "recommended"],
                        "solver": ["sem"] * 3, "spindle_rpm": [28000.0, 28000.0, 30000.0],
                        "axial_depth_mm": [0.25, 0.5, 0.22],
                        "stability_margin": [0.1, -0.45, 0.25],
                        "stability_margin_min": [0.09, -0.46, 0.25],
                        "chatter_free": [True, False, True],
                        "limited_by": ["regenerative"] * 3, "a_limit_mm": [1.0, 1.0, 1.1]})
    return {"insperger2004_down005": case}, sim, lobes, rec


def test_chatter_findings_from_planted_artefacts():
    cases, sim, lobes, rec = _chatter_inputs()
    v = chatter_findings(cases, sim, lobes, rec, safety_fraction=0.2).values()
    assert v["bench_hopf_min_mm"] == 1.6 and v["bench_n_flip"] == 1
    assert v["bench_flip_rpm"] == [10000.0, 10000.0] and v["bench_flip_zoa_mm"] == 3.0
    assert v["bench_worst_err_pct"] == pytest.approx(0.2)  # 0.0034 / 1.7
    assert v["bench_worst_rpm"] == 8400.0 and v["bench_worst_order"] == 10
    assert v["verdict_bench_worst_err_pct"] == "pass" and v["bench_has_checks"]
    assert v["bench_a_6400rpm_mm"] == 1.6 and not v["has_slot"]
    assert v["seed_boundary_ratio"] == pytest.approx(2.0)
    assert v["seed_sdm_worst_err_pct"] == pytest.approx(2.0)  # 0.004 / 0.2
    assert v["seed_a_star_sem_mm"] == 0.099 and v["seed_point2_chatter_hz"] == 205.0
    assert v["seed_point1_stable"] and v["seed_first_detection_s"] == 1.5
    assert v["seed_setpoint_pct"] == [99.0, 98.0] and v["seed_lowered_pct"] == 2.0
    assert v["seed_efold_s"] == 0.5 and v["seed_adapted_below_pct"] == pytest.approx(10.0)
    assert v["seed_adaptive_share"] == 0.25
    assert (v["onset_agree"], v["onset_n"]) == (1, 2)  # 1.1 x boundary but stable: disagree
    assert v["robot_worst_err_pct"] == pytest.approx(0.4) and v["robot_worst_direction"] == "py"
    assert v["robot_worst_rpm"] == 27000.0
    assert (v["n_cuts"], v["n_cuts_chatter_free"]) == (2, 1) and v["safety_pct"] == 20.0
    assert v["ref_sdm_converged_6400_mm"] == 1.6392
    assert v["bench_published"] is True  # the benchmark is configured under its own name


def test_chatter_findings_of_another_case_and_a_slotting_case():
    """A case under another name is not the published benchmark; a slotting case of 3 teeth
    with one mode in x and another in y is not symmetric (planted by hand)."""
    cases, sim, lobes, rec = _chatter_inputs()
    other = cases.pop("insperger2004_down005").assign_attrs(case_name="my_tool")
    slot = other.assign_attrs(case_name="insperger2004_slot", case_teeth=3, case_modes=(
        '{"x": [{"f_hz": 500.0, "zeta": 0.02, "k_N_m": 1e7}], '
        '"y": [{"f_hz": 600.0, "zeta": 0.02, "k_N_m": 1e7}]}'), worst_relative_error=0.001)
    v = chatter_findings({"my_tool": other, "insperger2004_slot": slot}, sim, lobes, rec,
                         safety_fraction=0.2).values()
    assert v["bench_case"] == "my_tool" and v["bench_published"] is False
    assert v["has_slot"] and v["slot_teeth"] == 3 and v["slot_symmetric"] is False
    same = slot.assign_attrs(case_modes='{"x": [{"f_hz": 1.0}], "y": [{"f_hz": 1.0}]}')
    v = chatter_findings({"insperger2004_slot": same}, sim, lobes, rec,
                         safety_fraction=0.2).values()
    assert v["slot_symmetric"] is True and v["bench_case"] == "insperger2004_slot"


def test_chatter_findings_flip_speed_of_a_one_mode_case():
    cases, sim, lobes, rec = _chatter_inputs()
    cases["insperger2004_down005"].attrs["case_modes"] = (
        '{"x": [{"f_hz": 900.0, "zeta": 0.01, "k_N_m": 1e6}], "y": []}')
    v = chatter_findings(cases, sim, lobes, rec, safety_fraction=0.2).values()
    assert v["bench_flip_speed_rpm"] == pytest.approx(18000.0)  # 60 * 2 * 900 / (3 * 2)
    assert v["bench_Kn_N_m2"] == pytest.approx(1.8e8) and v["bench_fn_hz"] == 900.0


def _refs(templates):
    return {f"ref_{k}": f"[{k}]" for k in (
        "hits", "impact_test", "frf_grid", "frf_first", "frf_last", "peak_groups",
        "stabilization", "modes", "mac_shapes", "truth", "misfit", "coupling",
        "benchmark_lobes", "benchmark_error", "slot", "seed_lobes", "seed_time",
        "seed_spectra", "detection", "onset", "thesis_lobes", "recommendations")}


def test_chapter_3_3_prose_follows_its_findings():
    ds, synth, tables = _modal_inputs(misfit=0.37)
    tables["modes"]["f_n_hz"] = [21.5, 47.25]
    found = modal_findings(ds, synth, tables, coherence_min=0.6, coupling_tolerance=0.25,
                           stability={"tol_f": 0.02, "tol_zeta": 0.07, "mac_min": 0.9})
    say = Prose(load_templates("ch3_modal"), found)
    text = say(*say.templates, **_refs(say.templates))
    assert "21.50, 47.25 Hz" in text and "**2 modes**" in text
    assert "coherence > 0.6" in text and "±25 %" in text
    assert "median 37.00 %" in text
    joined = " ".join(text.split())
    assert "within 2 % in frequency" in joined and "7 % in damping" in joined
    assert "MAC ≥ 0.9 " in joined
    assert "**6 hits**" in text and "**2 rejected**" in " ".join(text.split())
    assert "from the hammer spectrum" in text
    assert "{" not in text  # every field filled or its sentence left out
    found.items["n_modes"].value = 0
    assert "**No mode**" in Prose(load_templates("ch3_modal"), found)("modes", ref_modes="[t]")
    del found.items["mac_offdiag_max"]
    assert "a single mode" in say("mac", ref_mac_shapes="[f]")
    thesis = Findings("modal")
    thesis.comparisons = [{"verdict": "pass"}, {"verdict": "miss"}]
    assert "1 of 2" in Prose(load_templates("ch3_modal"), thesis)("against")
    assert "not compared" in Prose(load_templates("ch3_modal"), Findings("modal"))("against")
    found.comparisons = [{"verdict": "miss"}]
    joined = " ".join(Prose(load_templates("ch3_modal"), found)("thesis_test", "against").split())
    assert "averages 5 accepted hits" in joined and "0 of 1 reproduced" in joined


def test_chapter_4_prose_follows_its_findings():
    cases, sim, lobes, rec = _chatter_inputs()
    found = chatter_findings(cases, sim, lobes, rec, safety_fraction=0.3)
    say = Prose(load_templates("ch4"), found)
    text = " ".join(say(*say.templates, **_refs(say.templates)).split())
    assert "30 % (`chatter.thesis.safety_fraction`)" in text
    assert "at 28000 rpm" in text and "(1 of 2 cuts chatter-free)" in text
    assert "not compared with the thesis'" in text  # not the thesis' study: no comparison
    assert "{" not in text
    thesis = chatter_findings(cases, sim, lobes, rec, safety_fraction=0.3, thesis_study=True)
    against = " ".join(Prose(load_templates("ch4"), thesis)("against", ref_coupling="[t]")
                       .split())
    assert "60–120 Hz" in against and "chapter 6.1" in against  # from references.yaml
    assert "Reference" not in " ".join(load_templates("ch4"))  # no Shagniev 2019 template left


def test_chapter_4_states_what_the_axial_force_does():
    """With K_ac identified, each slot's zero-order depth with the axial force beside the
    planar model's at the speed of most of its cuts (planted: px 3.5 against 7.0 mm, py 9 against
    6 mm); without it, the chapter says the lobes are planar."""
    cases, sim, lobes, rec = _chatter_inputs()
    planar_text = " ".join(Prose(load_templates("ch4"), chatter_findings(
        cases, sim, lobes, rec, safety_fraction=0.3))("axial").split())
    assert "planar model" in planar_text and "not identified" in planar_text
    a = np.ones((2, 2, 2))
    a[0, 0, 1], a[1, 0, 1] = 3.5, 9.0                  # zoa at 28 000 rpm: px, py
    axial = lobes.assign(a_crit_mm=(("direction", "solver", "spindle_rpm"), a),
                         a_crit_planar_mm=(("direction", "spindle_rpm"), [[1.0, 7.0],
                                                                          [1.0, 6.0]]),
                         study_spindle_rpm=("direction", [28000.0, 28000.0]))
    axial.attrs.update(Ka=0.25, Kt_N_m2=8.0e8)
    v = chatter_findings(cases, sim, axial, rec, safety_fraction=0.3)
    assert v.values()["robot_axial_force"] and v.values()["robot_Kac_N_mm2"] == 200.0
    assert v.values()["robot_axial_over_planar"] == [0.5, 1.5]
    say = Prose(load_templates("ch4"), v)
    text = " ".join(say("axial", "axial_lines").split())
    assert "K_ac = 200 N/mm²" in text
    assert "px: 3.50 mm with the axial force, 7.00 mm without (-50 %) at 28000 rpm" in text
    assert "py: 9.00 mm with the axial force, 6.00 mm without (+50 %)" in text
    # a study speed within the grid's tolerance of a grid point (not added to the grid again)
    near = axial.assign(study_spindle_rpm=("direction", [28000.0 * (1 + 1e-12)] * 2))
    assert chatter_findings(cases, sim, near, rec, safety_fraction=0.3).values()[
        "robot_axial_over_planar"] == [0.5, 1.5]


def test_chapter_6_1_prose_follows_its_findings_without_the_studys_robot():
    """The reference study of chatter (chapter 6.1) renders from the configured cases and the
    Shagniev 2019 simulation alone: a study without impact or force data has no robot findings."""
    cases, sim, _, _ = _chatter_inputs()
    sim.attrs["sdm_bifurcation_at_n"] = "hopf"
    sim.attrs["a_star_mm"] = 0.0777
    found = chatter_findings(cases, sim, None, None, safety_fraction=0.3)
    assert found.values()["has_robot"] is False and "robot_rpm" not in found
    say = Prose(load_templates("ch6_chatter"), found)
    text = " ".join(say(*say.templates, **_refs(say.templates)).split())
    assert "a* = **0.078 mm**" in text and "of **Hopf** type" in text
    assert "t = 1.5 s" in text and "99, 98 %" in text
    assert "agree at 1 of 2 checks" in text
    assert "No slotting case configured." in text
    assert "+3.1 %" in text and "1.6392 mm" in text  # from references.yaml
    assert "≈ 18440 rpm" not in text  # the planted case lists no modes: no flip-speed sentence
    assert "Case `insperger2004_down005` (`config.yaml: chatter.cases`)." in text
    assert "tool partial frequency 167 Hz" in text and "K_t = 900 MPa" in text
    assert "1-DOF benchmark of Insperger" in text  # bench_published
    assert "Their diagram" not in text  # ... but no one-mode setup to state its flip speed
    assert text.count("No slotting case configured") == 1
    assert "holds no check" in text  # no scorecard rows given
    assert "{" not in text
    found.items["bench_published"].value = False
    assert Prose(load_templates("ch6_chatter"), found)("bench_published") == ""
    found = chatter_findings({**cases, "insperger2004_slot": cases["insperger2004_down005"]
                              .assign_attrs(case_teeth=5, worst_relative_error=0.001)},
                             sim, None, None, safety_fraction=0.3)
    say = Prose(load_templates("ch6_chatter"), found)
    text = " ".join(say("slot_case", slot_symmetry=say("slot_symmetry")).split())
    assert "5 teeth, the same modes in x and y" in text


def _surface_findings(**kw):
    """Three cuts along +X and +Y, roughness 0.1 × feed; two kinematic waviness peaks, three
    dynamic roughness peaks (robomill.surface.findings)."""
    from robomill.surface.findings import surface_findings
    from robomill.surface.options import settings

    metrics = pd.DataFrame({"cut": ["s1_g1_px", "s1_g1_py", "s1_g2_px"], "set": [1, 1, 1],
                            "segment": [1, 1, 2], "direction": ["px", "py", "px"],
                            "feed_mm_s": [2.0, 2.0, 5.0], "tilt_um_per_mm": [0.25, 0.5, 1.0],
                            "waviness_rms_um": [1.5, 7.25, 2.5],
                            "roughness_rms_um": [0.2, 0.2, 0.5], "Ra_um": [0.1, 0.2, 0.4]})
    peaks = pd.DataFrame({"cut": ["s1_g1_px", "s1_g2_px", "s1_g1_px", "s1_g2_px", "s1_g1_py"],
                          "band": ["waviness"] * 2 + ["roughness"] * 3,
                          "mechanism": ["kinematic"] * 2 + ["dynamic"] * 3,
                          "f_spatial_per_mm": [0.25, 0.25, 40.0, 16.0, 45.0],
                          "feed_mm_s": [2.0, 5.0, 2.0, 5.0, 2.0],
                          "f_temporal_hz": [0.5, 1.25, 80.0, 80.0, 90.0],
                          "resolution_per_mm": [0.1, 0.1, 4.0, 4.0, 4.0],
                          "below_resolution": [False] * 5})
    args = dict(settings=settings({}), thesis_layout=True, synthetic=False, design="3 cuts")
    return surface_findings(metrics, peaks, xr.Dataset(coords={"x": np.linspace(0, 12, 1201)}),
                            **{**args, **kw})


def test_chapter_2_prose_follows_its_findings():
    found = _surface_findings()
    say = Prose(load_templates("ch2"), found)
    refs = {f"ref_{k}": f"[{k}]" for k in (
        "detrend", "waviness", "roughness_feed", "profiles", "spectrum", "spectra", "rms",
        "rms_vs_feed", "peak_counts", "peak_mechanisms", "recovery")}
    text = " ".join(say(*say.templates, **refs).split())
    assert "**3 profiles**, 1201 samples each at 100 mm⁻¹ (12.00 mm)" in text
    assert "Data: measured profiles." in text and "Design of the profiled cuts: 3 cuts." in text
    assert "tilt removed from s1_g1_px: 0.25 µm/mm" in text
    assert "at feed 2 and 5 mm/s" in text and "The profiles of set 1" in text
    assert "waviness RMS 1.50–7.25 µm" in text
    assert "mean waviness RMS 2.00, 7.25 µm along +X, +Y respectively" in text
    assert "largest along +Y" in text and "roughness 1.00." in text
    assert "2 of 2 waviness peaks are kinematic, median wavelength 4.00 mm" in text
    assert "3 of 3 roughness peaks are dynamic, temporal frequencies 80–88 Hz (10–90 %)" in text
    assert "at least 2.5 periods" in text and "Measured data: no planted truth" in text
    assert "The waviness is kinematic: 100% of its resolved peaks" in text
    assert "at least 50%, `surface.mechanism_share_min`" in text
    assert "not compared with the thesis'" in text and "virtual cell" not in text
    assert "{" not in text
    # altered values: the verdicts and numbers follow
    found.items["waviness_mechanism"].value = found.items["waviness_mechanism"].verdict = "mixed"
    found.items["waviness_kinematic_share"].value = 0.3
    found.items["n_kinematic_waviness"].value = 0
    found.items["peaks_resolved"].verdict = "fail"
    found.add("n_below_resolution", 4)
    found.add("below_resolution_example_cut", "s9_g9_my")
    found.add("below_resolution_example_per_mm", 0.123)
    found.add("below_resolution_example_resolution_per_mm", 0.0667)
    found.items["feed_correlation_waviness"].value = None
    say = Prose(load_templates("ch2"), found)
    text = " ".join(say("mechanism_waviness", "kinematic", "resolution",
                        "feed_correlation").split())
    assert "no single mechanism: kinematic 30%" in text
    assert "None of the 2 waviness peaks is kinematic." in text
    assert "**Sanity flag: 4 of 5 peaks" in text and "s9_g9_my at 0.12 mm⁻¹" in text
    assert "1/L = 0.067 mm⁻¹" in text and "share one feed" in text
    thesis = _surface_findings(synthetic=True, comparison=pd.DataFrame(
        {"table": ["table_2_1_waviness_rms_um", "table_2_2_roughness_rms_um"],
         "ratio": [1.25, 0.75], "within_2x": [True, False]}))
    thesis.comparisons = [{"verdict": "pass"}, {"verdict": "miss"}, {"verdict": "pass"}]
    text = " ".join(Prose(load_templates("ch2"), thesis)("against", "thesis_tables", "rows",
                                                          "levels").split())
    assert "2 of 3 reproduced" in text and "smallest along +X and largest along +Y" in text
    assert "within a factor 2 of the thesis: Table 2.1 (waviness) 1 of 1" in text
    assert "Table 2.2 (roughness) 0 of 1" in text and "0.75" in text
    assert "virtual cell" in text


def _forces_altered():
    """Chapter 3.1's findings with values no study of the default config gives."""
    f = Findings("forces")
    for key, value in {
            "n_cuts": 7, "n_samples_total": 12345, "tooth_passing_hz_values": [700.0, 1400.0],
            "design": "7 cuts: 7 spindle speeds", "grouping": ["spindle_rpm"],
            "thesis_layout": False, "figure_set": None, "model_flutes": 3,
            "model_milling": "down", "model_radial_immersion": 0.25, "lowband_hz": 180.0,
            "full_band_min_hz": 800.0, "full_band_peak_cut": "x1", "full_band_peak_hz": 4321.0,
            "full_band_peak_harmonic": 6.17, "n_kinematic": 5, "n_kinematic_none": 2,
            "kinematic_per_mm_median": 0.77, "kinematic_per_mm_range": [0.61, 0.83],
            "kinematic_band_per_mm": [0.6, 0.9], "kinematic_prominence_db": 7.0,
            "resolution_feed_mm_s": 3.0, "resolution_per_mm": 0.125,
            "kinematic_below_resolution": ["x2 (0.61 mm⁻¹ at 1/L = 0.125 mm⁻¹)", "x3"],
            "kinematic_uncertainty_pct": 4.0, "kinematic_record_needed_mm": 20.6,
            "F_feed_N_range": [-7.25, -1.5], "F_cross_feed_N_range": [0.25, 3.0],
            "F_axial_N_range": [0.125, 0.5], "all_slot": False,
            "millings": ["down milling, a_e/D 0.25"], "confidence_pct": 90.0,
            "coefficient_flags_checked": True, "n_coefficients": 6, "n_not_physical": 1,
            "not_physical": ["Krc is negative (-3 N/mm^2)"],
            "planted_error_pct_max": 7.5, "planted_error_worst": "Kae",
            "ref_full_band_peak_hz": 12000.0, "ref_kinematic_per_mm": 0.45}.items():
        f.add(key, value)
    for name, value in {"Ktc": 812.25, "Krc": -3.0, "Kac": 1.0, "Kte": 2.0, "Kre": 3.0,
                        "Kae": 4.0}.items():
        f.add(f"coefficient_{name}", value)
        f.add(f"coefficient_{name}_ci", [value - 12.25, value + 7.75])
    f.add("n_kinematic_below_resolution", 2, verdict="fail", threshold=12.5,
          config_key="forces.min_peak_cycles")
    return f


def test_chapter_3_1_prose_follows_altered_findings():
    """Every statement of chapter 3.1 beyond the dominant peak (tests/test_forces_findings.py)
    follows its findings: records, figures' selection, full-band peak, kinematic flag,
    levels, engagement, coefficients and the thesis' numbers."""
    found = _forces_altered()
    say = Prose(load_templates("ch3_forces"), found)
    refs = {f"ref_{k}": f"[{k}]" for k in (
        "peaks", "record", "full_band_psd", "spatial", "time", "model_force_shape",
        "harmonics", "mean_forces_vs_feed", "coefficients")}
    shape, which = say("model_shape"), say("which")
    assert shape == "3-flute down-milling cut at a_e/D 0.25" and which == "every cut"
    text = " ".join(say(*say.templates, shape=shape, which=which, direction="+X",
                        **refs).split())
    assert "12,345 samples" in text and "700.0, 1400.0 Hz" in text
    assert "Design: 7 cuts: 7 spindle speeds." in text and "groups the cuts by spindle_rpm" in text
    assert "above 800 Hz is at **4321 Hz**, 6.17 times" in text
    assert "0–180 Hz of every cut along +X" in text
    assert "median **0.77 mm⁻¹** over the 5 cuts" in text and "0.6–0.9 mm⁻¹" in text
    assert "rises 7 dB" in text and "In 2 of 7 cuts" in text
    assert "3 mm/s record is 1/L = 0.125 mm⁻¹" in text
    assert "**Sanity flag: 2 of 7 cuts" in text and "fewer than 12.5 periods" in text
    assert "±4 %" in text and "21 mm for the lowest flagged peak" in text
    assert "feed -7.25 to -1.50 N" in text and "axial 0.12 to 0.50 N" in text
    assert "engaged arc: down milling, a_e/D 0.25" in text
    assert "90 % intervals" in text and "Ktc = 812.2 [800.0, 820.0] N/mm²" in text
    assert "+7.50 % (Kae)" in text and "**Not physical:** Krc is negative" in text
    assert "All 6 coefficients are physical" not in text
    assert "{" not in text
    assert "Against the thesis" not in text and "12,000" not in text  # not the thesis' study
    found.comparisons = [{"verdict": "pass"}]
    closing = " ".join(Prose(load_templates("ch3_forces"), found)("thesis_says", "against").split())
    assert "above 12,000 Hz" in closing and "near 0.45 mm⁻¹" in closing
    assert "1 of 1 reproduced" in closing
    found.items["n_kinematic_below_resolution"].verdict = "pass"
    found.items["n_not_physical"].value = 0
    found.items["all_slot"].value = True
    again = " ".join(Prose(load_templates("ch3_forces"), found)(
        "kinematic_flag", "physical", "physical_ok", "mean_forces", **refs).split())
    assert "at least 12.5 periods" in again and "All 6 coefficients are physical" in again
    assert "K_tc c/4 + K_te/π" in again and "Sanity flag" not in again


def test_chapter_3_3_tables_shown():
    """The peak groups without the thesis' reference column (left to 'Against the thesis'),
    the misfit per FRF and the rounded mode table (robomill.modal.shown)."""
    from robomill.modal.shown import misfit_table, shown_modes, shown_peak_groups

    groups = pd.DataFrame({"group": [1], "f_hz": [19.961], "n_frfs": [5], "frfs": ["X/X"],
                           "reference_hz": [20.0], "offset_hz": [-0.039]})
    assert list(shown_peak_groups(groups).columns) == ["group", "f_hz", "n_frfs", "frfs"]
    assert shown_peak_groups(groups)["f_hz"].iloc[0] == 19.96
    ds, synth, _ = _modal_inputs(misfit=0.25)
    err = misfit_table(ds, synth, [10.0, 90.0])
    assert err.shape == (3, 3) and np.allclose(err.to_numpy(), 25.0)
    assert shown_modes(pd.DataFrame({"f_n_hz": [20.12345], "zeta": [0.012345]})).iloc[0].tolist() \
        == [20.123, 0.0123]


def _chapter_0(found):
    """Chapter 0's sentences as its notebook renders them (notebooks/src/ch0.py)."""
    from robomill.pipeline.prose import render

    say = Prose(load_templates("ch0"), found)
    refs = {"ref_plan": "[plan]", "ref_feed_per_tooth": "[feed]"}
    v = found.values()
    lines = [render(say.templates["group"], g) for g in v.get("groups") or []]
    return " ".join(" ".join([
        say("caption_plan", grouped_by=say("grouped_by")), say("caption_feed_per_tooth"),
        say("layout", "design", "missing"),
        say("summary", cut_count=say("cut_count"), speed=say("speed"),
            shown_per=say("shown_per"), **refs),
        say("by_group", "same_feed", group_lines=lines, **refs),
        say("against", "against_rows")]).split())


def test_chapter_0_prose_follows_altered_findings():
    """Chapter 0 states the cuts, speeds, feed per tooth and design of its findings (values
    no study of the default config gives), the layout only in the thesis' layout and the
    thesis' cell only for the thesis' study, in the closing section."""
    f = Findings("ingest")
    for key, value in {
            "n_cuts": 12, "has_cuts": True, "thesis_layout": True, "thesis_study": False,
            "missing": [], "n_sets": 4, "n_segments": 6, "directions": ["+X", "−Y"],
            "n_directions": 2, "single_speed": True, "spindle_rpm": 21000.0,
            "spindle_hz": 350.0, "tooth_passing_hz": 1400.0,
            "feed_per_tooth_um_range": [0.125, 9.875], "design": "12 cuts: 4 sets × 3 x",
            "grouping": ["set", "segment"], "groups": [], "ref_robot": "Robot R-9",
            "ref_workpiece": "brass", "ref_dynamometer": "Dyno 7", "ref_tool": "5-flute mill",
            "ref_spindle_rpm": 12345.0, "ref_cell_where": "§9.9"}.items():
        f.add(key, value)
    text = _chapter_0(f)
    assert "the cuts of every segment" in text and "of every segment, per set" in text
    assert "4 sets of 6 U-shaped segments; each segment is 2 straight cuts, **+X, −Y**" in text
    assert "**Design:** 12 cuts: 4 sets × 3 x." in text and "Not stated" not in text
    assert "**12 cuts** in 4 sets; spindle 350.0 Hz (21000 rpm), tooth passing 1400.0 Hz" in text
    assert "from 0.12 µm to 9.88 µm" in text and "feed per tooth of every segment." in text
    assert "[feed]:" not in text  # the thesis' layout: no per-group sentence
    assert "not the thesis' design" in text and "Robot R-9" not in text
    assert "{" not in text.replace("`s{set}_g{segment}_{dir}`", "")
    # the thesis' study: its cell and the comparison rows, in the closing section
    f.items["thesis_study"].value = True
    f.comparisons = [{"verdict": "pass"}, {"verdict": "miss"}, {"verdict": "pass"}]
    text = _chapter_0(f)
    assert "The thesis' cell (§9.9): the robot, Robot R-9, slot-milled a block of brass" in text
    assert "dynamometer, Dyno 7; the tool, 5-flute mill, turned at 12345 rpm" in text
    assert "2 of 3 within the tolerance" in text
    # another design: a speed series grouped by speed, no layout sentence
    for key, value in {"thesis_layout": False, "thesis_study": False, "single_speed": False,
                       "spindle_rpm": None, "spindle_rpm_range": [6000.0, 30000.0],
                       "tooth_passing_hz_range": [400.0, 2000.0],
                       "grouping": ["spindle_rpm", "direction"],
                       "groups": [{"label": "6000 rpm", "feed_per_tooth_um": [1.5, 4.25],
                                   "tooth_passing_hz": [400.0, 400.0]},
                                  {"label": "30000 rpm", "feed_per_tooth_um": [0.3, 0.85],
                                   "tooth_passing_hz": [2000.0, 2000.0]}]}.items():
        f.add(key, value)
    f.comparisons = []
    text = _chapter_0(f)
    assert "grouped by what varies (spindle_rpm, direction)" in text
    assert "U-shaped" not in text and "**12 cuts**;" in text
    assert "spindle 6000–30000 rpm, tooth passing 400.0–2000.0 Hz" in text
    assert "feed per tooth of every cut." in text
    assert ("[feed]: 6000 rpm: c 1.50–4.25 µm, tooth passing 400–400 Hz; 30000 rpm: c "
            "0.30–0.85 µm, tooth passing 2000–2000 Hz.") in text
    assert "same feed per tooth" not in text and "not the thesis' design" in text
    f.add("groups", [])
    f.add("grouping", [])
    text = _chapter_0(f)
    assert "grouped by what varies (nothing)" in text
    assert "[feed]: every cut has the same feed per tooth." in text
    f.add("missing", ["spindle_rpm"])
    del f.items["feed_per_tooth_um_range"]
    text = _chapter_0(f)
    assert "**Not stated:** spindle_rpm" in text and "[plan] lists the cuts." in text
