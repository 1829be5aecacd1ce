"""Designs that learn (purpose: learn): the pair of cuts straddles a planted stability limit,
and every learn cut says why it was chosen and what it should narrow."""

import numpy as np
import pandas as pd
import pytest
import yaml

from robomill.chatter import CuttingModel, ModeXY, tool_from_modes, zoa_lobes
from robomill.kinematics import robot_from_mapping
from robomill.plan.extrapolation import StudyReach
from robomill.plan.learn import learn_design
from robomill.plan.material import segment_distance_mm, slot_segment
from robomill.plan.measured import Measured
from robomill.plan.predict import Cell, apply_extrapolation, predict_grid
from robomill.plan.request import parse_request

KTC, KRC = 800.0, 240.0
PLANTED = ModeXY(40.0, 0.04, 1.0e6, (0.0, 1.0))      # along the wall normal of a py cut


def _toy():
    """Candidates of a one-mode toy request (the planted mode, narrow identification
    intervals), the request and the study's reach."""
    cfg = yaml.safe_load(open("config.yaml"))["cell"]
    cell = Cell(robot_from_mapping(cfg["robot"]), np.asarray(cfg["tool_rotation"], float),
                np.deg2rad(cfg["q_home_deg"]), np.array([650.0, 0.0, 200.0]))
    spread = {"f_n_hz": 0.002, "zeta": 0.1, "k_modal_N_m": 0.1}
    modes = pd.DataFrame({"f_n_hz": [PLANTED.f_hz], "zeta": [PLANTED.zeta],
                          "k_modal_N_m": [PLANTED.k_N_m], "shape_x": [1.0], "shape_y": [0.0],
                          "shape_z": [0.0]})
    for name, rel in spread.items():
        modes[f"{name}_low"] = modes[name] * (1 - rel)
        modes[f"{name}_high"] = modes[name] * (1 + rel)
    names = ["Ktc", "Krc", "Kac", "Kte", "Kre", "Kae"]
    vals = [KTC, KRC, 200.0, 25.0, 30.0, 6.0]
    coeffs = pd.DataFrame({"name": names, "value": vals, "ci_low": vals, "ci_high": vals})
    req = parse_request({"kind": "plan", "purpose": "learn",
                         "operation": {"length_mm": 20, "directions": ["py"]},
                         "tool": {"diameter_mm": 6, "flutes": 2},
                         "placement": {"points_mm": [[650, 0, 200], [650, 150, 200]]},
                         # tooth frequencies from 50 Hz: a lobe squeezed between the mode
                         # and a tooth frequency within a few % of it is resolved coarsely
                         # (robomill.plan.stability's frequency grid)
                         "spindle_rpm": {"min": 1500, "max": 2900, "n": 29},
                         "depth_mm": {"min": 0.25, "max": 12.0, "n": 48},
                         "feed_mm_s": [1, 2], "n_cuts": 4,
                         "extrapolation": {"max_pose_distance_mm": 100}})
    m = Measured(modes=modes, coefficients=coeffs)
    reach = StudyReach(modal_band_hz=(10.0, 100.0), midpoints_mm=np.array([[650, 0, 200.0]]))
    return apply_extrapolation(predict_grid(req, m, cell), req, m, cell, reach), req, reach


def test_learn_pair_straddles_the_planted_stability_limit():
    ds, req, reach = _toy()
    d = learn_design(ds, req, midpoints_mm=reach.midpoints_mm)
    assert len(d) >= 3 and d["reason"].str.len().gt(0).all()
    assert d["expected_narrowing"].between(0, 1).all()
    below, above = d.iloc[0], d.iloc[1]
    assert below["spindle_rpm"] == above["spindle_rpm"]
    assert below["depth_mm"] < above["depth_mm"]
    # below the interval's low end (stable at its level), above the nominal limit
    assert below["depth_mm"] <= below["a_crit_low_mm"] < below["a_crit_mm"] < above["depth_mm"]
    # the truth: the planted mode's lobes by the package's single-tool solver
    cut = CuttingModel(2, KTC * 1e6, KRC / KTC, 0.0, np.pi)
    a_true, _ = zoa_lobes(tool_from_modes([PLANTED]), cut, np.array([below["spindle_rpm"]]))
    assert below["depth_mm"] < a_true[0] * 1e3 < above["depth_mm"]
    # at the speed and pose where the limit is least certain, with the widest interval
    rel = (ds["a_crit_high_mm"] - ds["a_crit_low_mm"]) / ds["a_crit_mm"]
    here = rel.sel(placement=int(below["placement"]), spindle_rpm=below["spindle_rpm"])
    assert float(here.max()) >= 0.9 * float(rel.where(np.isfinite(ds["a_crit_mm"])).max())
    # the far pose, and every cut on its own material
    assert "farthest" in d.iloc[2]["reason"] and d.iloc[2]["placement"] == 1
    segs = [slot_segment([r.placement_x_mm, r.placement_y_mm, r.placement_z_mm],
                         r.direction_deg, 20.0) for r in d.itertuples()]
    for i in range(len(segs)):
        for j in range(i + 1, len(segs)):
            assert segment_distance_mm(segs[i], segs[j]) >= 6.0 - 1e-9
    assert d.iloc[0]["expected_narrowing"] == pytest.approx(max(0.0,
        1 - (above["depth_mm"] - below["depth_mm"])
        / (below["a_crit_high_mm"] - below["a_crit_low_mm"])), rel=1e-6, abs=1e-12)


def test_learn_cuts_aim_at_the_binding_cuts_stability_interval():
    ds, req, reach = _toy()
    rpm = float(ds["spindle_rpm"].values[14])
    binding = pd.Series({"i_placement": 0, "i_rotation": 0, "i_direction": 0,
                         "spindle_rpm": rpm, "depth_mm": 0.25, "feed_mm_s": 1.0})
    d = learn_design(ds, req, midpoints_mm=reach.midpoints_mm, binding=binding)
    aimed = d[d["learn_target"] == "a_crit_mm at the binding cut"]
    assert 1 <= len(aimed) <= req.n_cuts == 4 and len(d) <= req.n_cuts
    # the members disagree on every chosen cut's verdict
    assert aimed["p_stable"].between(0, 1, inclusive="neither").all()
    # the expected narrowing grows with each cut, and is a share
    gains = aimed["expected_narrowing"].to_numpy(float)
    assert np.all(np.diff(gains) >= -1e-12) and 0 < gains[0] and gains[-1] <= 1
    assert aimed["reason"].str.contains(f"{rpm:.6g} rpm").all()
    segs = [slot_segment([r.placement_x_mm, r.placement_y_mm, r.placement_z_mm],
                         r.direction_deg, 20.0) for r in d.itertuples()]
    for i in range(len(segs)):
        for j in range(i + 1, len(segs)):
            assert segment_distance_mm(segs[i], segs[j]) >= 6.0 - 1e-9


def test_a_binding_cut_outside_the_study_is_itself_a_learn_cut():
    """Placement 1 lies 150 mm from the study's only cut (farther than the request's 100 mm):
    its intervals are widened. With the binding cut there, one learn cut is that cut (its
    speed, depth and feed) on its own material, expected to remove the widening."""
    ds, req, reach = _toy()
    rpm = float(ds["spindle_rpm"].values[14])
    binding = pd.Series({"i_placement": 1, "i_rotation": 0, "i_direction": 0,
                         "spindle_rpm": rpm, "depth_mm": 0.25, "feed_mm_s": 2.0})
    w = float(ds["interval_widening"].isel(placement=1).sel(spindle_rpm=rpm,
                                                             feed_mm_s=2.0).max())
    assert w > 1
    d = learn_design(ds, req, midpoints_mm=reach.midpoints_mm, binding=binding)
    own = d[d["learn_target"] == "force and deflection at the binding cut"]
    assert len(own) == 1 and len(d) <= req.n_cuts
    r = own.iloc[0]
    assert (r["spindle_rpm"], r["depth_mm"], r["feed_mm_s"]) == (rpm, 0.25, 2.0)
    assert r["expected_narrowing"] == pytest.approx(1 - 1 / w, rel=1e-5)
    assert (d["learn_target"] == "a_crit_mm at the binding cut").sum() >= 1
    # inside the study's reach (placement 0) no such cut
    inside = binding.copy()
    inside["i_placement"] = 0
    d0 = learn_design(ds, req, midpoints_mm=reach.midpoints_mm, binding=inside)
    assert not (d0["learn_target"] == "force and deflection at the binding cut").any()


# the expected-information design at the binding cut (robomill.plan.learn.bisect_binding)

def _threshold_patterns(a_mm, depths_mm):
    """Members' predicted verdicts (True stable) of cuts at the binding cut itself."""
    return np.asarray(a_mm)[:, None] > np.asarray(depths_mm)[None]


def test_first_learn_cut_bisects_evenly_spread_members_at_their_median():
    from robomill.plan.learn import candidate_widths
    a = np.arange(1.0, 25.0)                       # 24 members, a_crit 1 ... 24 mm
    w = np.full(a.size, 1 / a.size)
    depths = np.arange(0.5, 25.0, 1.0)             # between every pair of members, and outside
    ew = candidate_widths(a, w, 0.95, _threshold_patterns(a, depths), [], 1e-9)
    assert depths[np.argmin(ew)] == 12.5           # the weighted median of the members
    # by hand: a stable verdict at depth k + 1/2 keeps members k+1 ... 24 (width 23 - k),
    # chatter keeps 1 ... k (width k - 1), with probabilities (24 - k)/24 and k/24
    for k in (6, 12, 17):
        hand = ((24 - k) * (23 - k) + k * (k - 1)) / 24
        assert ew[k] == pytest.approx(hand, rel=1e-6)
    # depths every member agrees on (below all, above all) are never chosen
    assert np.isinf(ew[0]) and np.isinf(ew[-1])


def test_weighted_median_moves_the_bisection():
    from robomill.plan.learn import candidate_widths
    a = np.arange(1.0, 25.0)
    w = np.where(a > 16, 3.0, 1.0)                 # the deep members weigh three times more
    w = w / w.sum()
    depths = np.arange(0.5, 25.0, 1.0)
    ew = candidate_widths(a, w, 0.95, _threshold_patterns(a, depths), [], 1e-9)
    best = depths[np.argmin(ew)]
    assert 12.5 < best < 24.0                      # toward the heavier members


def test_a_cut_all_members_agree_on_is_never_chosen():
    from robomill.plan.learn import candidate_widths, expected_width
    a = np.linspace(2.0, 9.0, 12)
    w = np.full(a.size, 1 / a.size)
    agree = np.ones((a.size, 3), bool)
    agree[:, 1] = False
    ew = candidate_widths(a, w, 0.95, agree, [], 0.05)
    assert np.isinf(ew).all()
    # a verdict cannot narrow what it does not split: no cut, the prior width
    prior, p_y = expected_width(a, w, 0.95, np.zeros((a.size, 0), bool), 0.05)
    assert prior == pytest.approx(7.0) and p_y == pytest.approx([1.0])


def test_second_cut_uses_the_first_verdicts_and_narrows_further():
    from robomill.plan.learn import candidate_widths, expected_width
    a = np.arange(1.0, 25.0)
    w = np.full(a.size, 1 / a.size)
    depths = np.arange(1.5, 24.0, 1.0)
    pats = _threshold_patterns(a, depths)
    first = pats[:, int(np.argmin(candidate_widths(a, w, 0.95, pats, [], 0.05)))]
    one = expected_width(a, w, 0.95, first[:, None], 0.05)[0]
    ew2 = candidate_widths(a, w, 0.95, pats, [first], 0.05)
    assert np.nanmin(ew2) < one < 23.0
    # repeating the first cut adds only a second opinion on the same split
    same = ew2[int(np.flatnonzero((pats == first[:, None]).all(0))[0])]
    assert same > np.nanmin(ew2)
