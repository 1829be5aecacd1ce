"""Where the study does not reach (robomill.plan.extrapolation): the flags and their reasons,
the stated widening, and a planted mode above the impact test's band that the plan must not
claim to be stable against."""

import numpy as np
import pandas as pd
import pytest
from plan_cell import coefficients, default_cell

from robomill.chatter import CuttingModel, ModeXY, tool_from_modes, zoa_lobes
from robomill.plan.choose import PlanInfeasible, choose
from robomill.plan.extrapolation import StudyReach, reason_text
from robomill.plan.measured import Measured
from robomill.plan.predict import apply_extrapolation, predict_grid
from robomill.plan.request import parse_request

KTC, KRC = 800.0, 240.0
MEASURED = ModeXY(40.0, 0.04, 1.0e6, (0.0, 1.0))     # inside the impact test's 10-100 Hz
HIDDEN = ModeXY(400.0, 0.03, 2.0e6, (0.0, 1.0))      # above it: the test never saw it


@pytest.fixture(scope="module")
def cell():
    return default_cell()


def _coefficients():
    return coefficients(KTC, KRC)


def _modes(mode):
    # the mode along the wall normal of a cut fed along base Y (normal: base X)
    return pd.DataFrame({"f_n_hz": [mode.f_hz], "zeta": [mode.zeta],
                         "k_modal_N_m": [mode.k_N_m], "shape_x": [1.0], "shape_y": [0.0],
                         "shape_z": [0.0], "f_n_hz_low": [mode.f_hz * 0.995],
                         "f_n_hz_high": [mode.f_hz * 1.005], "zeta_low": [mode.zeta * 0.95],
                         "zeta_high": [mode.zeta * 1.05], "k_modal_N_m_low": [mode.k_N_m * 0.97],
                         "k_modal_N_m_high": [mode.k_N_m * 1.03]})


def _request(**extra):
    return parse_request({"kind": "plan", "operation": {"length_mm": 20, "directions": ["py"]},
                          "tool": {"diameter_mm": 6, "flutes": 2},
                          "placement": {"points_mm": [[650, 0, 200], [650, 400, 200]]},
                          "spindle_rpm": {"min": 1000, "max": 15000, "n": 57},
                          "depth_mm": [0.05, 0.5], "feed_mm_s": [1, 4], **extra})


def _plan(cell, req, reach):
    m = Measured(modes=_modes(MEASURED), coefficients=_coefficients())
    ds = predict_grid(req, m, cell)
    return ds, apply_extrapolation(ds, req, m, cell, reach)


def test_a_mode_above_the_band_enters_as_a_prior_and_its_interval_holds_the_truth(cell):
    """The impact test never saw HIDDEN (400 Hz); the request states a prior of modes above
    the band (250-700 Hz, 1-6 N/um, 2-5 %) that holds it. The truth: both modes, by the
    package's single-tool solver. The interval must hold the true limit at the speeds where
    the measured mode alone misleads (no claim of stability beyond the truth), without a cap
    at the measured modes' absolute limit (speeds inside the band keep their pockets)."""
    prior = {"members": 48, "tool_modes": [{"f_hz": [250.0, 700.0], "zeta": [0.02, 0.05],
                                            "k_N_m": [1.0e6, 6.0e6], "shape": [1, 0, 0]}]}
    req = _request(stability=prior)
    _, ds = _plan(cell, req, StudyReach(modal_band_hz=(10.0, 100.0)))
    rpm = ds["spindle_rpm"].values
    assert not bool(ds["extrapolation"].any())          # the band is no extrapolation reason
    cut = CuttingModel(2, KTC * 1e6, KRC / KTC, 0.0, np.pi)
    a_true, _ = zoa_lobes(tool_from_modes([MEASURED, HIDDEN]), cut, rpm)
    a_meas, _ = zoa_lobes(tool_from_modes([MEASURED]), cut, rpm)
    a_true = np.nan_to_num(a_true, nan=np.inf)
    a_meas = np.nan_to_num(a_meas, nan=np.inf)
    sel = {"placement": 0, "rotation": 0, "direction": 0}
    lo = ds["a_crit_low_mm"].isel(**sel).values * 1e-3
    hi = ds["a_crit_high_mm"].isel(**sel).values * 1e-3
    wrong = a_true < 0.5 * a_meas                          # where the measured mode misleads
    assert wrong.sum() >= 10
    assert np.all(lo[wrong] <= a_true[wrong] * 1.02)
    held = (lo <= a_true * 1.02) & (hi >= a_true * 0.98)
    assert held.mean() >= 0.9
    # p_stable at twice the true limit: the members mostly see the chatter
    p2 = ds["p_stable"].isel(**sel)
    assert p2.dims == ("spindle_rpm", "depth_mm")
    # no cap: the pessimistic limit still follows the lobes over the speeds (a cap at an
    # absolute limit would be one flat value)
    assert np.nanmax(lo) > 1.3 * np.nanmin(lo)


def test_the_widening_is_continuous_in_the_distance(cell):
    req = _request(spindle_rpm=[10000.0, 10007.0, 15000.0])
    _, ds = _plan(cell, req, StudyReach(spindle_rpm=(1000.0, 10000.0)))
    w = ds["interval_widening"].isel(placement=0, feed_mm_s=0).values
    assert w == pytest.approx([1.0, 1.0007, 1.5], rel=1e-9)


def test_ranges_and_poses_outside_the_study_widen_by_the_stated_rule(cell):
    req = _request(extrapolation={"max_pose_distance_mm": 100})
    reach = StudyReach(spindle_rpm=(1000.0, 10000.0), feed_per_tooth_mm=(0.002, 0.01),
                       radial_immersion=(1.0, 1.0),
                       midpoints_mm=np.array([[650.0, 20.0, 200.0]]))
    before, ds = _plan(cell, req, reach)
    sel = {"spindle_rpm": 15000.0, "feed_mm_s": 1.0}
    # 15000 rpm is 50 % above the identified 10000; c = 1·60/(2·15000) = 0.002 mm: inside
    assert reason_text(int(ds["extrapolation_code"].sel(placement=0, **sel))) == "spindle speed"
    assert float(ds["interval_widening"].sel(placement=0, **sel)) == pytest.approx(1.5)
    # placement 1 lies 380 mm from the study's cut, 100 mm allowed: e = 2.8
    assert float(ds["interval_widening"].sel(placement=1, **sel)) == pytest.approx(3.8)
    assert reason_text(int(ds["extrapolation_code"].sel(placement=1, **sel))) == \
        "spindle speed; pose"
    f, f0 = ds["force_high_N"].sel(depth_mm=0.5, **sel), before["force_high_N"].sel(
        depth_mm=0.5, **sel)
    nom = before["force_N"].sel(depth_mm=0.5, **sel)
    assert float(f - nom) == pytest.approx(3.8 * float(f0 - nom), rel=1e-9)
    # 4 mm/s at 1000 rpm: c = 0.12 mm, 11 times the identified 0.01 mm
    c_sel = {"spindle_rpm": 1000.0, "feed_mm_s": 4.0}
    assert "feed per tooth" in reason_text(int(ds["extrapolation_code"].sel(placement=0,
                                                                              **c_sel)))
    inside = {"spindle_rpm": 5000.0, "feed_mm_s": 1.0}       # c = 0.006 mm
    assert not bool(ds["extrapolation"].sel(placement=0, **inside))


def test_one_line_when_every_candidate_is_extrapolated_and_none_is_allowed(cell):
    req = _request(extrapolation={"allow": False})
    _, ds = _plan(cell, req, StudyReach(spindle_rpm=(50.0, 100.0)))
    with pytest.raises(PlanInfeasible) as e:
        choose(ds, req)
    msg = str(e.value)
    assert "\n" not in msg and "extrapolated" in msg and "spindle speed" in msg


def test_chapter_7_states_the_band_against_the_chosen_speeds():
    from robomill.pipeline.prose import Prose, load_templates
    from robomill.plan.extrapolation import reach_values

    chosen = pd.DataFrame({"tooth_passing_hz": [933.3, 1000.0, 60.0],
                           "extrapolation": [True, True, False],
                           "extrapolation_reason": ["modal band", "spindle speed; modal band",
                                                    ""]})
    attrs = {"interval_level": 0.9, "modal_band_hz": [10.0, 100.0],
             "extrapolation_harmonics": 1}
    v = reach_values(chosen, attrs)
    assert v["n_above_band"] == 2 and v["band_case"] == "above" and v["n_extrapolated"] == 2
    assert v["reasons"] == "modal band, spindle speed"
    text = Prose(load_templates("ch7"), v)("reach_level", "reach_extrapolated", "reach_band")
    assert "90 %" in text and "10–100 Hz" in text and "60–1000 Hz" in text
    inside = reach_values(chosen.iloc[2:], attrs)
    assert inside["band_case"] == "inside" and inside["n_extrapolated"] == 0
    assert "stays inside it" in Prose(load_templates("ch7"), inside)("reach_band")
    assert Prose(load_templates("ch7"), v)("reach_direction") == ""


def test_chapter_7_says_why_a_cut_whose_direction_was_not_measured_is_flagged():
    from robomill.pipeline.prose import Prose, load_templates
    from robomill.plan.extrapolation import reach_values, reason_text

    codes = [32 | 128, 1, 128]                       # X and Z; speed alone; Z
    chosen = pd.DataFrame({"tooth_passing_hz": [50.0, 60.0, 70.0],
                           "extrapolation": [True, True, True],
                           "extrapolation_reason": [reason_text(c) for c in codes]})
    v = reach_values(chosen, {"interval_level": 0.95, "modal_band_hz": [10.0, 100.0]})
    assert v["axes_not_measured"] == "X, Z" and v["n_direction_not_measured"] == 2
    text = Prose(load_templates("ch7"), v)("reach_direction")
    assert text.startswith("2 of the chosen cuts are flagged `direction not measured: X, Z`")
    assert "no interval is widened for it" in text


def test_the_modes_intervals_carry_into_the_critical_depth(cell):
    """One mode, exact coefficients: the lobes' minimum scales with k ζ (1 + ζ) (Altintas 2012
    §4.3), so the members (ζ and k drawn with the σ of their 95 % intervals, 5 % and 3 %) put
    the pessimistic end of the minimum below the nominal's, but not below ζ and k both at
    3 σ: 0.923 · 0.954 (1 + 0.923 ζ)/(1 + ζ); without intervals the interval is a point."""
    names = ["Ktc", "Krc", "Kac", "Kte", "Kre", "Kae"]
    vals = [KTC, KRC, 200.0, 25.0, 30.0, 6.0]
    coeffs = pd.DataFrame({"name": names, "value": vals, "ci_low": vals, "ci_high": vals})
    req = _request()
    m = Measured(modes=_modes(MEASURED), coefficients=coeffs)
    ds = predict_grid(req, m, cell)
    sel = {"placement": 0, "rotation": 0, "direction": 0}
    a = ds["a_crit_mm"].isel(**sel).values
    lo = ds["a_crit_low_mm"].isel(**sel).values
    z = MEASURED.zeta
    r3 = (1 - 3 * 0.05 / 1.96) * (1 - 3 * 0.03 / 1.96) * (1 + (1 - 3 * 0.05 / 1.96) * z) / (1 + z)
    assert r3 < lo.min() / a.min() < 0.995
    bare = predict_grid(req, Measured(modes=_modes(MEASURED).iloc[:, :6], coefficients=coeffs),
                        cell)
    a_bare = bare["a_crit_mm"].isel(**sel).values
    assert np.allclose(bare["a_crit_low_mm"].isel(**sel).values, a_bare)  # a point
    assert np.allclose(bare["a_crit_high_mm"].isel(**sel).values, a_bare)


def test_the_studys_own_stable_cuts_stay_inside_what_the_plan_allows(cell):
    """A study cut at 28 000 rpm, 0.5 mm deep, judged stable, its tooth frequency (933 Hz) far
    above the impact test's 10-100 Hz band, predicted at its own pose with the study's reach:
    inside what the study covered (no extrapolation flag, no modal-band cap), it meets the
    plan's stability constraints (p_stable ≥ 0.95, pessimistic margin ≥ 0.2), before and
    after its own verdict weights the members."""
    import dataclasses

    from robomill.experiment import Cut
    from robomill.plan.compare import predict_study_cut
    from robomill.plan.make import verdict_conditioned

    prior = {"members": 24, "tool_modes": [{"f_hz": [1500.0, 4000.0], "zeta": [0.02, 0.06],
                                            "k_N_m": [3.0e7, 3.0e8], "shape": [1, 0, 0]}]}
    req = _request(stability=prior, constraints={"min_stability_margin": 0.2})
    m = Measured(modes=_modes(MEASURED), coefficients=_coefficients())
    exp = {"spindle_rpm": 28000.0, "flutes": 2, "tool_diameter_mm": 6.0, "cut_length_mm": 20.0}
    cut = Cut("s2_g5_py", 2, 5, "py", 5.0, 0.5, start_mm=(650.0, -10.0, 199.5))
    reach = StudyReach(spindle_rpm=(28000.0, 28000.0), feed_per_tooth_mm=(0.001, 0.011),
                       radial_immersion=(1.0, 1.0), midpoints_mm=np.array([[650.0, 0.0, 200.0]]),
                       modal_band_hz=(10.0, 100.0))
    row = predict_study_cut(cut, exp, req, m, cell, reach)
    assert row["reachable"] and not row["extrapolation"]
    assert row["p_stable"] >= 0.95 and row["stability_margin_low"] >= 0.2 and row["feasible"]
    m2, ev = verdict_conditioned(m, req, cell, [cut], exp, pd.Series({cut.id: 1.0}))
    assert ev is not None and ev.n_used == 1
    again = predict_study_cut(dataclasses.replace(cut), exp, req, m2, cell, reach)
    assert again["p_stable"] >= 0.95 and again["feasible"]
