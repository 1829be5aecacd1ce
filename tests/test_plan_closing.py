"""Closing the loop (issue 28): the time-domain check agrees with the planner's stability
prediction on a planted tool, and results/plan/check.csv puts the stability and deflection
outcomes beside their predictions."""

import numpy as np
import pandas as pd
import pytest

from robomill.chatter.modal_timedomain import ModalCut, simulate_modal_cut, stability_verdict
from robomill.chatter.model import CuttingModel
from robomill.plan.check import check_table
from robomill.plan.lobes import batch_coupling_depth, batch_zoa_lobes

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
    a = min(batch_zoa_lobes(*args, np.array([rpm]))[0, 0], batch_coupling_depth(*args)[0])
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
SIM = pd.DataFrame({"cut": ["plan_01", "plan_02", "s1"], "stable": [True, True, False],
                    "deflection_normal_um": [10.5, 7.0, 3.0],
                    "deflection_axial_um": [2.1, 1.0, 0.5], "force_N": [15.05, 12.0, 7.0]})
MEAN = pd.DataFrame({"cut": ["s1"], "Fx_N": [3.0], "Fy_N": [6.0], "Fz_N": [2.0]})


def test_check_rows_for_stability_and_deflection():
    t = check_table(PRED, mean_forces=MEAN, simulated=SIM).set_index(["cut", "quantity"])
    s = t.loc[("plan_01", "stability")]
    assert (s["predicted"], s["low"], s["high"], s["outcome"]) == (0.8, 0.6, 1.0, 1.0)
    assert s["within_interval"] and s["within_tolerance"] and s["unit"] == "1"
    s = t.loc[("plan_02", "stability")]  # predicted chatter, simulated stable: both miss
    assert s["outcome"] == 1.0 and not s["within_interval"] and not s["within_tolerance"]
    s = t.loc[("s1", "stability")]       # interval straddles 0: chatter admitted, nominal wrong
    assert s["outcome"] == 0.0 and s["within_interval"] and not s["within_tolerance"]
    d = t.loc[("plan_01", "deflection_normal")]
    assert d["unit"] == "um" and d["outcome"] == 10.5 and d["within_interval"]
    d = t.loc[("plan_02", "deflection_normal")]  # 7 um outside 4-6 and 2/7 > 25 %
    assert not d["within_interval"] and not d["within_tolerance"]
    assert t.loc[("plan_02", "deflection_axial"), "within_interval"]
    assert ("s1", "deflection_normal") not in t.index        # no prediction, no row
    # force: the dynamometer's where it recorded the cut, the simulation's elsewhere
    assert t.loc[("s1", "force"), "source"] == "results/forces/mean_forces.csv"
    assert t.loc[("s1", "force"), "outcome"] == pytest.approx(7.0)
    assert t.loc[("plan_01", "force"), "source"] == "results/plan/simulated.csv"
    assert set(t.loc[("plan_01", "stability"), ["source"]]) == {"results/plan/simulated.csv"}


def test_real_data_stability_from_the_force_spectrum():
    peaks = pd.DataFrame({"cut": ["s1", "plan_01"], "dominant_power": [0.25, 1.0]})
    mean = pd.DataFrame({"cut": ["s1", "plan_01"], "Fx_N": [3.0, 0.0], "Fy_N": [6.0, 15.0],
                         "Fz_N": [2.0, 0.0]})
    # s1: line 0.5 N on 7 N (7 %) -> chatter; plan_01: 1 N on 15 N (6.7 %) at a 10 % limit
    t = check_table(PRED, mean_forces=mean, force_peaks=peaks,
                    chatter_fraction_of_mean=0.1).set_index(["cut", "quantity"])
    assert t.loc[("s1", "stability"), "outcome"] == 1.0
    assert t.loc[("plan_01", "stability"), "outcome"] == 1.0
    t = check_table(PRED, mean_forces=mean, force_peaks=peaks,
                    chatter_fraction_of_mean=0.05).set_index(["cut", "quantity"])
    assert t.loc[("s1", "stability"), "outcome"] == 0.0
    assert t.loc[("plan_01", "stability"), "outcome"] == 0.0
    assert t.loc[("s1", "stability"), "source"] == "results/forces/peaks.csv"


def test_summary_counts_and_the_chapter_follows_them():
    from robomill.pipeline.prose import Prose, load_templates
    from robomill.plan.check import check_summary

    t = check_table(PRED, mean_forces=MEAN, simulated=SIM)
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


def test_the_cells_modes_move_with_the_pose_only_below_the_robot_limit():
    from pathlib import Path

    import yaml

    from robomill.kinematics import robot_from_mapping
    from robomill.synth.cell import Mode, VirtualCell
    from robomill.synth.plancuts import modes_at_poses

    cfg = yaml.safe_load((Path(__file__).parents[1] / "config.yaml").read_text())
    robot = robot_from_mapping(cfg["cell"]["robot"])
    cell = VirtualCell(robot, [], [Mode(20.0, 0.04, 8e5, (0.0, 1.0, 0.0)),
                                   Mode(900.0, 0.02, 5e7, (0.0, 1.0, 0.0))], {}, {}, 0)
    q_ref = np.deg2rad([0.0, 20.0, 10.0, 0.0, 60.0, 0.0])
    q = np.stack([q_ref, np.deg2rad([30.0, 40.0, -10.0, 0.0, 50.0, 0.0])])
    c = 1.0 / np.array([1e6, 8e5, 4e5, 6e4, 5e4, 2e4])
    f, z, k, _ = modes_at_poses(cell, q, q_ref, c, 200.0)
    np.testing.assert_allclose(f[0], [20.0, 900.0])          # the reference pose: as measured
    np.testing.assert_allclose(k[0], [8e5, 5e7])
    assert not np.isclose(k[1, 0], 8e5) and k[1, 1] == 5e7   # the robot's mode moves
    np.testing.assert_allclose(f[1, 0] / 20.0, np.sqrt(k[1, 0] / 8e5))   # modal mass kept
    f0, _, k0, _ = modes_at_poses(cell, q, q_ref, None, 200.0)
    np.testing.assert_allclose(k0, [[8e5, 5e7]] * 2)


def test_a_planned_cut_is_cut_on_the_virtual_cell_at_its_pose():
    from pathlib import Path

    import yaml

    from robomill.forces import CuttingCoefficients, mean_milling_forces
    from robomill.synth.cell import cell_from_config
    from robomill.synth.plancuts import planned_cuts, planted_compliance, simulate_cuts

    cfg = yaml.safe_load((Path(__file__).parents[1] / "config.yaml").read_text())
    cell = cell_from_config(cfg)
    cut = {"id": "plan_01", "feed_mm_s": 10.0, "depth_mm": 0.2, "direction": "px",
           "spindle_rpm": 30000.0, "flutes": 2, "tool_diameter_mm": 6.0,
           "radial_immersion": 1.0, "milling": "slot", "start_mm": [580.0, 50.0, 200.0]}
    manifest = {"experiment": {"cut_length_mm": 40.0, "spindle_rpm": 30000.0, "flutes": 2},
                "cuts": [cut], "plan": {"cuts": {"plan_01": {"redundancy_deg": 45.0}}}}
    posed = planned_cuts(manifest)
    assert posed[0].redundancy_deg == 45.0
    np.testing.assert_allclose(posed[0].middle_mm, [600.0, 50.0, 200.0])
    t = simulate_cuts(posed, cell, planted_compliance(cfg), np.array([700.0, -50.0, 200.0]),
                      {"duration_s": 1.5})
    r = t.iloc[0]
    assert r["reachable"] and r["stable"]
    c = cfg["synth"]["cutting"]
    truth = CuttingCoefficients(c["Ktc_N_mm2"], c["Krc_N_mm2"], c["Kac_N_mm2"], c["Kte_N_mm"],
                                c["Kre_N_mm"], c["Kae_N_mm"])
    F = mean_milling_forces(10.0 * 60 / (2 * 30000.0), 0.2, truth)
    assert r["force_N"] == pytest.approx(np.linalg.norm(F), rel=0.01)
    assert 0 < r["deflection_normal_um"] < 50 and 0 < r["deflection_axial_um"] < 50


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
