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


def test_learn_pair_straddles_the_planted_stability_limit():
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
    ds = apply_extrapolation(predict_grid(req, m, cell), req, m, cell, reach)
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
