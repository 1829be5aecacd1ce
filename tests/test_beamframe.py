"""Beam-frame model with closed forms: cantilever tip deflection, 42×42 SPD, torsion."""

import numpy as np
import pytest

from robomill.beamframe import (
    Section,
    cantilever_check,
    element_stiffness_local,
    global_stiffness,
    link_polyline_mm,
    tool_displacement,
    vibration_sigma,
    wheel_forces_N,
    wheel_normal_force_N,
)
from robomill.kinematics import robot_from_mapping

SEC = Section.tube(200.0, 10.0, 2.1e11, 8.1e10)


@pytest.mark.parametrize("n_el", [1, 3, 7])
def test_cantilever_tip_deflection_equals_closed_form(n_el):
    tip, closed = cantilever_check(SEC, length_m=1.3, n_elements=n_el, force_N=800.0)
    assert tip == pytest.approx(closed, rel=1e-10)


def test_inclined_cantilever_bending_torsion_and_axial():
    """A cantilever along an arbitrary direction: axial FL/EA, transverse FL³/3EI, and a
    tip moment about the axis twists by TL/GJ."""
    L = 0.9
    e = np.array([1.0, 2.0, 2.0]) / 3.0
    nodes = np.outer(np.linspace(0, L, 4), e)
    K = global_stiffness(nodes, [SEC])
    d_ax = tool_displacement(K, 500.0 * e)
    assert d_ax[:3] @ e == pytest.approx(500.0 * L / (SEC.E_Pa * SEC.A_m2), rel=1e-9)
    n = np.cross(e, [0, 0, 1.0])
    n /= np.linalg.norm(n)
    d_tr = tool_displacement(K, 500.0 * n)
    assert d_tr[:3] @ n == pytest.approx(500.0 * L**3 / (3 * SEC.E_Pa * SEC.I_m4), rel=1e-9)
    F = np.zeros(K.shape[0])
    F[-3:] = 200.0 * e
    twist = np.linalg.solve(K, F)[-3:] @ e
    assert twist == pytest.approx(200.0 * L / (SEC.G_Pa * SEC.J_m4), rel=1e-9)


def test_hp20_frame_is_42_by_42_symmetric_positive_definite(config):
    bf = config["stiffness"]["beamframe"]
    robot = robot_from_mapping(bf["robot"])
    nodes = link_polyline_mm(robot, np.deg2rad([10, 20, -10, 30, 60, 0])) * 1e-3
    assert nodes.shape == (8, 3)
    K = global_stiffness(nodes, [SEC])
    assert K.shape == (42, 42)
    assert np.allclose(K, K.T, rtol=0, atol=1e-9 * np.abs(K).max())
    assert np.linalg.eigvalsh(K).min() > 0
    free = global_stiffness(nodes, [SEC], fix_first=False)
    assert free.shape == (48, 48)
    assert np.sum(np.abs(np.linalg.eigvalsh(free)) < 1e-6 * np.abs(free).max()) == 6


def test_element_matrix_has_six_rigid_body_modes():
    k = element_stiffness_local(SEC, 0.7)
    assert np.allclose(k, k.T)
    ev = np.linalg.eigvalsh(k)
    assert np.sum(np.abs(ev) < 1e-6 * ev.max()) == 6


def test_wheel_forces_and_sigma():
    Fn = wheel_normal_force_N(1.0, 1.0e5, 40.0)
    assert Fn == pytest.approx(1.0e5 * np.pi * (2 * 0.04 * 0.001 - 1e-6))
    P = np.array([np.sin(0.3), 0.0, -np.cos(0.3)])
    F = wheel_forces_N(Fn, 0.3, [0, 0, 1.0], P)
    assert F[2] == pytest.approx(Fn)
    assert np.hypot(F[0], F[1]) == pytest.approx(0.3 * Fn)
    assert vibration_sigma(0.0, 1e-5) == pytest.approx(1.3e4 * 2 * 1e-5 + 0.6)
