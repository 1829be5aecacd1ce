"""A robot's rigid-body mass matrix from point masses (robomill.inertia; the virtual cell's
robomill.synth.inertia and the planner's documented masses use it): the rigid-body library's
tree must be the analysis kinematics' robot, for D-H and modified D-H parameters."""

from __future__ import annotations

import numpy as np
import pytest
from point_masses import kinetic_energy_J

from robomill.inertia import mass_matrix_kg_m2, rigid_body_model
from robomill.kinematics import SerialRobot


def test_two_link_planar_arm_has_the_textbook_mass_matrix():
    # point masses m1, m2 at the ends of links l1, l2 turning about parallel z axes:
    # M11 = m1 l1² + m2 (l1² + l2² + 2 l1 l2 cos q2), M12 = m2 (l2² + l1 l2 cos q2), M22 = m2 l2²
    l1, l2, m1, m2 = 0.5, 0.3, 4.0, 2.5
    robot = SerialRobot("planar", "dh", np.array([l1, l2]) * 1e3, np.zeros(2), np.zeros(2),
                        np.zeros(2))
    model = rigid_body_model(robot, np.array([1, 2]), np.array([m1, m2]),
                             np.array([[l1 * 1e3, 0, 0], [(l1 + l2) * 1e3, 0, 0]]))
    for q2 in (0.0, 0.7, -2.1):
        c = np.cos(q2)
        M = mass_matrix_kg_m2(model, np.array([0.4, q2]))
        expected = np.array([[m1 * l1**2 + m2 * (l1**2 + l2**2 + 2 * l1 * l2 * c),
                              m2 * (l2**2 + l1 * l2 * c)],
                             [m2 * (l2**2 + l1 * l2 * c), m2 * l2**2]])
        np.testing.assert_allclose(M, expected, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("convention", ["dh", "mdh"])
def test_kinetic_energy_matches_the_analysis_kinematics(convention):
    rng = np.random.default_rng(3)
    base = np.eye(4)
    base[:3, 3] = [100.0, -50.0, 20.0]
    robot = SerialRobot("r6", convention, rng.uniform(-300, 600, 6),
                        rng.uniform(-np.pi, np.pi, 6), rng.uniform(-200, 500, 6),
                        rng.uniform(-1, 1, 6), tool_mm=np.array([0.0, 10.0, 150.0]), base=base)
    link = np.array([1, 2, 3, 4, 5, 6, 6])
    mass_kg = rng.uniform(0.5, 30.0, 7)
    com_mm = rng.uniform(-500, 1200, (7, 3))
    model = rigid_body_model(robot, link, mass_kg, com_mm)
    for _ in range(3):
        q, qdot = rng.uniform(-2, 2, 6), rng.normal(size=6)
        M = mass_matrix_kg_m2(model, q)
        np.testing.assert_allclose(M, M.T, atol=1e-12)
        assert np.linalg.eigvalsh(M).min() > -1e-9
        assert 0.5 * qdot @ M @ qdot == pytest.approx(
            kinetic_energy_J(robot, link, mass_kg, com_mm, q, qdot), rel=1e-6)


def test_a_cell_files_mass_model_is_its_point_masses():
    """The planner's rigid-body model of a cell file's ``mass_model`` (links, then the tool on
    the last link) has the kinetic energy of those point masses; none without one."""
    from robomill.inertia import documented_rigid_body_model
    from robomill.io.cell import CellMassModel, PointMass

    rng = np.random.default_rng(5)
    robot = SerialRobot("r6", "dh", rng.uniform(-300, 600, 6), rng.uniform(-np.pi, np.pi, 6),
                        rng.uniform(-200, 500, 6), rng.uniform(-1, 1, 6))
    links = tuple(PointMass(j, float(m), tuple(c)) for j, m, c in
                  zip((1, 2, 3), rng.uniform(1, 40, 3), rng.uniform(-500, 1200, (3, 3)),
                      strict=True))
    tool = PointMass(6, 5.0, (880.0, 10.0, 1186.5))
    model = documented_rigid_body_model(robot, CellMassModel(links, tool))
    q, qdot = rng.uniform(-2, 2, 6), rng.normal(size=6)
    pts = [*links, tool]
    expected = kinetic_energy_J(robot, np.array([p.link for p in pts]),
                                np.array([p.mass_kg for p in pts]),
                                np.array([p.com_mm for p in pts]), q, qdot)
    assert 0.5 * qdot @ mass_matrix_kg_m2(model, q) @ qdot == pytest.approx(expected, rel=1e-6)
    assert documented_rigid_body_model(robot, None) is None


def test_a_shape_no_elastic_joint_moves_has_no_rayleigh_mass():
    """A planar arm's tool tip along z (the joints turn about z): no joint compliance moves
    it, so the quotient has no stiffness to divide by: κ infinite, μ NaN, never an error; a
    shape in the plane gets both finite."""
    from robomill.inertia import rayleigh_stiffness_mass

    robot = SerialRobot("planar", "dh", np.array([500.0, 300.0]), np.zeros(2), np.zeros(2),
                        np.zeros(2))
    model = rigid_body_model(robot, np.array([1, 2]), np.array([4.0, 2.5]),
                             np.array([[500.0, 0, 0], [800.0, 0, 0]]))
    c = np.array([1e-6, 3e-6])
    kappa, mu = rayleigh_stiffness_mass(robot, c, model, np.array([0.3, 1.1]), [0, 0, 1.0])
    assert np.isinf(kappa) and np.isnan(mu)
    kappa, mu = rayleigh_stiffness_mass(robot, c, model, np.array([0.3, 1.1]), [1.0, 0, 0])
    assert np.isfinite(kappa) and kappa > 0 and np.isfinite(mu) and mu > 0
