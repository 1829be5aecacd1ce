"""The tool tip's static compliance the plan predicts deflection with (robomill.plan.tooltip),
against truths written by hand: the modal sum of two orthogonal modes, and one robot mode
along base Y whose stiffness follows the joint model's, k_y(q)/k_y(q_ref) computed from the
Jacobian column by column."""

import numpy as np
import pandas as pd
import pytest
import yaml

from robomill.kinematics import robot_from_mapping
from robomill.plan.measured import Measured
from robomill.plan.predict import Cell
from robomill.plan.tooltip import nominal_key, static_compliance_m_N
from robomill.stiffness import solve_poses


@pytest.fixture(scope="module")
def cell():
    spec = yaml.safe_load(open("config.yaml"))["cell"]
    rb = robot_from_mapping(spec["robot"])
    return Cell(rb, np.asarray(spec["tool_rotation"], float), np.deg2rad(spec["q_home_deg"]),
                np.array([650.0, 0.0, 200.0]))


def _modes(rows):
    cols = ("f_n_hz", "zeta", "k_modal_N_m", "shape_x", "shape_y", "shape_z")
    return pd.DataFrame([dict(zip(cols, r, strict=True)) for r in rows])


K_JOINT = np.array([1e6, 8e5, 4e5, 6e4, 5e4, 3e4])
JOINTS = pd.DataFrame({"joint": np.arange(1, 7), "k_Nm_rad": K_JOINT,
                       "ci95_low_Nm_rad": 0.8 * K_JOINT, "ci95_high_Nm_rad": 1.25 * K_JOINT,
                       "observable": True})


def test_the_modal_sum_without_load_tests(cell):
    """Modes along X (k = 1e6) and Y (2e6) and no load tests: C = diag(1e-6, 5e-7, 0) at every
    pose; a spindle mode along Z above the robot's band adds 1/k along Z."""
    modes = _modes([(20.0, 0.04, 1e6, 1, 0, 0), (35.0, 0.03, 2e6, 0, 1, 0),
                    (2500.0, 0.03, 5e7, 0, 0, 1)])
    q, ok = solve_poses(cell.robot, np.array([[650.0, 0, 200], [900.0, 100, 150]]), cell.R0,
                        cell.q_seed_rad)
    assert ok.all()
    C = static_compliance_m_N(Measured(modes=modes), cell, q, 100.0, corners=False)
    assert list(C) == ["nominal/nominal"]
    assert np.allclose(C["nominal/nominal"], np.diag([1e-6, 5e-7, 2e-8]), rtol=1e-12,
                       atol=0)


def test_a_robot_mode_follows_the_joints_and_its_ends_bound_the_compliance(cell):
    modes = _modes([(40.0, 0.04, 1e6, 0, 1, 0)])
    modes["k_modal_N_m_low"], modes["k_modal_N_m_high"] = 0.9e6, 1.2e6
    pts = np.array([[650.0, 0.0, 200.0], [450.0, 0.0, 300.0], [950.0, 0.0, 150.0]])
    q, ok = solve_poses(cell.robot, pts, cell.R0, cell.q_seed_rad)
    assert ok.all()

    def ky(qq, k_joint):
        J = np.asarray(cell.robot.jacobian(qq))[:3] * 1e-3
        return 1.0 / sum(J[1, j] ** 2 / k_joint[j] for j in range(6))

    C = static_compliance_m_N(Measured(modes=modes, joints=JOINTS), cell, q[1:], 100.0)
    yy = np.array([ky(qq, K_JOINT) / ky(q[0], K_JOINT) for qq in q[1:]])
    assert abs(yy[0] - yy[1]) > 0.5                                     # the poses differ
    assert np.allclose(C[nominal_key(C)][:, 1, 1], 1.0 / (1e6 * yy), rtol=1e-9)
    assert np.allclose(C[nominal_key(C)][:, 0, 0], 0.0)
    ends = np.stack([c[:, 1, 1] for c in C.values()])
    # the softest end: the modes' low stiffness (the joints' ends move the ratio only)
    assert np.allclose(ends.max(0), C["low/nominal"][:, 1, 1], rtol=0.05)
    assert np.allclose(C["low/nominal"][:, 1, 1] / C["high/nominal"][:, 1, 1], 1.2 / 0.9,
                       rtol=1e-9)


def test_the_joint_model_without_an_impact_test(cell):
    q, ok = solve_poses(cell.robot, np.array([[700.0, 50.0, 200.0]]), cell.R0, cell.q_seed_rad)
    C = static_compliance_m_N(Measured(joints=JOINTS), cell, q, 100.0, corners=False)
    J = np.asarray(cell.robot.jacobian(q[0]))[:3] * 1e-3
    assert nominal_key(C) == "joints/nominal"
    assert np.allclose(C["joints/nominal"][0], J @ np.diag(1 / K_JOINT) @ J.T, rtol=1e-9)
    assert static_compliance_m_N(Measured(), cell, q, 100.0) is None
