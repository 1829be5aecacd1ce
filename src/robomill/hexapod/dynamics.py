"""Inverse and forward dynamics of the Stewart–Gough hexapod [Rybak n.d., eqs 1–8].

Notation follows the seed (Khalil & Guegan's method): the platform twist
``V_p = [v_p; ω_p]`` (velocity of the platform origin and angular velocity, both in base
axes). The forward dynamics is seed eq. 6,

    V̇_p = A_m⁻¹ (J_rᵀ Γ − h_m),

with ``A_m`` (seed eq. 7) and ``h_m`` (seed eq. 8) (:func:`dynamic_model`).

The leg model is evaluated at its tip (Cartesian): ``A_xi = J_i⁻ᵀ A_i J_i⁻¹`` is the leg's
kinetic-energy metric in tip coordinates, ``A_xi = m_2 u uᵀ + (J_e/ℓ²)(E − u uᵀ)`` with
``J_e = m_1 c_1² + m_2 (ℓ − c_2)² + I_1 + I_2`` the leg inertia about its base joint, and the
combination ``h_xi − A_xi J̇_i q̇_i`` of seed eq. 8 is the leg's Newton–Euler tip force at zero
tip acceleration (``b_i`` below; it holds gravity, centripetal and Coriolis terms). The
seed's ``h_i = H_i(q, q̇, q̈ = 0)`` is the same idea in joint coordinates; the tip form needs no
universal-joint angles and no ``J̇_i``.

Units: SI throughout (m, kg, s, N, rad).
"""

from __future__ import annotations

import numpy as np

from robomill.hexapod.geometry import (
    Hexapod,
    Leg,
    inverse_kinematics,
    jacobian,
    skew,
    vcross,
    vdot,
)


def leg_inertia(leg: Leg, u: np.ndarray, length: np.ndarray) -> np.ndarray:
    """``A_xi``, the leg's inertia in tip coordinates (seed, after eq. 8:
    ``A_xi = J_i⁻ᵀ A_i J_i⁻¹``): ``m_2 u uᵀ + (J_e/ℓ²)(E − u uᵀ)``, with
    ``J_e = m_1 c_1² + m_2 (ℓ − c_2)² + I_1 + I_2``. Vectorised: ``u`` (..., 3), ``length``
    (...) → (..., 3, 3)."""
    length = np.asarray(length, float)
    je = (leg.m1_kg * leg.c1_m**2 + leg.m2_kg * (length - leg.c2_m) ** 2
          + leg.I1_kg_m2 + leg.I2_kg_m2)
    uu = u[..., :, None] * u[..., None, :]
    k = (je / length**2)[..., None, None]
    return leg.m2_kg * uu + k * (np.eye(3) - uu)


def leg_tip_force(leg: Leg, base: np.ndarray, tip: np.ndarray, tip_vel: np.ndarray,
                  tip_acc: np.ndarray, gravity: np.ndarray) -> np.ndarray:
    """Newton–Euler model of an unactuated leg (seed eq. 2 with Γ = 0, damping included):
    the force the platform must apply at the tip to move it with ``tip_vel``, ``tip_acc``.

    Equals ``A_xi p̈ + b_i`` with ``b_i`` this function at ``tip_acc = 0``; the force of the leg
    on the platform is ``u Γ − (A_xi p̈ + b_i)``. Moment balance about the base joint
    (perpendicular to the leg; gyroscopic terms vanish for axisymmetric bodies that do not
    spin) gives the lateral part, the piston's axial balance the axial part. Vectorised over
    leading dimensions of the (..., 3) arguments.
    """
    d = tip - base
    ell = np.linalg.norm(d, axis=-1)
    u = d / ell[..., None]
    ell_d = vdot(u, tip_vel)
    w = vcross(u, tip_vel) / ell[..., None]              # leg angular velocity (no spin)
    ell_dd = vdot(u, tip_acc) + (vdot(tip_vel, tip_vel) - ell_d**2) / ell
    u_d = vcross(w, u)
    w_d = ((vcross(u_d, tip_vel) + vcross(u, tip_acc)) / ell[..., None]
           - (ell_d / ell)[..., None] * w)
    # centre-of-mass accelerations (the base joint is fixed)
    rot = vcross(w_d, u) + vcross(w, u_d)
    arm2 = (ell - leg.c2_m)[..., None]
    a1 = leg.c1_m * rot
    a2 = ell_dd[..., None] * u + 2.0 * ell_d[..., None] * u_d + arm2 * rot
    moment = (leg.m1_kg * leg.c1_m * vcross(u, a1 - gravity)
              + leg.m2_kg * arm2 * vcross(u, a2 - gravity)
              + (leg.I1_kg_m2 + leg.I2_kg_m2) * w_d)
    f_perp = vcross(moment, u) / ell[..., None]
    f_axial = leg.m2_kg * vdot(u, a2 - gravity) + leg.damping_N_s_m * ell_d
    return f_axial[..., None] * u + f_perp


def leg_energy(leg: Leg, base: np.ndarray, tip: np.ndarray, tip_vel: np.ndarray,
               gravity: np.ndarray) -> np.ndarray:
    """Kinetic plus potential energy of a leg (J), potential zero at the base joint
    (vectorised over leading dimensions)."""
    d = tip - base
    ell = np.linalg.norm(d, axis=-1)
    u = d / ell[..., None]
    kin = 0.5 * np.einsum("...i,...ij,...j->...", tip_vel, leg_inertia(leg, u, ell), tip_vel)
    pot = -(leg.m1_kg * leg.c1_m + leg.m2_kg * (ell - leg.c2_m)) * vdot(u, gravity)
    return kin + pot


def platform_inertia(hx: Hexapod, R: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(I_s, MS_p, I_p)``: the platform's 6×6 spatial inertia about its origin, first moment
    ``M_p R c`` and inertia about the origin, all in base axes (seed eqs 7–8)."""
    r = R @ hx.com_m
    ms = hx.mass_kg * r
    ip = R @ hx.inertia_kg_m2 @ R.T + hx.mass_kg * ((r @ r) * np.eye(3) - np.outer(r, r))
    i_s = np.block([[hx.mass_kg * np.eye(3), -skew(ms)], [skew(ms), ip]])
    return i_s, ms, ip


def dynamic_model(hx: Hexapod, p: np.ndarray, R: np.ndarray, twist: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(A_m, h_m, J_r)`` at one state so that ``A_m V̇_p + h_m = J_rᵀ Γ``.

    ``A_m = I_s + Σ J_viᵀ A_xi J_vi`` (seed eq. 7 with S = E) and
    ``h_m = [ω×(ω×MS_p); ω×(I_p ω)] − [M_p g; MS_p × g] + Σ J_viᵀ (A_xi J̇_vi V_p + b_i)``
    (seed eq. 8 with S = E, ``b_i`` = ``h_xi − A_xi J̇_i q̇_i``).
    """
    legs = inverse_kinematics(hx, p, R)
    i_s, ms, ip = platform_inertia(hx, R)
    v, w = twist[:3], twist[3:]
    g = hx.gravity_m_s2
    h_m = np.concatenate([vcross(w, vcross(w, ms)) - hx.mass_kg * g,
                          vcross(w, ip @ w) - vcross(ms, g)])
    a = legs.a
    ax = leg_inertia(hx.leg, legs.u, legs.length)                 # (6, 3, 3)
    tip_vel = v + vcross(w, a)
    bias = leg_tip_force(hx.leg, hx.base_m, legs.tip, tip_vel, np.zeros_like(a), g)
    tip_force = np.einsum("ijk,ik->ij", ax, vcross(w, vcross(w, a))) + bias  # (6, 3)
    # J_viᵀ f = [f; a × f];  J_viᵀ A J_vi = [[A, −A â], [â A, −â A â]]
    ahat = np.zeros((6, 3, 3))
    ahat[:, 0, 1], ahat[:, 0, 2], ahat[:, 1, 2] = -a[:, 2], a[:, 1], -a[:, 0]
    ahat = ahat - ahat.transpose(0, 2, 1)
    a_ahat = ax @ ahat
    a_m = i_s.copy()
    a_m[:3, :3] += ax.sum(0)
    a_m[:3, 3:] -= a_ahat.sum(0)
    a_m[3:, :3] += (ahat @ ax).sum(0)
    a_m[3:, 3:] -= (ahat @ a_ahat).sum(0)
    h_m = h_m + np.concatenate([tip_force.sum(0), vcross(a, tip_force).sum(0)])
    return a_m, h_m, jacobian(legs)


def inverse_dynamics(hx: Hexapod, p: np.ndarray, R: np.ndarray, twist: np.ndarray,
                     twist_dot: np.ndarray) -> np.ndarray:
    """Actuator forces ``Γ`` (N) for the platform motion (seed's inverse problem
    ``M(X) Ẇ + C(W, X) + G = τ``): ``Γ = J_r⁻ᵀ (A_m V̇_p + h_m)``."""
    a_m, h_m, jr = dynamic_model(hx, p, R, twist)
    return np.linalg.solve(jr.T, a_m @ twist_dot + h_m)


def forward_acceleration(hx: Hexapod, p: np.ndarray, R: np.ndarray, twist: np.ndarray,
                         forces_N: np.ndarray) -> np.ndarray:
    """``V̇_p = A_m⁻¹ (J_rᵀ Γ − h_m)`` (seed eq. 6)."""
    a_m, h_m, jr = dynamic_model(hx, p, R, twist)
    return np.linalg.solve(a_m, jr.T @ forces_N - h_m)


def total_energy(hx: Hexapod, p: np.ndarray, R: np.ndarray, twist: np.ndarray) -> float:
    """Kinetic + gravitational energy of platform and legs (J); conserved when ``Γ = 0`` and
    the actuators have no damping."""
    i_s, ms, _ = platform_inertia(hx, R)
    g = hx.gravity_m_s2
    e = 0.5 * twist @ i_s @ twist - g @ (hx.mass_kg * p + ms)
    legs = inverse_kinematics(hx, p, R)
    tip_vel = twist[:3] + vcross(twist[3:], legs.a)
    return float(e + np.sum(leg_energy(hx.leg, hx.base_m, legs.tip, tip_vel, g)))


def static_force_closed_form(hx: Hexapod, height_m: float) -> float:
    """Actuator force holding a symmetric platform (centre of mass on the axis) at rest at
    ``(0, 0, h)`` with zero orientation: all six equal,

        Γ = [M_p g/6 + (s/ℓ) g (1 − u_z²)] / u_z + m_2 g u_z,

    with ``s = m_1 c_1 + m_2 (ℓ − c_2)`` the leg's first moment about its base joint and
    ``u_z = h/ℓ`` (vertical force balance of the platform with the legs' static tip forces).
    Valid when both joint circles have the same pair layout up to a rotation about z."""
    legs = inverse_kinematics(hx, np.array([0.0, 0.0, height_m]), np.eye(3))
    ell, uz = legs.length[0], legs.u[0, 2]
    lg = hx.leg
    s = lg.m1_kg * lg.c1_m + lg.m2_kg * (ell - lg.c2_m)
    g = -hx.gravity_m_s2[2]
    return float((hx.mass_kg * g / 6.0 + s / ell * g * (1.0 - uz**2)) / uz + lg.m2_kg * g * uz)
