"""Hexapod dynamics [Rybak n.d.]: closed forms, algebraic and numerical round trips, energy."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from robomill import hexapod as hp


@pytest.fixture(scope="module")
def section(config):
    return config["hexapod"]


@pytest.fixture(scope="module")
def hx(section):
    return hp.hexapod_from_config(section)


def _random_state(rng, z0=0.0533):
    p = np.array([0.0, 0.0, z0]) + rng.normal(0, 3e-3, 3)
    R = Rotation.from_rotvec(rng.normal(0, 0.05, 3)).as_matrix()
    return p, R, rng.normal(0, 0.02, 6)


def test_joint_circle_pairs():
    pts = hp.joint_circle(2.0, 10.0, 0.0)
    np.testing.assert_allclose(np.linalg.norm(pts, axis=1), 2.0)
    ang = np.rad2deg(np.arctan2(pts[:, 1], pts[:, 0]))
    np.testing.assert_allclose(ang, [-10, 10, 110, 130, -130, -110], atol=1e-12)


def test_static_forces_equal_closed_form(hx, section):
    """Symmetric platform at rest at (0, 0, h): six equal forces, equal to the closed form
    (platform weight and the legs' own weight shared by the six legs)."""
    for h in (0.045, 0.0533, 0.07):
        forces = hp.inverse_dynamics(hx, np.array([0, 0, h]), np.eye(3), np.zeros(6),
                                     np.zeros(6))
        np.testing.assert_allclose(forces, hp.static_force_closed_form(hx, h), rtol=1e-12)
    # massless legs: Γ = M g ℓ / (6 h)
    light = hp.Hexapod(hx.base_m, hx.platform_m, hx.mass_kg, hx.com_m, hx.inertia_kg_m2,
                       hp.Leg(0, 0, 0, 0, 0, 0))
    legs = hp.inverse_kinematics(light, np.array([0, 0, 0.0533]), np.eye(3))
    expect = hx.mass_kg * hp.G0_M_S2 * legs.length[0] / (6 * 0.0533)
    forces = hp.inverse_dynamics(light, np.array([0, 0, 0.0533]), np.eye(3), np.zeros(6),
                                 np.zeros(6))
    np.testing.assert_allclose(forces, expect, rtol=1e-12)


def test_jacobian_gives_leg_rates(hx):
    rng = np.random.default_rng(1)
    p, R, twist = _random_state(rng)
    dt = 1e-7
    R2 = Rotation.from_rotvec(twist[3:] * dt).as_matrix() @ R
    l1 = hp.inverse_kinematics(hx, p + twist[:3] * dt, R2).length
    l0 = hp.inverse_kinematics(hx, p, R).length
    jr = hp.jacobian(hp.inverse_kinematics(hx, p, R))
    np.testing.assert_allclose((l1 - l0) / dt, jr @ twist, rtol=1e-5, atol=1e-10)


def test_leg_inertia_is_linear_part_of_newton_euler(hx):
    """A_xi (seed: J_i⁻ᵀ A_i J_i⁻¹) equals the p̈-linear part of the leg's Newton–Euler."""
    rng = np.random.default_rng(2)
    base, tip, vel = hx.base_m[0], np.array([0.03, -0.01, 0.055]), rng.normal(0, 0.05, 3)
    g = hx.gravity_m_s2
    b = hp.leg_tip_force(hx.leg, base, tip, vel, np.zeros(3), g)
    d = tip - base
    ax = hp.leg_inertia(hx.leg, d / np.linalg.norm(d), np.linalg.norm(d))
    for k in range(3):
        e = np.eye(3)[k]
        np.testing.assert_allclose(hp.leg_tip_force(hx.leg, base, tip, vel, e, g) - b,
                                   ax @ e, rtol=1e-10, atol=1e-14)


def test_inverse_then_forward_acceleration_is_identity(hx):
    """Seed eq. 6 inverts the inverse model exactly at arbitrary states."""
    rng = np.random.default_rng(3)
    for _ in range(5):
        p, R, twist = _random_state(rng)
        acc = rng.normal(0, 1.0, 6)
        forces = hp.inverse_dynamics(hx, p, R, twist, acc)
        np.testing.assert_allclose(hp.forward_acceleration(hx, p, R, twist, forces), acc,
                                   rtol=1e-9, atol=1e-9)


def test_programme_state_matches_seed_programme(section):
    prog = hp.programme_from_config(section)
    p, v, a = prog.state(4.0)
    np.testing.assert_allclose(p * 1e3, [4.0, 40.0, 53.3], atol=1e-12)
    np.testing.assert_allclose(v * 1e3, [0.0, 20.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(prog.state(2.0, segment=0)[2] * 1e3, [1, 5, 0])
    np.testing.assert_allclose(prog.state(2.0)[2] * 1e3, [-1, 5, 0])


ROUND_TRIP_BOUND_MM = 1e-6
"""Inverse → forward dynamics round trip: largest position error over the first 0.5 s of the
seed programme (and the whole 0.3 s vertical move) with rtol 1e-10, atol 1e-12. Open-loop
force control is unstable (e-folding time ≈ 80 ms, see test_open_loop_is_unstable), so the
replay of the full 4 s programme cannot hold: the bound is stated for this horizon."""


def test_round_trip_reproduces_commanded_trajectory(hx, section):
    prog = hp.programme_from_config(section)
    short = hp.Programme(np.array([0.0, 0.25, 0.5]), prog.accel_m_s2, prog.start_m)
    for pr in (short, hp.vertical_from_config(section)):
        t = np.linspace(pr.edges_s[0], pr.edges_s[-1], 51)
        sim = hp.run_programme(hx, pr, t)
        cmd = np.array([pr.state(ti)[0] for ti in t])
        err_mm = np.abs(sim.position - cmd).max() * 1e3
        assert err_mm < ROUND_TRIP_BOUND_MM, err_mm
        assert np.abs(sim.euler).max() < 1e-9
    # and the check bites: a 0.1 % force error leaves the commanded path at once
    sim = hp.run_programme(hx, short, t * 0.5, force_scale=[1.001, 1, 1, 1, 1, 1])
    assert np.abs(sim.position[-1] - short.state(0.5)[0]).max() * 1e3 > 1e3 * ROUND_TRIP_BOUND_MM


@pytest.mark.parametrize("damping", [0.0, 0.5])
def test_energy_conserved_without_actuation_and_damping(hx, damping):
    """Γ = 0: the platform falls freely on its legs; total energy is constant without
    actuator damping and decreases with it."""
    leg = hp.Leg(**{**hx.leg.__dict__, "damping_N_s_m": damping})
    free = hp.Hexapod(hx.base_m, hx.platform_m, hx.mass_kg, np.array([0.002, -0.001, 0.004]),
                      hx.inertia_kg_m2, leg)
    p0, R0 = np.array([0.001, 0.0, 0.0533]), Rotation.from_rotvec([0.02, -0.01, 0.03])
    twist0 = np.array([0.01, -0.02, 0.03, 0.2, -0.1, 0.3])
    y0 = hp.state_vector(p0, R0.as_matrix(), twist0)
    t = np.linspace(0.0, 0.05, 11)
    sim = hp.simulate(free, y0, lambda t, y, s: np.zeros(6), t)
    energy = np.array([hp.total_energy(free, p, R, tw) for p, R, tw in
                       zip(sim.position, sim.rotation, sim.twist, strict=True)])
    assert np.ptp(sim.position[:, 2]) > 1e-3        # it really moved (fell ≈ 12 mm)
    if damping == 0.0:
        assert np.ptp(energy) < 1e-9 * np.abs(energy).max()
    else:
        assert np.all(np.diff(energy) < 0)


def test_open_loop_is_unstable(hx, section):
    """Linearised force-controlled platform: real ±λ pairs (inverted pendulum)."""
    p0 = np.asarray(section["start_mm"]) * 1e-3
    ev, _ = hp.instability_rates(hx, p0, np.eye(3))
    assert np.abs(ev.imag).max() < 1e-6 * np.abs(ev).max()
    lam = np.sort(ev.real)
    np.testing.assert_allclose(lam, -lam[::-1], rtol=1e-5, atol=1e-6)
    assert 5.0 < lam[-1] < 30.0       # order of sqrt(g / h) = 13.6 1/s


def test_sensitivity_antisymmetric_to_first_order(hx, section):
    """Drift for +e and −e cancel to first order: |d(+e) + d(−e)| ≪ |d(+e)|, and halving e
    divides that remainder by about four (second order)."""
    prog = hp.vertical_from_config(section)
    rem = []
    for e in (0.5, 0.25):
        dp_plus, dr_plus = hp.force_error_drift(hx, prog, 1, e)
        dp_minus, dr_minus = hp.force_error_drift(hx, prog, 1, -e)
        sym = np.linalg.norm(dp_plus + dp_minus)
        assert sym < 0.1 * np.linalg.norm(dp_plus)
        assert np.linalg.norm(dr_plus + dr_minus) < 0.1 * np.linalg.norm(dr_plus)
        rem.append(sym)
    assert 3.0 < rem[0] / rem[1] < 5.0


def test_seed_vertical_move_behaviour(hx, section):
    """The seed's case: equal forces of ≈1.65 N lift the platform; actuator 1 at +1 %
    drifts it by millimetres and tilts it by degrees."""
    prog = hp.vertical_from_config(section)
    forces = hp.programme_forces(hx, prog)(0.0)
    np.testing.assert_allclose(forces, forces[0], rtol=1e-12)
    assert abs(forces[0] - 1.65) < 0.01
    dp, dr = hp.force_error_drift(hx, prog, 1, 1.0)
    assert 1.0 < np.linalg.norm(dp) * 1e3 < 10.0
    assert 1.0 < np.rad2deg(np.linalg.norm(dr)) < 10.0


def _planted_map(slopes_mm_per_pct, errors=(-1.0, -0.5, 0.5, 1.0), bend=0.0):
    """A sensitivity map whose drift is exactly slope · e (plus ``bend`` · e² along x)."""
    import xarray as xr

    from robomill.hexapod import gather_sensitivity

    e = np.asarray(errors)
    shards = []
    for i, s in enumerate(slopes_mm_per_pct, start=1):
        d = np.zeros((1, e.size, 3))
        d[0, :, 2] = s * e
        d[0, :, 0] = bend * e**2
        shards.append(xr.Dataset(
            {"drift_components_mm": (("actuator", "force_error_pct", "axis"), d),
             "rotvec_deg": (("actuator", "force_error_pct", "axis"), 0 * d)},
            coords={"actuator": [i], "force_error_pct": e, "axis": ["x", "y", "z"]},
            attrs={"duration_s": 0.3}))
    return gather_sensitivity(shards)


def test_force_accuracy_requirement_from_a_planted_linear_map():
    from robomill.hexapod import force_accuracy_requirement

    sens = _planted_map([2.0, 4.0, 3.0])  # mm per %: actuator 2 is the worst
    t = force_accuracy_requirement(sens, actuator_force_N=1.65, tolerances_mm=[0.01, 0.1])
    assert list(t.columns) == ["position_tolerance_mm", "force_accuracy_pct",
                               "force_accuracy_mN", "worst_actuator", "drift_mm_per_pct",
                               "duration_s"]
    assert t["worst_actuator"].tolist() == [2, 2]
    np.testing.assert_allclose(t["drift_mm_per_pct"], 4.0)
    np.testing.assert_allclose(t["force_accuracy_pct"], [0.0025, 0.025])
    np.testing.assert_allclose(t["force_accuracy_mN"], [0.0025 / 100 * 1650, 0.025 / 100 * 1650])
    assert t["duration_s"].iloc[0] == 0.3
    with pytest.raises(ValueError, match="tolerances_mm"):
        force_accuracy_requirement(sens, 1.65, tolerances_mm=[0.0])
    with pytest.raises(ValueError, match="actuator_force_N"):
        force_accuracy_requirement(sens, -1.0)


def test_drift_antisymmetry_sees_a_planted_even_part():
    from robomill.hexapod import drift_antisymmetry

    assert drift_antisymmetry(_planted_map([2.0]))[1] == pytest.approx(0.0, abs=1e-12)
    ep, frac = drift_antisymmetry(_planted_map([2.0], bend=1.0))
    # at e = 0.5: d(+e) + d(-e) = (2 · 0.25, 0, 0); |d(+e)| = |(0.25, 0, 1)|
    assert ep == 0.5 and frac == pytest.approx(0.5 / np.hypot(0.25, 1.0))
    assert drift_antisymmetry(_planted_map([2.0], errors=(0.5, 1.0))) is None
