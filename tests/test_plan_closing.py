"""Closing the loop: the time-domain check agrees with the planner's stability prediction on a
planted tool, and results/plan/check.csv puts the outcomes a run's files recorded (chatter
verdicts, loaded-minus-air tracker deflections, mean forces) beside their predictions, says
which rows are in-sample and counts how often the out-of-sample intervals held."""

import numpy as np
import pandas as pd
import pytest

from robomill.chatter.modal_timedomain import ModalCut, simulate_modal_cut, stability_verdict
from robomill.chatter.model import CuttingModel
from robomill.plan.check import RunOutcomes, check_table
from robomill.plan.lobes import batch_zoa_lobes

# one mode along the wall normal, slot milling with two teeth (no edge forces)
F_HZ, ZETA, K_N_M = 2000.0, 0.03, 2.0e7
KT_N_M2, KR, TEETH = 6.0e8, 0.3, 2
# Tlusty's absolute limit of a single mode in a slot (written by hand, not by the library):
# the mean oriented coefficient along y is −N K_t K_r / 4, the most negative real part of the
# receptance −1/(4 k ζ (1 + ζ)), so a_lim = 1/(2 · N K_t K_r/4 · 1/(4kζ(1+ζ)))
A_LIM_M = 8 * K_N_M * ZETA * (1 + ZETA) / (TEETH * KT_N_M2 * KR)


def predicted_margin(depth_m, rpm):
    cut = CuttingModel(TEETH, KT_N_M2, KR, 0.0, np.pi)
    args = ([[F_HZ]], [ZETA], [[K_N_M]], [[[0.0, 1.0]]], cut)
    a = batch_zoa_lobes(*args, np.array([rpm]))[0, 0]
    return a / depth_m - 1


def simulated_stable(depth_m, rpm):
    runs = [simulate_modal_cut(
        ModalCut(np.array([F_HZ]), np.array([ZETA]), np.array([K_N_M]),
                 np.array([[0.0, 1.0]]), rpm, TEETH, 0.0, np.pi, 5e-5, depth_m, KT_N_M2,
                 KR * KT_N_M2, 0.0, overlap=mu),
        duration_s=0.6, steps_per_tooth=256, Kt_noise_fraction=0.005, noise_seed=1)
        for mu in (1.0, 0.0)]
    return stability_verdict(*runs, TEETH * rpm / 60.0, band_hz=(100.0, 5000.0),
                             harmonic_halfwidth_hz=10.0, growth_ratio=3.0).stable


@pytest.mark.parametrize("rpm", [6000.0, 7000.0])
def test_well_below_the_limit_is_stable_in_both(rpm):
    depth = 0.4 * A_LIM_M
    assert predicted_margin(depth, rpm) > 0
    assert simulated_stable(depth, rpm)


@pytest.mark.parametrize("rpm", [6000.0, 7000.0])
def test_well_above_the_limit_chatters_in_both(rpm):
    depth = 3.0 * A_LIM_M
    assert predicted_margin(depth, rpm) < 0
    assert not simulated_stable(depth, rpm)


def test_without_vibration_the_mean_force_is_the_closed_form():
    from robomill.forces import CuttingCoefficients, mean_milling_forces

    cut = ModalCut(np.array([50.0]), np.array([0.05]), np.array([1e12]),
                   np.array([[0.0, 1.0]]), 30000.0, 2, 0.0, np.pi, 1e-5, 5e-4,
                   796e6, 168e6, 222e6, 27.7e3, 30.8e3, 6.7e3)
    F = simulate_modal_cut(cut, duration_s=0.02, steps_per_tooth=2048,
                           Kt_noise_fraction=0.0)["force_N"].mean(0)
    ref = mean_milling_forces(0.01, 0.5, CuttingCoefficients(796, 168, 222, 27.7, 30.8, 6.7))
    np.testing.assert_allclose(F, ref, rtol=2e-3)


def test_the_structures_own_excitation_moves_one_mode_as_its_receptance_says():
    """Without material (depth 0) the excitation alone moves the tool: one 80 Hz mode along y
    (ζ 0.05, 10⁶ N/m) under a white force of 5 N rms low-passed to 1 kHz. The regenerative
    displacement Δ = d(t) − d(t − τ) then has the variance, written by hand from the
    receptance H = 1/(k (1 − r² + 2iζr)) and the filter (a Butterworth's |B|² = 1/(1 + (f/f_c)⁸),
    squared once more by the zero-phase pass): σ_Δ² = σ_F² ∫ 4 sin²(πfτ) |H|² |B|⁴ df /
    ∫ |B|⁴ df. Along x nothing moves (the mode's shape has no x)."""
    f_n, zeta, k, sigma = 80.0, 0.05, 1.0e6, 5.0
    rpm, teeth = 12000.0, 2
    tau = 60.0 / (teeth * rpm)
    rec = simulate_modal_cut(
        ModalCut(np.array([f_n]), np.array([zeta]), np.array([k]), np.array([[0.0, 1.0]]),
                 rpm, teeth, 0.0, np.pi, 1e-5, 0.0, KT_N_M2, KR * KT_N_M2, 0.0),
        duration_s=30.0, steps_per_tooth=16, excitation_N=sigma, noise_seed=3)
    keep = rec["t_s"] > 1.0
    d = rec["delta_m"][keep]
    f = np.linspace(0.0, 5000.0, 500001)
    r = f / f_n
    H2 = 1.0 / (k**2 * ((1 - r**2) ** 2 + (2 * zeta * r) ** 2))
    B4 = 1.0 / (1.0 + (f / 1000.0) ** 8) ** 2
    var = sigma**2 * np.trapezoid(4 * np.sin(np.pi * f * tau) ** 2 * H2 * B4, f) / \
        np.trapezoid(B4, f)
    assert np.std(d[:, 1]) == pytest.approx(np.sqrt(var), rel=0.06)
    assert np.std(d[:, 0]) == 0.0


PRED = pd.DataFrame({
    "cut": ["plan_01", "plan_02", "s1"],
    "stability_margin": [0.8, -0.5, 0.1], "stability_margin_low": [0.6, -0.7, -0.1],
    "stability_margin_high": [1.0, -0.3, 0.3],
    "deflection_normal_um": [10.0, 5.0, np.nan], "deflection_normal_low_um": [9.0, 4.0, np.nan],
    "deflection_normal_high_um": [11.0, 6.0, np.nan],
    "deflection_axial_um": [2.0, 1.0, np.nan], "deflection_axial_low_um": [1.8, 0.9, np.nan],
    "deflection_axial_high_um": [2.2, 1.1, np.nan],
    "force_N": [15.0, 12.0, 7.0], "force_low_N": [14.9, 11.9, 6.9],
    "force_high_N": [15.1, 12.1, 7.1]})
NEXT = "results/plan/next/run"
# the planned cuts' own run: chatter verdicts (plan_02 heard twice, one recording
# undetermined), loaded-minus-air deflections (signed: the planner predicts magnitudes)
PLANNED = RunOutcomes(
    NEXT,
    mean_forces=pd.DataFrame({"cut": ["plan_01", "plan_02"], "Fx_N": [0.0, 0.0],
                              "Fy_N": [15.05, 12.0], "Fz_N": [0.0, 0.0]}),
    verdicts=pd.DataFrame({"cut": ["plan_01", "plan_02", "plan_02"],
                           "verdict": ["stable", "stable", "undetermined"],
                           "chatter_hz": [np.nan] * 3,
                           "source": ["forces/plan_01.h5", "forces/plan_02.h5", "mic/p2.wav"],
                           "evidence": ["", "", ""]}),
    deflection=pd.DataFrame({"cut": ["plan_01", "plan_02"], "loaded_run": ["plan_01", "plan_02"],
                             "air_run": ["plan_01_air", "plan_02_air"],
                             "deflection_normal_um": [-10.5, 7.0],
                             "deflection_axial_um": [2.1, -1.0]}))
MEAN = pd.DataFrame({"cut": ["s1"], "Fx_N": [3.0], "Fy_N": [6.0], "Fz_N": [2.0]})
# the study: s1's force spectrum has a 1 N line on 7 N, above 5 %: chatter
STUDY = RunOutcomes(mean_forces=MEAN,
                    force_peaks=pd.DataFrame({"cut": ["s1"], "dominant_power": [1.0]}))


def check():
    return check_table(PRED, study=STUDY, planned_run=PLANNED, identified_cuts=["s1"])


def test_check_rows_for_stability_and_deflection():
    t = check().set_index(["cut", "quantity"])
    s = t.loc[("plan_01", "stability")]
    assert (s["predicted"], s["low"], s["high"], s["outcome"]) == (0.8, 0.6, 1.0, 1.0)
    assert s["within_interval"] and s["within_tolerance"] and s["unit"] == "1" and s["held"]
    s = t.loc[("plan_02", "stability")]  # predicted chatter, measured stable: both miss
    assert s["outcome"] == 1.0 and not s["within_interval"] and not s["within_tolerance"]
    assert not s["held"]
    s = t.loc[("s1", "stability")]       # interval straddles 0: chatter admitted, nominal wrong
    assert s["outcome"] == 0.0 and s["within_interval"] and not s["within_tolerance"]
    assert s["held"] and s["source"] == "results/forces/peaks.csv"
    d = t.loc[("plan_01", "deflection_normal")]
    assert d["unit"] == "um" and d["outcome"] == 10.5 and d["within_interval"] and d["held"]
    d = t.loc[("plan_02", "deflection_normal")]  # 7 um outside 4-6 and 2/7 > 25 %
    assert not d["within_interval"] and not d["within_tolerance"] and not d["held"]
    assert t.loc[("plan_02", "deflection_axial"), "held"]      # |-1.0| inside 0.9-1.1
    assert ("s1", "deflection_normal") not in t.index        # no prediction, no row
    assert t.loc[("s1", "force"), "source"] == "results/forces/mean_forces.csv"
    assert t.loc[("s1", "force"), "outcome"] == pytest.approx(7.0)
    # the planned cuts: every outcome from their own run's files
    for q, f in (("force", "results/forces/mean_forces.csv"),
                 ("stability", "results/chatter/verdicts.csv"),
                 ("deflection_normal", "results/straightness/deflection.csv"),
                 ("deflection_axial", "results/straightness/deflection.csv")):
        assert set(t.loc[(["plan_01", "plan_02"], q), "source"]) == {f"{NEXT}/{f}"}
    # in-sample: the study's cut only
    assert t["in_sample"].groupby(level="cut").all().to_dict() == {
        "plan_01": False, "plan_02": False, "s1": True}


def test_an_undetermined_verdict_leaves_the_row_unjudged():
    verdicts = pd.DataFrame({"cut": ["plan_01", "plan_02", "plan_02"],
                             "verdict": ["undetermined", "stable", "chatter"],
                             "chatter_hz": [np.nan, np.nan, 31.0], "source": "f",
                             "evidence": ""})
    run = RunOutcomes(NEXT, verdicts=verdicts)
    t = check_table(PRED, planned_run=run).set_index(["cut", "quantity"])
    a = t.loc[("plan_01", "stability")]
    assert np.isnan(a["outcome"]) and pd.isna(a["held"]) and pd.isna(a["within_interval"])
    b = t.loc[("plan_02", "stability")]   # one recording chatters: the cut chattered
    assert b["outcome"] == 0.0 and b["held"]


def test_a_verdicts_file_off_its_contract_is_one_line(tmp_path):
    from robomill.errors import RawDataError
    from robomill.plan.evidence import read_verdicts

    f = tmp_path / "verdicts.csv"
    f.write_text("cut,verdict,chatter_hz,source,evidence\nplan_01,stable,,a,\n"
                 "plan_02,wobbly,,b,\n")
    with pytest.raises(RawDataError, match=r"verdicts.csv: row 3, column verdict: verdict "
                                           r"is 'wobbly' \(expected stable \| chatter"):
        read_verdicts(f)
    f.write_text("cut,verdict\nplan_01,stable\n")
    with pytest.raises(RawDataError, match="chatter_hz, source, evidence missing"):
        read_verdicts(f)
    f.write_text("cut,verdict,chatter_hz,source,evidence\nplan_01,chatter,31.5,a,line\n")
    assert read_verdicts(f)["chatter_hz"].tolist() == [31.5]


def test_real_data_stability_from_the_force_spectrum():
    peaks = pd.DataFrame({"cut": ["s1", "plan_01"], "dominant_power": [0.25, 1.0]})
    mean = pd.DataFrame({"cut": ["s1", "plan_01"], "Fx_N": [3.0, 0.0], "Fy_N": [6.0, 15.0],
                         "Fz_N": [2.0, 0.0]})
    study = RunOutcomes(mean_forces=mean, force_peaks=peaks)
    # s1: line 0.5 N on 7 N (7 %) -> chatter; plan_01: 1 N on 15 N (6.7 %) at a 10 % limit
    t = check_table(PRED, study=study,
                    chatter_fraction_of_mean=0.1).set_index(["cut", "quantity"])
    assert t.loc[("s1", "stability"), "outcome"] == 1.0
    assert t.loc[("plan_01", "stability"), "outcome"] == 1.0
    t = check_table(PRED, study=study,
                    chatter_fraction_of_mean=0.05).set_index(["cut", "quantity"])
    assert t.loc[("s1", "stability"), "outcome"] == 0.0
    assert t.loc[("plan_01", "stability"), "outcome"] == 0.0
    assert t.loc[("s1", "stability"), "source"] == "results/forces/peaks.csv"


def test_summary_counts_and_the_chapter_follows_them():
    from robomill.pipeline.prose import Prose, load_templates
    from robomill.plan.check import check_summary

    t = check()
    s = check_summary(t, tolerance=0.25)
    # plan_01 predicted stable and stable; plan_02 predicted chatter; s1 predicted stable, chattered
    assert s["n_predicted_stable_plan"] == 1 and s["n_predicted_stable_stable_plan"] == 1
    assert s["n_predicted_stable"] == 2 and s["n_predicted_stable_stable"] == 1
    assert s["n_stability_agree"] == 1
    assert s["n_deflection_normal_plan"] == 2 and s["n_deflection_normal_in_interval_plan"] == 1
    say = Prose(load_templates("ch7"), {**s, "n_predicted_stable_stable_plan": 7.0,
                                        "tolerance_percent": 13.0})
    assert "7 of these" in say("check_stability_plan")
    assert "13 %" in say("check_deflection")
    assert say("check_deflection") != Prose(load_templates("ch7"), s)("check_deflection")
    empty = Prose(load_templates("ch7"), check_summary(t.iloc[:0]))
    assert empty("check_stability_plan") == "No planned cut has a stability outcome yet."


def test_out_of_sample_rows_are_counted_apart_with_their_coverage():
    from robomill.plan.check import check_summary
    from robomill.plan.evidence import coverage_case

    t = check()
    s = check_summary(t, tolerance=0.25, nominal_coverage=0.9)
    # out of sample: plan_01 force 15.05 in 14.9-15.1, stability held, deflection both held;
    # plan_02 force 12.0 in 11.9-12.1, stability missed, normal 7 missed, axial held: 6 of 8
    assert (s["n_oos"], s["n_judged_oos"], s["n_held_oos"]) == (8, 8, 6)
    assert s["coverage_oos_percent"] == pytest.approx(75.0)
    assert s["n_stability_oos"] == 2 and s["n_stability_held_oos"] == 1
    # in sample: s1 force 7.0 in 6.9-7.1 and its stability (straddling interval): 2 of 2
    assert (s["n_in"], s["n_held_in"]) == (2, 2)
    assert s["nominal_coverage_percent"] == pytest.approx(90.0)
    # binomial(8, 0.9): 2.5 % and 97.5 % quantiles 5 and 8 (by hand: P(X <= 5) = 0.038)
    assert (s["held_range_low_oos"], s["held_range_high_oos"]) == (5.0, 8.0)
    assert coverage_case(s) == "consistent"
    assert coverage_case({**s, "n_held_oos": 4.0}) == "below"
    assert coverage_case({"n_judged_oos": 0.0}) == "none"


def test_the_table_written_and_read_back_keeps_empty_verdicts_unjudged(tmp_path):
    from robomill.io import write_table
    from robomill.plan.check import check_summary

    verdicts = PLANNED.verdicts.assign(verdict=["undetermined", "stable", "stable"])
    t = check_table(PRED, study=STUDY, identified_cuts=["s1"],
                    planned_run=RunOutcomes(NEXT, verdicts=verdicts))
    write_table(t, tmp_path / "check.csv")
    back = pd.read_csv(tmp_path / "check.csv")
    a, b = check_summary(t), check_summary(back)
    assert a == pytest.approx(b, nan_ok=True)
    assert a["n_stability_judged_oos"] == 1 and a["n_stability_oos"] == 2


def test_chapter_7_states_the_request_and_what_it_could_not_predict():
    """The request sentence follows the candidates' attributes (templates/ch7.yaml)."""
    from robomill.pipeline.prose import Prose, load_templates

    say = Prose(load_templates("ch7"), {})
    one = say("request", "missing_predictions", request="r.yaml", constraints="",
              missing_predictions="waviness (no tracker runs)")
    assert one == ("Request `r.yaml`, constraints none. Missing predictions (planned without "
                   "them): waviness (no tracker runs).")
    two = say("request", "missing_predictions", request="p.yaml",
              constraints="max_force_N=100.0", missing_predictions="")
    assert two == "Request `p.yaml`, constraints max_force_N=100.0. Every prediction could be made."


def test_chapter_7_states_the_coverage_against_the_nominal_level():
    """The coverage sentence follows check_summary.csv (templates/ch7.yaml): the counts held
    out-of-sample, the nominal level and, below it, that the intervals are too narrow."""
    from robomill.pipeline.prose import Prose, load_templates
    from robomill.plan.check import check_summary
    from robomill.plan.evidence import coverage_case

    s = check_summary(check(), tolerance=0.25, nominal_coverage=0.9)
    say = Prose(load_templates("ch7"), {**s, "coverage_case": coverage_case(s)})
    text = say("check_coverage")
    assert "6 of 8 outcomes fell inside" in text and "**75 %**" in text
    assert "nominal 90 %: consistent" in text and "In-sample, 2 of 2." in text
    low = {**s, "n_held_oos": 2.0, "coverage_oos_percent": 25.0}
    text = Prose(load_templates("ch7"), {**low, "coverage_case": coverage_case(low)})(
        "check_coverage")
    assert "narrower than the truth" in text and "fewer than the 5" in text
    none = check_summary(check_table(PRED, study=STUDY, identified_cuts=["s1"]))
    text = Prose(load_templates("ch7"), {**none, "coverage_case": coverage_case(none)})(
        "check_coverage")
    assert text.startswith("No out-of-sample outcome has been judged yet")


def test_a_cut_without_a_prediction_has_no_row_even_with_an_outcome():
    """The study tracked s1 loaded and in the air, but the plan made no deflection prediction
    for it (NaN): no row, rather than a miss."""
    study = RunOutcomes(mean_forces=MEAN, deflection=pd.DataFrame(
        {"cut": ["s1"], "loaded_run": ["r"], "air_run": ["a"],
         "deflection_normal_um": [4.0], "deflection_axial_um": [1.0]}))
    t = check_table(PRED, study=study).set_index(["cut", "quantity"])
    assert ("s1", "deflection_normal") not in t.index and ("s1", "force") in t.index


def test_brier_score_and_sharpness_by_hand():
    """Two judged stability rows with p 0.9 (stable) and 0.3 (chatter): B = (0.1² + 0.3²)/2;
    a force interval 90-110 around 100 and one 45-55 around 50: half-width 10 % both; an
    undetermined stability row and one without a probability do not count."""
    from robomill.plan.check import CHECK_COLUMNS, check_summary

    rows = [
        {"cut": "a", "quantity": "stability", "predicted": 1.0, "low": 0.5, "high": 2.0,
         "outcome": 1.0, "p_stable": 0.9},
        {"cut": "b", "quantity": "stability", "predicted": -0.2, "low": -0.5, "high": 0.1,
         "outcome": 0.0, "p_stable": 0.3},
        {"cut": "c", "quantity": "stability", "predicted": 0.5, "low": 0.1, "high": 1.0,
         "outcome": np.nan, "p_stable": 0.8},
        {"cut": "d", "quantity": "stability", "predicted": 0.5, "low": 0.1, "high": 1.0,
         "outcome": 1.0, "p_stable": np.nan},
        {"cut": "a", "quantity": "force", "predicted": 100.0, "low": 90.0, "high": 110.0,
         "outcome": 95.0},
        {"cut": "b", "quantity": "force", "predicted": 50.0, "low": 45.0, "high": 55.0,
         "outcome": 70.0},
    ]
    t = pd.DataFrame(rows).reindex(columns=CHECK_COLUMNS)
    t["in_sample"] = False
    s = check_summary(t)
    assert s["brier_score"] == pytest.approx((0.1**2 + 0.3**2) / 2)
    assert s["n_brier"] == 2
    assert s["sharpness_force_percent"] == pytest.approx(10.0)
    assert s["sharpness_force_oos_percent"] == pytest.approx(10.0)


def test_the_stability_row_is_judged_on_the_critical_depth():
    """A stable outcome bounds the true a_crit from below by the cut's depth, a chatter outcome
    from above: the row holds where the predicted a_crit interval reaches that side, and it is
    decisive only where the depth lies inside the interval. By hand: a 0.05 mm cut under an
    a_crit of 6 mm [5, +inf] that stayed stable holds but is not decisive (depth/a_crit 1/120); a
    0.5 mm cut under [0.4, 0.9] that chattered holds (0.4 < 0.5) and is decisive, its nominal
    0.6 mm on the wrong side; a 1 mm cut under [1.2, 3] that chattered misses."""
    from robomill.plan.check import check_summary

    pred = pd.DataFrame({
        "cut": ["plan_01", "plan_02", "plan_03"], "depth_mm": [0.05, 0.5, 1.0],
        "a_crit_mm": [6.0, 0.6, 2.0], "a_crit_low_mm": [5.0, 0.4, 1.2],
        "a_crit_high_mm": [np.inf, 0.9, 3.0]})  # plan_01: no chatter at any depth in reach
    pred["stability_margin"] = pred["a_crit_mm"] / pred["depth_mm"] - 1
    pred["stability_margin_low"] = pred["a_crit_low_mm"] / pred["depth_mm"] - 1
    pred["stability_margin_high"] = pred["a_crit_high_mm"] / pred["depth_mm"] - 1
    verdicts = pd.DataFrame({"cut": ["plan_01", "plan_02", "plan_03"],
                             "verdict": ["stable", "chatter", "chatter"],
                             "chatter_hz": [np.nan, 900.0, 900.0], "source": ["a", "b", "c"],
                             "evidence": ["", "", ""]})
    t = check_table(pred, planned_run=RunOutcomes(NEXT, verdicts=verdicts))
    t = t.set_index("cut")
    assert t.loc["plan_01", "held"] and not t.loc["plan_01", "decisive"]
    assert t.loc["plan_01", "depth_over_a_crit"] == pytest.approx(0.05 / 6.0)
    assert t.loc["plan_02", "held"] and t.loc["plan_02", "decisive"]
    assert not t.loc["plan_02", "within_tolerance"]
    assert not t.loc["plan_03", "held"] and not t.loc["plan_03", "decisive"]
    s = check_summary(t.reset_index())
    assert s["n_stability_decisive_oos"] == 1 and s["n_stability_decisive_agree_oos"] == 0
    assert s["median_depth_over_a_crit_oos"] == pytest.approx(0.5)
    from robomill.pipeline.prose import Prose, load_templates

    text = Prose(load_templates("ch7"), s)("check_decisive")
    assert "median 0.5 of their predicted critical depth" in text
    assert "1 of them inside its interval" in text and "for 0 of these" in text
    assert Prose(load_templates("ch7"), {})("check_decisive").startswith("No out-of-sample")


def test_stability_sharpness_on_the_critical_depth_by_hand():
    """The stability row's sharpness is the a_crit interval's half-width over the nominal
    a_crit: 2 mm in [1, 4] is 75 %, 5 mm in [4, 6] is 20 %, their median 47.5 %; a judged row
    whose interval is unbounded (high +inf) is counted apart, an undetermined row not at all,
    and the in-sample row (5 mm in [4, 6]) leaves the out-of-sample median at 75 %."""
    from robomill.plan.check import CHECK_COLUMNS, sharpness

    def row(cut, a, lo, hi, outcome, in_sample):
        return {"cut": cut, "quantity": "stability", "predicted": a / 0.5 - 1, "low": np.nan,
                "high": np.nan, "outcome": outcome, "a_crit_mm": a, "a_crit_low_mm": lo,
                "a_crit_high_mm": hi, "depth_mm": 0.5, "in_sample": in_sample}

    t = pd.DataFrame([row("a", 2.0, 1.0, 4.0, 1.0, False), row("b", 5.0, 4.0, 6.0, 0.0, True),
                      row("c", 3.0, 1.0, np.inf, 1.0, False),
                      row("d", 3.0, 2.9, 3.1, np.nan, False)]).reindex(columns=CHECK_COLUMNS)
    s = sharpness(t)
    assert s["sharpness_stability_percent"] == pytest.approx(47.5)
    assert s["sharpness_stability_oos_percent"] == pytest.approx(75.0)
    assert (s["n_stability_bounded"], s["n_stability_unbounded"]) == (2, 1)
    assert (s["n_stability_bounded_oos"], s["n_stability_unbounded_oos"]) == (1, 1)
