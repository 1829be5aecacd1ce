"""Joint-stiffness model with exact truth: planted K_θ recovered, intervals, observability,
Jacobians vs finite differences (dh and mdh), directional stiffness vs K = J⁻ᵀ K_θ J⁻¹."""

import warnings

import numpy as np
import pytest

from robomill.kinematics import SerialRobot, ik_batch, robot_from_mapping
from robomill.stiffness import (
    cartesian_stiffness,
    design_matrix,
    directional_stiffness_N_m,
    identify_from_tests,
    identify_joint_stiffness,
    jacobian_m,
    predict_deflection_m,
    translational_compliance_m_N,
)

K_TRUE = np.array([6.89e6, 4.53e6, 3.40e6, 2.13e6, 1.27e6, 6.32e5])


@pytest.fixture
def kr360():
    return SerialRobot("kr360", "mdh", a_mm=[0, 500, 1300, 55, 0, 0],
                       alpha_rad=np.deg2rad([0, -90, 0, -90, 90, -90]),
                       d_mm=[1045, 0, 0, 1025, 0, 0],
                       theta_offset_rad=np.deg2rad([0, 0, -90, 0, 0, 0]),
                       tool_mm=[150, 0, 690])


@pytest.fixture
def irb(config):
    return robot_from_mapping(config["cell"]["robot"])


def _tests(robot, n, rng, directions=None):
    q = rng.uniform(-1.2, 1.2, size=(n, 6))
    if directions is None:
        F = rng.normal(size=(n, 3))
        F *= 600.0 / np.linalg.norm(F, axis=1, keepdims=True)
    else:
        F = np.asarray(directions, float)[np.arange(n) % len(directions)] * 600.0
    return q, F


@pytest.mark.parametrize("which", ["kr360", "irb"])
def test_jacobian_m_matches_finite_differences(which, request):
    robot = request.getfixturevalue(which)
    q = np.random.default_rng(3).uniform(-1, 1, 6)
    J = jacobian_m(robot, q)
    h = 1e-6
    for j in range(6):
        dq = np.zeros(6)
        dq[j] = h
        dp = (robot.fk(q + dq)[:3, 3] - robot.fk(q - dq)[:3, 3]) / (2 * h) * 1e-3
        assert np.allclose(J[:3, j], dp, rtol=1e-6, atol=1e-9)


def test_design_matrix_reproduces_the_compliance_model(kr360):
    rng = np.random.default_rng(0)
    q, F = _tests(kr360, 5, rng)
    J = jacobian_m(kr360, q)
    c = 1.0 / K_TRUE
    X = np.einsum("mij,j,mkj,mk->mi", J[:, :3], c, J[:, :3], F)
    assert np.allclose(design_matrix(J, F) @ c, X.ravel(), rtol=1e-12)
    assert np.allclose(predict_deflection_m(J, F, c), X, rtol=1e-12)


def test_identification_recovers_planted_stiffness_exactly_without_noise(kr360):
    rng = np.random.default_rng(1)
    q, F = _tests(kr360, 30, rng)
    J = jacobian_m(kr360, q)
    X = predict_deflection_m(J, F, 1.0 / K_TRUE)
    r = identify_joint_stiffness(J, F, X)
    assert r.observable.all()
    assert np.allclose(r.k_Nm_rad, K_TRUE, rtol=1e-8)
    assert np.allclose(r.ci95_low_Nm_rad, K_TRUE, rtol=1e-5)
    assert np.allclose(r.ci95_high_Nm_rad, K_TRUE, rtol=1e-5)
    assert 1 <= r.condition_number < 1e3


def test_intervals_cover_the_planted_stiffness_with_noise(kr360):
    rng = np.random.default_rng(2)
    q, F = _tests(kr360, 30, rng)
    J = jacobian_m(kr360, q)
    X0 = predict_deflection_m(J, F, 1.0 / K_TRUE)
    inside = []
    for _ in range(200):
        r = identify_joint_stiffness(J, F, X0 + rng.normal(0, 5e-6, X0.shape))
        inside.append((r.ci95_low_Nm_rad <= K_TRUE) & (K_TRUE <= r.ci95_high_Nm_rad))
    coverage = np.mean(inside, axis=0)
    assert np.all(coverage > 0.88) and np.all(coverage < 0.995), coverage
    r = identify_joint_stiffness(J, F, X0 + np.random.default_rng(7).normal(0, 5e-6, X0.shape))
    assert np.all(np.abs(r.k_Nm_rad / K_TRUE - 1) < 0.3)


def test_vertical_loads_leave_joint_1_unobservable(kr360):
    """A hanging load gives no torque about the vertical joint 1: reported, not invented."""
    rng = np.random.default_rng(4)
    q, F = _tests(kr360, 20, rng, directions=[[0, 0, -1]])
    J = jacobian_m(kr360, q)
    X = predict_deflection_m(J, F, 1.0 / K_TRUE)
    with pytest.warns(UserWarning, match="joint 1"):
        r = identify_joint_stiffness(J, F, X)
    assert not r.observable[0] and r.observable[1:].all()
    assert np.isnan(r.k_Nm_rad[0]) and r.compliance[0] == 0.0
    assert np.allclose(r.k_Nm_rad[1:], K_TRUE[1:], rtol=1e-8)
    assert np.isfinite(r.condition_number)


def test_tool_on_flange_axis_leaves_joint_6_unobservable(irb):
    rng = np.random.default_rng(5)
    q, F = _tests(irb, 20, rng)
    J = jacobian_m(irb, q)
    X = predict_deflection_m(J, F, 1.0 / K_TRUE)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        r = identify_joint_stiffness(J, F, X)
    assert [bool(o) for o in r.observable] == [True] * 5 + [False]
    assert any("joint 6" in str(m.message) for m in w)


def test_directional_stiffness_is_consistent_with_cartesian_stiffness(kr360):
    q = np.deg2rad([10, -60, 80, 20, 70, 30])
    J = jacobian_m(kr360, q)
    K = cartesian_stiffness(J, K_TRUE)
    C = translational_compliance_m_N(J, 1.0 / K_TRUE)
    assert np.allclose(np.linalg.inv(K)[:3, :3], C, rtol=1e-9)
    R = kr360.fk(q)[:3, :3]
    k = directional_stiffness_N_m(C, R)
    for i in range(3):
        u = R[:, i]
        assert k[i] == pytest.approx(1.0 / (u @ C @ u), rel=1e-12)
    assert np.all(k > 0)


def test_ik_batch_round_trip(kr360):
    rng = np.random.default_rng(6)
    q = rng.uniform(-0.6, 0.6, size=(8, 6)) + np.deg2rad([0, -60, 80, 0, 70, 0])
    T = kr360.fk(q)
    q2, ok = ik_batch(kr360, T, q + 0.05)
    assert ok.all()
    assert np.allclose(kr360.fk(q2), T, atol=1e-6)


def test_identify_from_tests_tables(kr360):
    import pandas as pd

    rng = np.random.default_rng(8)
    q, F = _tests(kr360, 24, rng)
    X = predict_deflection_m(jacobian_m(kr360, q), F, 1.0 / K_TRUE) * 1e3
    df = pd.DataFrame({"pose": [f"{'cube' if i < 10 else 'plane'}_{i}" for i in range(20)]
                       + [f"val_{i}" for i in range(4)],
                       "role": ["identify"] * 20 + ["validate"] * 4})
    for j in range(6):
        df[f"q{j + 1}_deg"] = np.rad2deg(q[:, j])
    df[["Fx_N", "Fy_N", "Fz_N"]] = F
    df[["dx_mm", "dy_mm", "dz_mm"]] = X
    out = identify_from_tests(kr360, df)
    assert list(out["joint_stiffness"].columns) == ["joint", "k_Nm_rad", "ci95_low_Nm_rad",
                                                    "ci95_high_Nm_rad", "observable"]
    assert set(out["models"]["model"]) == {"all", "cube", "plane"}
    assert np.abs(out["validation"]["error_pct"]).max() < 1e-6
