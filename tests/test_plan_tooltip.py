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


def test_the_modal_mass_moves_as_the_planar_arm_says_by_hand():
    """A two-link planar arm (links 0.5 and 0.3 m, point masses 4 and 2.5 kg at their ends,
    joint compliances 1e-6 and 3e-6 rad/(N·m)): the mass ratio of a mode along φ between two
    poses, with the textbook Jacobian and mass matrix written out here, not the library's:
    ψ = C_θ Jᵀ φ / (φᵀ J C_θ Jᵀ φ), μ = ψᵀ M ψ."""
    from robomill.inertia import rigid_body_model
    from robomill.kinematics import SerialRobot
    from robomill.plan.tooltip import mass_ratios

    l1, l2, m1, m2 = 0.5, 0.3, 4.0, 2.5
    c = np.array([1e-6, 3e-6])
    robot = SerialRobot("planar", "dh", np.array([l1, l2]) * 1e3, np.zeros(2), np.zeros(2),
                        np.zeros(2))
    rigid = rigid_body_model(robot, np.array([1, 2]), np.array([m1, m2]),
                             np.array([[l1 * 1e3, 0, 0], [(l1 + l2) * 1e3, 0, 0]]))
    shapes = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [np.cos(0.6), np.sin(0.6), 0.0]])

    def mu(q1, q2):
        s1, c1, s12, c12 = np.sin(q1), np.cos(q1), np.sin(q1 + q2), np.cos(q1 + q2)
        J = np.array([[-l1 * s1 - l2 * s12, -l2 * s12], [l1 * c1 + l2 * c12, l2 * c12]])
        M = np.array([[m1 * l1**2 + m2 * (l1**2 + l2**2 + 2 * l1 * l2 * np.cos(q2)),
                       m2 * (l2**2 + l1 * l2 * np.cos(q2))],
                      [m2 * (l2**2 + l1 * l2 * np.cos(q2)), m2 * l2**2]])
        out = []
        for phi in shapes[:, :2]:
            psi = c * (J.T @ phi) / (phi @ J @ np.diag(c) @ J.T @ phi)
            out.append(psi @ M @ psi)
        return np.array(out)

    q_ref = np.array([0.3, 1.1])
    q = np.array([[0.3, 1.1], [0.9, 0.6], [-0.4, 1.9]])
    got = mass_ratios(robot, rigid, c, q, q_ref, shapes)
    expected = np.array([mu(*qb) / mu(*q_ref) for qb in q])
    np.testing.assert_allclose(got, expected, rtol=1e-10)
    np.testing.assert_allclose(got[0], 1.0, rtol=1e-12)        # the impact test's own pose
    assert np.ptp(got[1:]) > 0.1                                 # the poses do move the mass


def test_without_documented_masses_the_modal_mass_is_held(cell):
    """No mass model in the cell file: the scalings carry no mass ratio (the frequency
    follows the stiffness alone, f ∝ √k); with one, a ratio per pose and robot mode, 1 for a
    mode above the robot's band."""
    import dataclasses

    from robomill.inertia import rigid_body_model
    from robomill.plan.tooltip import mode_scalings

    m = Measured(modes=None, coefficients=None, joints=JOINTS, level=0.95)
    shapes = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
    q_ref, _ = solve_poses(cell.robot, cell.reference_point_mm[None], cell.R0, cell.q_seed_rad)
    q = np.stack([q_ref[0], q_ref[0] + np.deg2rad([10.0, 5.0, -8.0, 0.0, 4.0, 0.0])])
    robot_mode = np.array([True, False])
    assert "mass" not in mode_scalings(m, cell, q, robot_mode, shapes)
    rigid = rigid_body_model(cell.robot, np.array([2, 3, 6]), np.array([35.0, 30.0, 5.0]),
                             np.array([[170.0, 0.0, 840.0], [250.0, 0.0, 1200.0],
                                       [880.0, 10.0, 1186.5]]))
    sc = mode_scalings(m, dataclasses.replace(cell, rigid_body=rigid), q, robot_mode, shapes)
    assert sc["mass"].shape == (2, 2)
    np.testing.assert_allclose(sc["mass"][0], 1.0, rtol=1e-9)
    assert abs(sc["mass"][1, 0] - 1.0) > 0.01 and sc["mass"][1, 1] == 1.0
