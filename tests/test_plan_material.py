"""Each production cut on its own stretch of material (robomill.plan.material and the
choice): slot overlap against a brute-force distance, and a plan whose best candidates all
sit on one placement."""

import itertools

import numpy as np
import pandas as pd
import pytest
import yaml

from robomill.kinematics import robot_from_mapping
from robomill.plan.choose import choose
from robomill.plan.material import overlaps, segment_distance_mm, slot_segment
from robomill.plan.measured import Measured
from robomill.plan.predict import Cell, predict_grid
from robomill.plan.request import parse_request


def brute_distance(a, b, n=801):
    s = np.linspace(0, 1, n)
    pa = a[0] + s[:, None] * (a[1] - a[0])
    pb = b[0] + s[:, None] * (b[1] - b[0])
    return np.sqrt(((pa[:, None] - pb[None]) ** 2).sum(-1)).min()


def test_segment_distance_against_sampling():
    rng = np.random.default_rng(4)
    cases = [rng.normal(0, 20, (2, 2, 3)) for _ in range(30)]
    cases.append(np.array([[[0, 0, 0], [10, 0, 0]], [[3, 2, 0], [8, 2, 0]]], float))  # parallel
    cases.append(np.array([[[0, 0, 0], [10, 0, 0]], [[12, 0, 0], [20, 0, 0]]], float))  # in line
    for a, b in cases:
        assert segment_distance_mm(a, b) == pytest.approx(brute_distance(a, b), abs=0.05)
    s = slot_segment([0, 0, 0], 90.0, 20.0)
    assert np.allclose(s, [[0, -10, 0], [0, 10, 0]], atol=1e-12)
    assert overlaps(s, [slot_segment([5.9, 0, 0], 90.0, 20.0)], 6.0)
    assert not overlaps(s, [slot_segment([6.0, 0, 0], 90.0, 20.0)], 6.0)
    assert overlaps(s, [slot_segment([0, 15, 0], 0.0, 20.0)], 6.0)     # a T: 5 mm apart


def test_no_two_production_cuts_overlap_nor_a_study_slot():
    cfg = yaml.safe_load(open("config.yaml"))["cell"]
    cell = Cell(robot_from_mapping(cfg["robot"]), np.asarray(cfg["tool_rotation"], float),
                np.deg2rad(cfg["q_home_deg"]), np.array([650.0, 0.0, 200.0]))
    pts = [[650, 0, 200], [650, 3, 200], [652, -2, 200], [650, 40, 200], [700, 0, 200],
           [700, 60, 200]]
    req = parse_request({"kind": "plan", "operation": {"length_mm": 20, "directions": ["py"]},
                         "tool": {"diameter_mm": 6, "flutes": 2},
                         "placement": {"points_mm": pts}, "spindle_rpm": [20000],
                         "depth_mm": [0.1, 0.2, 0.3, 0.4, 0.5], "feed_mm_s": [1, 2],
                         "n_cuts": 5})
    coeffs = pd.DataFrame({"name": ["Ktc", "Krc", "Kac", "Kte", "Kre", "Kae"],
                           "value": [800.0, 240.0, 200.0, 25.0, 30.0, 6.0]})
    k = np.array([1e6, 8e5, 4e5, 6e4, 5e4, 3e4])
    joints = pd.DataFrame({"joint": np.arange(1, 7), "k_Nm_rad": k, "ci95_low_Nm_rad": k,
                           "ci95_high_Nm_rad": k, "observable": True})
    ds = predict_grid(req, Measured(coefficients=coeffs, joints=joints), cell)
    study = [slot_segment([700, 0, 199.5], 90.0, 40.0)]                # occupies [700, 0]
    chosen, front = choose(ds, req, occupied=study)
    assert len(chosen) >= 3
    segs = [slot_segment([r.placement_x_mm, r.placement_y_mm, r.placement_z_mm],
                         r.direction_deg, 20.0) for r in chosen.itertuples()]
    for a, b in itertools.combinations(segs, 2):
        assert brute_distance(a, b) >= 6.0 - 1e-6
    for a in segs:
        assert brute_distance(a, study[0]) >= 6.0 - 1e-6
    # without the material rule the menu's best candidates share one placement
    assert front["placement"].head(5).nunique() < len(chosen)
    assert list(chosen["mrr_mm3_s"]) == sorted(chosen["mrr_mm3_s"], reverse=True)


def test_one_line_when_every_slot_is_taken():
    from robomill.plan.choose import PlanInfeasible

    cfg = yaml.safe_load(open("config.yaml"))["cell"]
    cell = Cell(robot_from_mapping(cfg["robot"]), np.asarray(cfg["tool_rotation"], float),
                np.deg2rad(cfg["q_home_deg"]), np.array([650.0, 0.0, 200.0]))
    req = parse_request({"kind": "plan", "operation": {"length_mm": 20, "directions": ["py"]},
                         "tool": {"diameter_mm": 6, "flutes": 2},
                         "placement": {"points_mm": [[650, 0, 200]]}, "spindle_rpm": [20000],
                         "depth_mm": [0.1], "feed_mm_s": [1]})
    coeffs = pd.DataFrame({"name": ["Ktc", "Krc", "Kac", "Kte", "Kre", "Kae"],
                           "value": [800.0, 240.0, 200.0, 25.0, 30.0, 6.0]})
    ds = predict_grid(req, Measured(coefficients=coeffs), cell)
    with pytest.raises(PlanInfeasible) as e:
        choose(ds, req, occupied=[slot_segment([652, 0, 199.5], 90.0, 40.0)])
    assert "\n" not in str(e.value) and "overlaps a cut of the study" in str(e.value)
