"""Kinematics with exact truth: Jacobian vs finite differences, eq. 1.4 vs D-H, IK round trip."""

import numpy as np
import pytest

from robomill.kinematics import (
    SerialRobot,
    geometric_model,
    robot_from_mapping,
    rodrigues,
    vector_model_from_robot,
)


@pytest.fixture
def irb(config):
    return robot_from_mapping(config["cell"]["robot"])


@pytest.fixture
def mdh_robot():
    return SerialRobot("mdh6", "mdh", a_mm=[0, 350, 1150, 40, 0, 0],
                       alpha_rad=np.deg2rad([0, -90, 0, -90, 90, -90]),
                       d_mm=[675, 0, 0, 1000, 0, 0], theta_offset_rad=np.zeros(6),
                       tool_mm=[50, 0, 250])


def test_rodrigues_is_a_rotation_about_its_axis():
    e = np.array([1.0, 2.0, 2.0]) / 3.0
    R = rodrigues(e, 0.7)
    assert np.allclose(R @ R.T, np.eye(3), atol=1e-14)
    assert np.linalg.det(R) == pytest.approx(1.0)
    assert np.allclose(R @ e, e)


@pytest.mark.parametrize("which", ["irb", "mdh_robot"])
def test_jacobian_matches_finite_differences(which, request):
    robot = request.getfixturevalue(which)
    rng = np.random.default_rng(1)
    for _ in range(5):
        q = rng.uniform(-1, 1, 6)
        J = robot.jacobian(q)
        eps = 1e-6
        Jn = np.empty((3, 6))
        for i in range(6):
            dq = np.zeros(6)
            dq[i] = eps
            Jn[:, i] = (robot.fk(q + dq)[:3, 3] - robot.fk(q - dq)[:3, 3]) / (2 * eps)
        assert np.allclose(J[:3], Jn, atol=1e-5)


def test_vector_model_eq_1_4_equals_dh_forward_model(irb):
    a0, avec, axes = vector_model_from_robot(irb)
    q = np.random.default_rng(2).uniform(-2, 2, (50, 6))
    p_dh = irb.fk(q)[:, :3, 3]
    assert np.abs(geometric_model(q, a0, avec, axes) - p_dh).max() < 1e-9


def test_ik_returns_the_pose(irb):
    q_true = np.deg2rad([10, 30, 20, 5, 40, -15])
    T = irb.fk(q_true)
    q = irb.ik(T, q_true + 0.05)
    assert np.allclose(irb.fk(q), T, atol=1e-9)


def test_unknown_convention_is_refused():
    with pytest.raises(ValueError, match="convention"):
        SerialRobot("x", "xyz", [0], [0], [0], [0])
