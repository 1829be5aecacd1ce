"""The virtual cell's robot modes from the generalized eigenproblem of the planted joint
stiffness and the mass matrix at the pose (robomill.synth.jointmodes, robomill.synth.structure).

Truths written here without the library's eigen solver: a two-mass spring chain in closed
form; the cell's mass matrix from the point masses' kinetic energy (tests/point_masses.py)
and the tip's motion from finite differences of the forward kinematics.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest
from point_masses import calibrated_mass_matrix

from robomill.io.synthetic_layout import synthetic_cuts
from robomill.synth.cell import cell_from_config
from robomill.synth.jointmodes import eigenmodes


def test_a_two_mass_chain_has_its_closed_form_modes():
    # ground - k1 - m1 - k2 - m2, the "tool tip" is m2 moving along X
    k1, k2, m1, m2 = 4.0e6, 1.5e6, 30.0, 5.0
    K = np.array([[k1 + k2, -k2], [-k2, k2]])
    M = np.diag([m1, m2])
    b = (k1 + k2) / m1 + k2 / m2
    disc = np.sqrt(b**2 - 4 * k1 * k2 / (m1 * m2))
    w2 = np.array([(b - disc) / 2, (b + disc) / 2])
    Jv = np.array([[0.0, 1.0], [0.0, 0.0], [0.0, 0.0]])
    modes = eigenmodes(K, M, Jv)
    np.testing.assert_allclose(modes.f_hz, np.sqrt(w2) / (2 * np.pi), rtol=1e-12)
    for r in range(2):
        ratio = (k1 + k2 - m1 * w2[r]) / k2         # x2/x1 of mode r
        x2 = ratio / np.sqrt(m1 + m2 * ratio**2)    # unit modal mass
        assert modes.k_tip_N_m[r] == pytest.approx(w2[r] / x2**2, rel=1e-10)
        np.testing.assert_allclose(np.abs(modes.tip_shape[r]), [1.0, 0.0, 0.0], atol=1e-12)
    # in phase below, out of phase above
    assert modes.psi[0, 0] * modes.psi[1, 0] > 0 > modes.psi[0, 1] * modes.psi[1, 1]
    # the tip's static compliance is the two springs in series
    assert np.sum(1.0 / modes.k_tip_N_m) == pytest.approx(1 / k1 + 1 / k2, rel=1e-12)


def test_a_mode_that_moves_the_tip_by_rounding_only_is_no_tip_mode():
    # two uncoupled joints; the second spins about an axis through the tool tip, so its column
    # of J_v is rounding noise (1e-17 m/rad), the first moves the tip 0.8 m/rad along Y
    K = np.diag([2.0e6, 5.0e4])
    M = np.diag([40.0, 0.3])
    Jv = np.array([[0.0, 1e-17], [0.8, 0.0], [0.0, -2e-17]])
    modes = eigenmodes(K, M, Jv)
    spin = int(np.argmin(np.abs(modes.psi[0])))            # the mode that is joint 2 alone
    arm = 1 - spin
    assert np.isinf(modes.k_tip_N_m[spin]) and np.all(np.isnan(modes.tip_shape[spin]))
    # the other mode: k = omega^2 / |J_v psi|^2 with psi = 1/sqrt(m1)
    assert modes.k_tip_N_m[arm] == pytest.approx(2.0e6 / 0.8**2, rel=1e-12)
    np.testing.assert_allclose(np.abs(modes.tip_shape[arm]), [0.0, 1.0, 0.0], atol=1e-12)


def _with_law(config, law):
    config = copy.deepcopy(config)
    config["synth"]["process"]["robot_modes"] = law
    return config


@pytest.fixture(scope="module")
def default_cell(config):
    """The default cell under the eigen law (``synth.process.robot_modes: eigen``; the default
    study itself keeps the planted law)."""
    config = _with_law(config, "eigen")
    return config, cell_from_config(config)


def _mass_matrix(cell, config, q):
    """M̃(q) from the calibrated bodies' kinetic energy (tests/point_masses.py)."""
    return calibrated_mass_matrix(cell, config["cell"]["mass_model"], q)


def _tip_jacobian(cell, q, eps=1e-7):
    cols = [(cell.robot.fk(q + eps * e)[:3, 3] - cell.robot.fk(q - eps * e)[:3, 3]) / (2 * eps)
            for e in np.eye(cell.robot.n_joints)]
    return np.array(cols).T * 1e-3


def _independent_modes(cell, config, q):
    """Frequencies [Hz] and tip directions of K_θ ψ = ω² M̃(q) ψ by numpy's symmetric
    eigensolver on M̃^-½ K M̃^-½ (M̃ from the calibrated bodies' kinetic energy)."""
    Mt = _mass_matrix(cell, config, q)
    lam, V = np.linalg.eigh(Mt)
    Mih = V @ np.diag(lam**-0.5) @ V.T
    w2, X = np.linalg.eigh(Mih @ np.diag(cell.joint_stiffness_Nm_rad) @ Mih)
    tip = _tip_jacobian(cell, q) @ (Mih @ X)
    return np.sqrt(w2) / (2 * np.pi), tip / np.linalg.norm(tip, axis=0), tip


def test_at_the_impact_pose_the_robot_modes_are_the_planted_ones_with_eigen_shapes(default_cell):
    from robomill.synth.structure import robot_modes_at

    config, cell = default_cell
    q = cell.q_reference_rad
    f, u, _ = _independent_modes(cell, config, q)
    # the calibration: the planted frequencies are the eigenproblem's lowest at q_ref (to the
    # fit's stated tolerance, 0.1 %, robomill.synth.shapecal)
    np.testing.assert_allclose(f, [m.f_hz for m in cell.modes], rtol=1e-3)
    for r, (planted, m) in enumerate(zip(cell.modes, robot_modes_at(cell, q), strict=True)):
        assert (m.f_hz, m.zeta, m.k_N_m) == pytest.approx(
            (planted.f_hz, planted.zeta, planted.k_N_m), rel=1e-9)
        assert abs(float(np.dot(m.shape, u[:, r]))) == pytest.approx(1.0, abs=1e-6)


def test_at_a_study_pose_the_modes_turn_and_move_with_the_eigenproblem(default_cell):
    from robomill.synth.structure import modes_at, robot_modes_at

    config, cell = default_cell
    cuts = {c.id: c for c in synthetic_cuts(config)}
    ref = robot_modes_at(cell, cell.q_reference_rad)
    f_ref, _, tip_ref = _independent_modes(cell, config, cell.q_reference_rad)
    shapes = {}
    for cut in ("s1_g1_py", "s3_g5_my"):
        q = cell.joint_path_rad(cuts[cut], np.array([50.0]))[0]
        f, u, tip = _independent_modes(cell, config, q)
        moved = robot_modes_at(cell, q)
        shapes[cut] = np.array([m.shape for m in moved])
        # each planted mode continues one eigenmode here (the 67-72 Hz modes may cross, so
        # the tracked one is found by its shape: the same direction, one mode each)
        which = [int(np.argmax(np.abs(u.T @ np.asarray(m.shape)))) for m in moved]
        assert sorted(which) == list(range(len(moved)))
        for r, (planted, m, j) in enumerate(zip(cell.modes, moved, which, strict=True)):
            # the planted frequency moved by the eigenproblem's ratio (exactly f[j] where the
            # calibration is exact; it is to 0.1 %)
            assert m.f_hz == pytest.approx(planted.f_hz * f[j] / f_ref[r], rel=1e-6)
            assert abs(float(np.dot(m.shape, u[:, j]))) == pytest.approx(1.0, abs=1e-6)
            k_ratio = (np.linalg.norm(tip_ref[:, r]) / np.linalg.norm(tip[:, j]))**2 \
                * (f[j] / f_ref[r])**2
            assert m.k_N_m == pytest.approx(planted.k_N_m * k_ratio, rel=1e-5)
            assert m.zeta == planted.zeta
        assert modes_at(cell, q)[len(moved):] == list(cell.spindle_modes)
        assert max(abs(m.f_hz / p.f_hz - 1) for m, p in zip(moved, ref, strict=True)) > 0.03
    # the shapes turn with the pose (a direction change, not a rescaled fixed shape)
    cos = np.abs(np.sum(shapes["s1_g1_py"] * shapes["s3_g5_my"], axis=1))
    assert np.degrees(np.arccos(np.clip(cos, -1, 1))).max() > 10.0


def test_without_joint_stiffness_the_planted_modes_hold(default_cell):
    from robomill.synth.structure import robot_modes_at

    config, _ = default_cell
    config = copy.deepcopy(config)
    config["synth"]["loadtests"]["robots"] = []
    cell = cell_from_config(config)
    q = cell.joint_path_rad(synthetic_cuts(config)[0], np.array([5.0]))[0]
    assert cell.robot_structure is None and robot_modes_at(cell, q) == list(cell.modes)


def test_the_config_key_selects_the_law(config):
    """``synth.process.robot_modes``: under ``planted`` a mode's tip shape is the planted one
    at every pose (only its stiffness and mass move); under ``eigen`` it turns between poses."""
    from robomill.synth.structure import robot_modes_at

    assert config["synth"]["process"]["robot_modes"] == "planted"
    cuts = {c.id: c for c in synthetic_cuts(config)}
    turned = {}
    for law in ("planted", "eigen"):
        cfg = _with_law(config, law)
        cell = cell_from_config(cfg)
        assert cell.robot_modes_law == law
        poses = [cell.joint_path_rad(cuts[c], np.array([50.0]))[0]
                 for c in ("s1_g1_py", "s3_g5_my")]
        a, b = (np.array([m.shape for m in robot_modes_at(cell, q)]) for q in poses)
        cos = np.clip(np.abs(np.sum(a * b, axis=1)), 0.0, 1.0)
        turned[law] = np.degrees(np.arccos(cos)).max()
        if law == "planted":
            # fixed shapes, the planted ones; stiffness (and frequency) rescaled by the pose
            planted = np.array([m.shape for m in cell.modes])
            np.testing.assert_array_equal(a, planted)
            np.testing.assert_array_equal(b, planted)
            ka, kb = ([m.k_N_m for m in robot_modes_at(cell, q)] for q in poses)
            assert max(abs(x / y - 1) for x, y in zip(ka, kb, strict=True)) > 0.01
    assert turned["planted"] < 1e-5 and turned["eigen"] > 10.0, turned


def test_point_masses_that_give_the_joints_no_inertia_still_give_finite_eigen_modes(
        default_cell):
    # point masses on joint 1's own axis have no inertia about any joint's motion: the
    # calibrated rotor inertias alone carry the modes, at the planted frequencies at q_ref
    from robomill.synth.inertia import mass_matrix_kg_m2, rigid_body_model
    from robomill.synth.structure import robot_modes_at

    config, cell = default_cell
    cell = copy.copy(cell)
    base = np.asarray(cell.robot.base, float)
    on_axis_mm = base[:3, 3] + np.outer([100.0, 300.0], base[:3, 2])
    cell.rigid_body_model = rigid_body_model(cell.robot, np.array([1, 1]),
                                             np.array([20.0, 5.0]), on_axis_mm)
    q = cell.joint_path_rad(synthetic_cuts(config)[0], np.array([5.0]))[0]
    assert np.abs(mass_matrix_kg_m2(cell.rigid_body_model, q)).max() < 1e-12
    at_ref = robot_modes_at(cell, cell.q_reference_rad)
    np.testing.assert_allclose([m.f_hz for m in at_ref], [m.f_hz for m in cell.modes],
                               rtol=1e-9)
    # rotor inertias alone: each mode is one joint; a joint whose spin moves no tool tip (the
    # wrist about an axis through the TCP) has no tip compliance (k infinite), never a stiffness
    # made of rounding values; every other mode is finite
    modes = robot_modes_at(cell, q)
    assert all(np.isfinite(m.f_hz) and m.k_N_m > 0 for m in modes)
    assert sum(np.isfinite(m.k_N_m) for m in modes) >= len(modes) - 1
