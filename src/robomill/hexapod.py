"""Stewart–Gough hexapod: kinematics, inverse and forward dynamics (seed 003, eqs 1–8).

The machine: six UPS legs (universal joint on the base, prismatic actuator, spherical joint on
the platform). Base joints ``B_i`` lie on a circle in the base plane, platform joints ``P_i`` on
a circle in the platform plane; each leg is two axisymmetric bodies, a cylinder hinged at
``B_i`` and a piston ending at ``P_i``, and the actuator force ``Γ_i`` acts between them.

Notation follows the seed (Khalil & Guegan's method): the platform twist
``V_p = [v_p; ω_p]`` (velocity of the platform origin and angular velocity, both in base
axes), the tip velocity of leg *i* ``v_i = J_vi V_p`` (seed eq. 4) with
``J_vi = [E_3, −â_i]``, and the kinematic Jacobian ``J_r`` whose row *i* is
``[u_iᵀ, (a_i × u_i)ᵀ]`` (``ℓ̇ = J_r V_p``). The forward dynamics is seed eq. 6,

    V̇_p = A_m⁻¹ (J_rᵀ Γ − h_m),

with ``A_m`` (seed eq. 7) and ``h_m`` (seed eq. 8). We integrate the twist itself, so the
seed's ``S`` is the identity and ``Ṡ = 0``; orientation is carried as a unit quaternion.

The leg model is evaluated at its tip (Cartesian): ``A_xi = J_i⁻ᵀ A_i J_i⁻¹`` is the leg's
kinetic-energy metric in tip coordinates, ``A_xi = m_2 u uᵀ + (J_e/ℓ²)(E − u uᵀ)`` with
``J_e = m_1 c_1² + m_2 (ℓ − c_2)² + I_1 + I_2`` the leg inertia about its base joint, and the
combination ``h_xi − A_xi J̇_i q̇_i`` of seed eq. 8 is the leg's Newton–Euler tip force at zero
tip acceleration (``b_i`` below; it holds gravity, centripetal and Coriolis terms). The
seed's ``h_i = H_i(q, q̇, q̈ = 0)`` is the same idea in joint coordinates; the tip form needs no
universal-joint angles and no ``J̇_i``.

Units: SI throughout (m, kg, s, N, rad). :func:`hexapod_from_config` converts the config's
millimetres.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

if TYPE_CHECKING:
    import pandas as pd

G0_M_S2 = 9.80665
"""Standard gravity (m/s²)."""


# ---------------------------------------------------------------------------------- geometry
def joint_circle(radius_m: float, half_angle_deg: float, phase_deg: float = 0.0) -> np.ndarray:
    """Six joints on a circle in pairs: pair *k* at ``phase + 120° k ± half_angle``.

    Returns
    -------
    ndarray, shape (6, 3)
        Joint positions (z = 0) in the circle's frame, ordered
        ``phase − h, phase + h, phase + 120° − h, …`` (joint 1 first).
    """
    centres = phase_deg + 120.0 * np.arange(3)
    ang = np.deg2rad(np.ravel(np.column_stack([centres - half_angle_deg,
                                               centres + half_angle_deg])))
    return np.column_stack([radius_m * np.cos(ang), radius_m * np.sin(ang), np.zeros(6)])


def skew(a: np.ndarray) -> np.ndarray:
    """The cross-product matrix ``â`` with ``â b = a × b``."""
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("...k,...k->...", a, b)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a × b`` over the last axis (broadcasting; faster than ``np.cross`` on small arrays)."""
    a, b = np.asarray(a), np.asarray(b)
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


@dataclass(frozen=True)
class Leg:
    """One UPS leg: cylinder (body 1, hinged at the base joint) and piston (body 2, ending at
    the platform joint). ``c1_m`` is the cylinder's centre of mass from the base joint,
    ``c2_m`` the piston's centre of mass from the platform joint; ``I*_kg_m2`` are the bodies'
    inertias about their own centre of mass, perpendicular to the leg (the axial inertia is
    neglected: a UPS leg cannot spin). ``damping_N_s_m`` is a viscous actuator friction."""

    m1_kg: float
    c1_m: float
    I1_kg_m2: float
    m2_kg: float
    c2_m: float
    I2_kg_m2: float
    damping_N_s_m: float = 0.0


@dataclass(frozen=True)
class Hexapod:
    """A Stewart–Gough platform (all quantities SI, base axes with z up).

    Attributes
    ----------
    base_m : (6, 3) base joints ``B_i`` in the base frame.
    platform_m : (6, 3) platform joints in the platform frame (origin = platform centre).
    mass_kg : platform mass ``M_p`` (with spindle and tool).
    com_m : (3,) platform centre of mass in the platform frame.
    inertia_kg_m2 : (3, 3) platform inertia about its centre of mass, platform frame.
    leg : the leg model (the same for all six legs).
    gravity_m_s2 : (3,) gravity vector in base axes.
    """

    base_m: np.ndarray
    platform_m: np.ndarray
    mass_kg: float
    com_m: np.ndarray
    inertia_kg_m2: np.ndarray
    leg: Leg
    gravity_m_s2: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, -G0_M_S2]))


def hexapod_from_config(section: Mapping[str, Any]) -> Hexapod:
    """Build a :class:`Hexapod` from the ``hexapod`` config section (millimetres → metres)."""
    g = section["geometry"]
    lg = section["leg"]
    p = section["platform"]
    mm = 1e-3
    return Hexapod(
        base_m=joint_circle(g["base_radius_mm"] * mm, g["base_half_angle_deg"],
                            g["base_phase_deg"]),
        platform_m=joint_circle(g["platform_radius_mm"] * mm, g["platform_half_angle_deg"],
                                g["platform_phase_deg"]),
        mass_kg=float(p["mass_kg"]),
        com_m=np.asarray(p["com_mm"], float) * mm,
        inertia_kg_m2=np.diag(np.asarray(p["inertia_kg_m2"], float)),
        leg=Leg(m1_kg=lg["cylinder_mass_kg"], c1_m=lg["cylinder_com_mm"] * mm,
                I1_kg_m2=lg["cylinder_inertia_kg_m2"], m2_kg=lg["piston_mass_kg"],
                c2_m=lg["piston_com_mm"] * mm, I2_kg_m2=lg["piston_inertia_kg_m2"],
                damping_N_s_m=lg["damping_N_s_m"]),
        gravity_m_s2=np.array([0.0, 0.0, -float(section["gravity_m_s2"])]),
    )


def euler_to_matrix(euler_rad: Sequence[float]) -> np.ndarray:
    """Rotation ``R = Rz(φ) Ry(θ) Rx(ψ)`` from Euler angles ``(ψ, θ, φ)`` (rad)."""
    return Rotation.from_euler("xyz", euler_rad).as_matrix()


def matrix_to_euler(R: np.ndarray) -> np.ndarray:
    """Euler angles ``(ψ, θ, φ)`` (rad) of ``R = Rz(φ) Ry(θ) Rx(ψ)``."""
    return Rotation.from_matrix(R).as_euler("xyz")


# ---------------------------------------------------------------------------------- kinematics
@dataclass(frozen=True)
class Legs:
    """Inverse kinematics at one pose: per leg the platform-joint offset ``a_i = R p_i`` (from
    the platform origin, base axes), tip ``P_i``, length ``ℓ_i`` and unit vector ``u_i``."""

    a: np.ndarray
    tip: np.ndarray
    length: np.ndarray
    u: np.ndarray


def inverse_kinematics(hx: Hexapod, p: np.ndarray, R: np.ndarray) -> Legs:
    """Leg lengths and directions at platform pose ``(p, R)`` (closed form, ``ℓ_i = |p + R
    p_i − B_i|``)."""
    a = hx.platform_m @ R.T
    tip = p + a
    d = tip - hx.base_m
    length = np.linalg.norm(d, axis=1)
    return Legs(a=a, tip=tip, length=length, u=d / length[:, None])


def jacobian(legs: Legs) -> np.ndarray:
    """The kinematic (inverse) Jacobian ``J_r``: ``ℓ̇ = J_r V_p``, row *i* =
    ``[u_iᵀ, (a_i × u_i)ᵀ]``; ``J_rᵀ Γ`` is the wrench of the actuator forces on the platform
    (about its origin)."""
    return np.hstack([legs.u, _cross(legs.a, legs.u)])


def tip_jacobian(a_i: np.ndarray) -> np.ndarray:
    """``J_vi = [E_3, −â_i]`` (seed eq. 4): tip velocity of leg *i* from the platform twist."""
    return np.hstack([np.eye(3), -skew(a_i)])


# ---------------------------------------------------------------------------------- leg model
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
    ell_d = _dot(u, tip_vel)
    w = _cross(u, tip_vel) / ell[..., None]              # leg angular velocity (no spin)
    ell_dd = _dot(u, tip_acc) + (_dot(tip_vel, tip_vel) - ell_d**2) / ell
    u_d = _cross(w, u)
    w_d = ((_cross(u_d, tip_vel) + _cross(u, tip_acc)) / ell[..., None]
           - (ell_d / ell)[..., None] * w)
    # centre-of-mass accelerations (the base joint is fixed)
    rot = _cross(w_d, u) + _cross(w, u_d)
    arm2 = (ell - leg.c2_m)[..., None]
    a1 = leg.c1_m * rot
    a2 = ell_dd[..., None] * u + 2.0 * ell_d[..., None] * u_d + arm2 * rot
    moment = (leg.m1_kg * leg.c1_m * _cross(u, a1 - gravity)
              + leg.m2_kg * arm2 * _cross(u, a2 - gravity)
              + (leg.I1_kg_m2 + leg.I2_kg_m2) * w_d)
    f_perp = _cross(moment, u) / ell[..., None]
    f_axial = leg.m2_kg * _dot(u, a2 - gravity) + leg.damping_N_s_m * ell_d
    return f_axial[..., None] * u + f_perp


def leg_energy(leg: Leg, base: np.ndarray, tip: np.ndarray, tip_vel: np.ndarray,
               gravity: np.ndarray) -> np.ndarray:
    """Kinetic plus potential energy of a leg (J), potential zero at the base joint
    (vectorised over leading dimensions)."""
    d = tip - base
    ell = np.linalg.norm(d, axis=-1)
    u = d / ell[..., None]
    kin = 0.5 * np.einsum("...i,...ij,...j->...", tip_vel, leg_inertia(leg, u, ell), tip_vel)
    pot = -(leg.m1_kg * leg.c1_m + leg.m2_kg * (ell - leg.c2_m)) * _dot(u, gravity)
    return kin + pot


# ---------------------------------------------------------------------------------- dynamics
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
    h_m = np.concatenate([_cross(w, _cross(w, ms)) - hx.mass_kg * g,
                          _cross(w, ip @ w) - _cross(ms, g)])
    a = legs.a
    ax = leg_inertia(hx.leg, legs.u, legs.length)                 # (6, 3, 3)
    tip_vel = v + _cross(w, a)
    bias = leg_tip_force(hx.leg, hx.base_m, legs.tip, tip_vel, np.zeros_like(a), g)
    tip_force = np.einsum("ijk,ik->ij", ax, _cross(w, _cross(w, a))) + bias  # (6, 3)
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
    h_m = h_m + np.concatenate([tip_force.sum(0), _cross(a, tip_force).sum(0)])
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
    tip_vel = twist[:3] + _cross(twist[3:], legs.a)
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


# ---------------------------------------------------------------------------------- motion
def _quat_dot(q: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Derivative of the scalar-last unit quaternion for the angular velocity ``w`` in base
    axes: ``q̇ = ½ [w, 0] ⊗ q``."""
    qv, qw = q[:3], q[3]
    return 0.5 * np.concatenate([qw * w + _cross(w, qv), [-(w @ qv)]])


def state_vector(p: np.ndarray, R: np.ndarray, twist: np.ndarray) -> np.ndarray:
    """ODE state ``[p (3), quaternion xyzw (4), v (3), ω (3)]``."""
    return np.concatenate([p, Rotation.from_matrix(R).as_quat(), twist])


def unpack_state(y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(p, R, twist)`` from an ODE state (quaternion renormalised)."""
    q = y[3:7] / np.linalg.norm(y[3:7])
    return y[:3], Rotation.from_quat(q).as_matrix(), y[7:13]


ForceLaw = Callable[[float, np.ndarray, int], np.ndarray]
"""``forces(t, state, segment) -> Γ`` (N, shape (6,)); ``segment`` is the index of the
integration interval between breakpoints (a law may ignore it)."""


@dataclass(frozen=True)
class Simulation:
    """Forward-dynamics result: time (s), position (m), Euler angles ``(ψ, θ, φ)`` (rad),
    twist and the applied forces at the output times; ``nfev`` right-hand-side calls."""

    t: np.ndarray
    position: np.ndarray
    euler: np.ndarray
    rotation: np.ndarray
    twist: np.ndarray
    forces: np.ndarray
    nfev: int
    t_stop: float | None = None


def simulate(hx: Hexapod, y0: np.ndarray, forces: ForceLaw, t_eval: np.ndarray,
             breakpoints: Sequence[float] = (), rtol: float = 1e-10, atol: float = 1e-12,
             method: str = "DOP853", stop: Callable[[float, np.ndarray], float] | None = None
             ) -> Simulation:
    """Integrate the forward dynamics (seed eq. 6) with ``scipy.integrate.solve_ivp``.

    The integration restarts at every ``breakpoint`` (a jump of the commanded acceleration),
    so the adaptive steps never straddle a discontinuity. Tolerances ``rtol``/``atol`` apply to
    the state in SI units (m, m/s, rad/s and the quaternion). ``stop(t, y)`` is a terminal
    event: the integration ends where it crosses zero (the result then stops early).
    """
    t_eval = np.asarray(t_eval, float)
    edges = [t_eval[0], *[b for b in breakpoints if t_eval[0] < b < t_eval[-1]], t_eval[-1]]

    events = None
    if stop is not None:
        def event(t, y, seg):
            return stop(t, y)
        event.terminal = True
        events = [event]

    def rhs(t, y, seg):
        p, R, twist = unpack_state(y)
        acc = forward_acceleration(hx, p, R, twist, forces(t, y, seg))
        q = y[3:7] / np.linalg.norm(y[3:7])
        return np.concatenate([twist[:3], _quat_dot(q, twist[3:]), acc])

    ys, ts, segs, nfev, y, t_stop = [], [], [], 0, np.asarray(y0, float), None
    for k, (t0, t1) in enumerate(zip(edges[:-1], edges[1:], strict=True)):
        last = k == len(edges) - 2
        sel = (t_eval >= t0) & ((t_eval <= t1) if last else (t_eval < t1))
        sol = solve_ivp(rhs, (t0, t1), y, method=method, t_eval=t_eval[sel], rtol=rtol,
                        atol=atol, dense_output=True, args=(k,), events=events)
        if not sol.success:
            raise RuntimeError(f"forward dynamics failed on [{t0}, {t1}] s: {sol.message}")
        nfev += sol.nfev
        ys.append(sol.y.T)
        ts.append(sol.t)
        segs.append(np.full(sol.t.size, k))
        y = sol.sol(t1)
        if sol.status == 1:                                   # stopped by the event
            t_stop = float(sol.t_events[0][0])
            break
    t = np.concatenate(ts)
    y_all = np.vstack(ys)
    pos, rot, tw, fs = [], [], [], []
    for ti, yi, si in zip(t, y_all, np.concatenate(segs), strict=True):
        p, R, twist = unpack_state(yi)
        pos.append(p)
        rot.append(R)
        tw.append(twist)
        fs.append(forces(ti, yi, int(si)))
    rot = np.array(rot)
    return Simulation(t=t, position=np.array(pos), euler=Rotation.from_matrix(rot).as_euler(
        "xyz"), rotation=rot, twist=np.array(tw), forces=np.array(fs), nfev=nfev,
        t_stop=t_stop)


@dataclass(frozen=True)
class Programme:
    """A platform motion with piecewise-constant linear acceleration and constant
    orientation (seed: γ_x = +1 on [0, 2] s, −1 on [2, 4] s, γ_y = 5 on [0, 4] s, start at
    rest). ``edges_s`` are the segment limits (n + 1), ``accel_m_s2`` one row (3,) per
    segment; ``start_m`` the start position and ``euler_rad`` the fixed orientation."""

    edges_s: np.ndarray
    accel_m_s2: np.ndarray
    start_m: np.ndarray
    euler_rad: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def segment_of(self, t: float) -> int:
        """Index of the segment holding ``t`` (right-continuous; the last one holds its end)."""
        k = int(np.searchsorted(self.edges_s, t, side="right")) - 1
        return int(np.clip(k, 0, len(self.edges_s) - 2))

    def state(self, t: float, segment: int | None = None
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Commanded ``(p, v, a)`` at time ``t`` (exact integration of the segments), on the
        polynomial of ``segment`` (default: the segment holding ``t``), so an integrator can
        reach a segment's end without seeing the next segment's acceleration."""
        k = self.segment_of(t) if segment is None else segment
        p, v = np.array(self.start_m, float), np.zeros(3)
        for j in range(k):
            a = np.asarray(self.accel_m_s2[j], float)
            dt = self.edges_s[j + 1] - self.edges_s[j]
            p, v = p + v * dt + 0.5 * a * dt**2, v + a * dt
        a = np.asarray(self.accel_m_s2[k], float)
        dt = t - self.edges_s[k]
        return p + v * dt + 0.5 * a * dt**2, v + a * dt, a

    @property
    def rotation(self) -> np.ndarray:
        return euler_to_matrix(self.euler_rad)


def programme_forces(hx: Hexapod, prog: Programme) -> ForceLaw:
    """Feed-forward force law: inverse dynamics of the commanded motion at time ``t`` (it does
    not look at the simulated state: open-loop force control, as in the seed)."""
    R = prog.rotation

    def law(t: float, y: np.ndarray | None = None, segment: int | None = None) -> np.ndarray:
        p, v, a = prog.state(t, segment)
        return inverse_dynamics(hx, p, R, np.concatenate([v, np.zeros(3)]),
                                np.concatenate([a, np.zeros(3)]))

    return law


def run_programme(hx: Hexapod, prog: Programme, t_eval: np.ndarray,
                  force_scale: np.ndarray | None = None, rtol: float = 1e-10,
                  atol: float = 1e-12, stop_error_m: float | None = None,
                  method: str = "DOP853") -> Simulation:
    """Forward dynamics under the programme's inverse-dynamics forces, each actuator's force
    multiplied by ``force_scale`` (6,) (1 = exact; 1.01 = +1 % error).

    With ``stop_error_m`` the integration stops once the position leaves the commanded one by
    that much (open-loop force control is unstable, see :func:`instability_rates`)."""
    law = programme_forces(hx, prog)
    scale = np.ones(6) if force_scale is None else np.asarray(force_scale, float)
    p0, _, _ = prog.state(prog.edges_s[0])
    y0 = state_vector(p0, prog.rotation, np.zeros(6))
    stop = None
    if stop_error_m is not None:
        def stop(t, y):
            return stop_error_m - np.linalg.norm(y[:3] - prog.state(t)[0])
    return simulate(hx, y0, lambda t, y, seg: scale * law(t, y, seg), t_eval,
                    breakpoints=list(prog.edges_s[1:-1]), rtol=rtol, atol=atol, stop=stop,
                    method=method)


def pose_error(sim: Simulation, prog: Programme) -> tuple[np.ndarray, np.ndarray]:
    """Final position error (m, (3,)) and orientation error as a rotation vector (rad, (3,))
    of a simulation against the programme's exact motion at the final time."""
    p_exact, _, _ = prog.state(sim.t[-1])
    dp = sim.position[-1] - p_exact
    drot = Rotation.from_matrix(sim.rotation[-1] @ prog.rotation.T).as_rotvec()
    return dp, drot


def vertical_programme(start_m: Sequence[float], rise_m: float, duration_s: float
                       ) -> Programme:
    """The seed's vertical move: from rest at ``start`` up by ``rise`` in ``duration`` at
    constant acceleration ``2 rise / T²`` (seed: 53.3 → 54.57)."""
    acc = np.array([[0.0, 0.0, 2.0 * rise_m / duration_s**2]])
    return Programme(edges_s=np.array([0.0, duration_s]), accel_m_s2=acc,
                     start_m=np.asarray(start_m, float))


def force_error_drift(hx: Hexapod, prog: Programme, actuator: int, error_pct: float,
                      n_eval: int = 2, rtol: float = 1e-10, atol: float = 1e-12,
                      method: str = "DOP853") -> tuple[np.ndarray, np.ndarray]:
    """Final position error (m) and rotation vector (rad) when actuator ``actuator`` (1–6)
    delivers ``(1 + error_pct/100)`` times its inverse-dynamics force (seed: actuator 1 at
    +1 %)."""
    scale = np.ones(6)
    scale[actuator - 1] += error_pct / 100.0
    t = np.linspace(prog.edges_s[0], prog.edges_s[-1], max(n_eval, 2))
    sim = run_programme(hx, prog, t, scale, rtol=rtol, atol=atol, method=method)
    return pose_error(sim, prog)


def instability_rates(hx: Hexapod, p: np.ndarray, R: np.ndarray, eps: float = 1e-7
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (1/s) and pose parts of the eigenvectors of the forward dynamics
    linearised about static equilibrium at ``(p, R)`` with the actuator forces held at their
    equilibrium values (central differences on the 12-state ``[δp, δφ, v, ω]``).

    A compressed leg pushing with a constant force is a negative lateral stiffness
    (``Γ/ℓ``), so the force-controlled platform is an inverted pendulum: real eigenvalue
    pairs ``±λ``, and any force error grows like ``e^{λt}``.
    """
    forces = inverse_dynamics(hx, p, R, np.zeros(6), np.zeros(6))

    def f(x):
        Rx = Rotation.from_rotvec(x[3:6]).as_matrix() @ R
        acc = forward_acceleration(hx, p + x[:3], Rx, x[6:], forces)
        return np.concatenate([x[6:], acc])

    jac = np.zeros((12, 12))
    for k in range(12):
        dx = np.zeros(12)
        dx[k] = eps
        jac[:, k] = (f(dx) - f(-dx)) / (2 * eps)
    ev, vec = np.linalg.eig(jac)
    order = np.argsort(-ev.real)
    return ev[order], vec[:6, order]


# ---------------------------------------------------------------------------------- config
def programme_from_config(section: Mapping[str, Any]) -> Programme:
    """The seed's acceleration programme from the ``hexapod`` config (mm → m)."""
    pr = section["programme"]
    acc = np.asarray(pr["accel_mm_s2"], float) * 1e-3
    edges = np.asarray(pr["edges_s"], float)
    if acc.shape != (len(edges) - 1, 3):
        raise ValueError(f"hexapod.programme: {len(edges) - 1} segments need as many "
                         f"[x, y, z] rows in accel_mm_s2, got shape {acc.shape}")
    return Programme(edges_s=edges, accel_m_s2=acc,
                     start_m=np.asarray(section["start_mm"], float) * 1e-3)


def vertical_from_config(section: Mapping[str, Any]) -> Programme:
    """The seed's vertical move from the ``hexapod`` config (mm → m)."""
    v = section["vertical"]
    return vertical_programme(np.asarray(section["start_mm"], float) * 1e-3,
                              v["rise_mm"] * 1e-3, v["duration_s"])


def solver_options(section: Mapping[str, Any]) -> dict[str, Any]:
    """``rtol``, ``atol`` and ``method`` for :func:`run_programme` from the config."""
    s = section["solver"]
    return {"rtol": float(s["rtol"]), "atol": float(s["atol"]), "method": s["method"]}


# ---------------------------------------------------------------------------------- artefacts
AXES = ("x", "y", "z")
ANGLES = ("psi", "theta", "phi")


def _var(dims, data, units, long_name):
    return (dims, np.asarray(data), {"units": units, "long_name": long_name})


def _coords(t: np.ndarray, tname: str, tlong: str) -> dict:
    return {tname: (tname, t, {"units": "s", "long_name": tlong}),
            "axis": ("axis", list(AXES), {"units": "1", "long_name": "base axis"}),
            "angle": ("angle", list(ANGLES), {"units": "1", "long_name":
                      "Euler angle: psi about x, theta about y, phi about z (R = Rz Ry Rx)"}),
            "actuator": ("actuator", np.arange(1, 7), {"units": "1", "long_name": "actuator"})}


def dynamics_datasets(section: Mapping[str, Any]) -> tuple[Any, Any]:
    """The chapter's trajectory and forces datasets (SI inside, mm/deg/N outside).

    Trajectory: the seed's programme (commanded pose, open-loop replay until it leaves the
    command by ``replay_tolerance_mm``), the vertical move exact and with the force error,
    and the instability rates of the force-controlled platform at the start pose.
    Forces: actuator forces of the programme (inverse dynamics, seed Fig. 4) and of the
    vertical move (nominal and with the error).
    """
    import xarray as xr

    hx = hexapod_from_config(section)
    opts = solver_options(section)
    prog = programme_from_config(section)
    dt = section["programme"]["dt_s"]
    t = np.round(np.arange(prog.edges_s[0], prog.edges_s[-1] + dt / 2, dt), 12)
    law = programme_forces(hx, prog)
    cmd = np.array([prog.state(ti)[0] for ti in t])
    vel = np.array([prog.state(ti)[1] for ti in t])
    acc = np.array([prog.state(ti)[2] for ti in t])
    f_prog = np.array([law(ti) for ti in t])
    lengths = np.array([inverse_kinematics(hx, p, prog.rotation).length for p in cmd])
    tol_m = section["replay_tolerance_mm"] * 1e-3
    replay = run_programme(hx, prog, t, stop_error_m=tol_m, **opts)
    rep_pos = np.full_like(cmd, np.nan)
    rep_pos[:replay.t.size] = replay.position
    hold_s = t[-1] if replay.t_stop is None else replay.t_stop
    # the vertical move, exact and with the force error (seed Fig. 5)
    vcfg = section["vertical"]
    vprog = vertical_from_config(section)
    tv = np.round(np.linspace(0.0, vcfg["duration_s"],
                              int(round(vcfg["duration_s"] / vcfg["dt_s"])) + 1), 12)
    scale = np.ones(6)
    scale[vcfg["actuator"] - 1] += vcfg["error_pct"] / 100.0
    exact = run_programme(hx, vprog, tv, **opts)
    pert = run_programme(hx, vprog, tv, scale, **opts)
    v_cmd = np.array([vprog.state(ti)[0] for ti in tv])
    dp, drot = pose_error(pert, vprog)
    ev, vec = instability_rates(hx, prog.start_m, prog.rotation)
    k = np.flatnonzero(ev.real > 0)
    mode_names = [["vx", "vy", "vz", "wx", "wy", "wz"][int(np.argmax(np.abs(vec[:, j])))]
                  for j in k]

    traj = xr.Dataset(
        {
            "position_mm": _var(("time", "axis"), cmd * 1e3, "mm",
                                "commanded platform position (seed programme)"),
            "velocity_mm_s": _var(("time", "axis"), vel * 1e3, "mm/s", "commanded velocity"),
            "acceleration_mm_s2": _var(("time", "axis"), acc * 1e3, "mm/s2",
                                       "commanded acceleration (seed: gamma_x, gamma_y)"),
            "replay_position_mm": _var(("time", "axis"), rep_pos * 1e3, "mm",
                                       "forward dynamics under the inverse-dynamics forces "
                                       "(open loop; NaN after it leaves the tolerance)"),
            "replay_error_mm": _var("time", np.linalg.norm(rep_pos - cmd, axis=1) * 1e3, "mm",
                                    "replay position error"),
            "replay_hold_s": _var((), hold_s, "s",
                                  "time the open-loop replay stays within the tolerance"),
            "replay_tolerance_mm": _var((), section["replay_tolerance_mm"], "mm",
                                        "replay tolerance"),
            "vertical_exact_mm": _var(("time_vertical", "axis"), exact.position * 1e3, "mm",
                                      "vertical move, exact forces (forward dynamics)"),
            "vertical_command_mm": _var(("time_vertical", "axis"), v_cmd * 1e3, "mm",
                                        "vertical move, commanded"),
            "vertical_perturbed_mm": _var(("time_vertical", "axis"), pert.position * 1e3, "mm",
                                          "vertical move, one actuator with a force error"),
            "vertical_perturbed_euler_deg": _var(("time_vertical", "angle"),
                                                 np.rad2deg(pert.euler), "deg",
                                                 "Euler angles with the force error"),
            "vertical_final_drift_mm": _var("axis", dp * 1e3, "mm",
                                            "final position minus exact final position"),
            "vertical_final_rotvec_deg": _var("axis", np.rad2deg(drot), "deg",
                                              "final orientation error as a rotation vector"),
            "instability_rate_per_s": _var("mode", ev.real[k], "1/s",
                                           "growth rate of the open-loop force-controlled "
                                           "platform (linearised at the start pose)"),
        },
        coords={**_coords(t, "time", "time of the seed programme"),
                "time_vertical": ("time_vertical", tv, {"units": "s",
                                                        "long_name": "time of the vertical move"}),
                "mode": ("mode", np.arange(1, k.size + 1), {"units": "1",
                                                             "long_name": "unstable mode"}),
                "mode_dominant": ("mode", mode_names, {"units": "1", "long_name":
                                  "largest twist component of the mode"})},
        attrs={"vertical_actuator": int(vcfg["actuator"]),
               "vertical_error_pct": float(vcfg["error_pct"]),
               "vertical_duration_s": float(vcfg["duration_s"]),
               "solver": f"solve_ivp {opts['method']} rtol={opts['rtol']} atol={opts['atol']}",
               "replay_nfev": int(replay.nfev)},
    )
    forces = xr.Dataset(
        {
            "force_N": _var(("time", "actuator"), f_prog, "N",
                            "actuator force, inverse dynamics of the seed programme"),
            "leg_length_mm": _var(("time", "actuator"), lengths * 1e3, "mm", "leg length"),
            "vertical_force_N": _var(("time_vertical", "actuator"), exact.forces, "N",
                                     "actuator force of the vertical move (exact)"),
            "vertical_perturbed_force_N": _var(("time_vertical", "actuator"), pert.forces, "N",
                                               "actuator force with the force error"),
            "static_force_N": _var((), static_force_closed_form(hx, prog.start_m[2]), "N",
                                   "closed-form static force at the start pose"),
        },
        coords={k: v for k, v in _coords(t, "time", "time of the seed programme").items()
                if k in ("time", "actuator")} | {
            "time_vertical": ("time_vertical", tv, {"units": "s",
                                                    "long_name": "time of the vertical move"})},
    )
    return traj, forces


def sensitivity_shard(section: Mapping[str, Any], actuator: int, progress=None) -> Any:
    """Drift of the vertical move's final pose for one actuator over every configured force
    error (one Snakemake job): signed components, ``drift_mm`` and ``tilt_deg``.
    ``progress(fraction)`` is called after each error size."""
    import xarray as xr

    hx = hexapod_from_config(section)
    prog = vertical_from_config(section)
    opts = solver_options(section)
    errs = np.asarray(section["sensitivity"]["error_pct"], float)
    dps, drs = [], []
    for k, e in enumerate(errs):
        dp, dr = force_error_drift(hx, prog, actuator, float(e), **opts)
        dps.append(dp)
        drs.append(dr)
        if progress is not None:
            progress((k + 1) / len(errs))
    dp = np.array(dps)[None] * 1e3
    dr = np.rad2deg(np.array(drs))[None]
    dims = ("actuator", "force_error_pct", "axis")
    return xr.Dataset(
        {
            "drift_mm": _var(dims[:2], np.linalg.norm(dp, axis=-1), "mm",
                             "final position error of the vertical move"),
            "tilt_deg": _var(dims[:2], np.linalg.norm(dr, axis=-1), "deg",
                             "final orientation error (rotation angle)"),
            "drift_components_mm": _var(dims, dp, "mm", "final position error, components"),
            "rotvec_deg": _var(dims, dr, "deg", "final orientation error, rotation vector"),
        },
        coords={"actuator": ("actuator", [int(actuator)], {"units": "1",
                                                           "long_name": "actuator in error"}),
                "force_error_pct": ("force_error_pct", errs, {"units": "%", "long_name":
                                    "actuator force error"}),
                "axis": ("axis", list(AXES), {"units": "1", "long_name": "base axis"})},
        attrs={"duration_s": float(section["vertical"]["duration_s"])},
    )


def gather_sensitivity(shards: Sequence[Any]) -> Any:
    """Concatenate per-actuator shards into the ``actuator × force_error_pct`` map; adds the
    first-order slopes (mm and deg per % of force error, least squares through zero)."""
    import xarray as xr

    ds = xr.concat(list(shards), dim="actuator").sortby("actuator")
    e = ds["force_error_pct"]
    for name, unit, long in (("drift_components_mm", "mm/%", "position drift per % error"),
                             ("rotvec_deg", "deg/%", "rotation per % error")):
        slope = (ds[name] * e).sum("force_error_pct") / (e**2).sum()
        ds[name.replace("_mm", "").replace("_deg", "") + "_per_pct"] = slope.assign_attrs(
            units=unit, long_name=f"first-order {long}")
    ds.attrs = dict(shards[0].attrs)
    return ds


#: position tolerances [mm] for which :func:`force_accuracy_requirement` states the force
#: accuracy needed (the chapter's table; results/hexapod/force_accuracy.csv)
FORCE_ACCURACY_TOLERANCES_MM = (0.005, 0.01, 0.05, 0.1)


def force_accuracy_requirement(sensitivity: Any, actuator_force_N: float,
                               tolerances_mm: Sequence[float] = FORCE_ACCURACY_TOLERANCES_MM
                               ) -> pd.DataFrame:
    """Force accuracy an open-loop move needs to end within a position tolerance.

    To first order the vertical move's final drift is linear in an actuator's force error,
    ``d = s_i · e`` with ``s_i = |Σ_e d_i(e) e / Σ_e e²|`` mm per % (the slope
    ``drift_components_per_pct`` of :func:`gather_sensitivity`, least squares through zero).
    A tolerance ``δ`` on the final position therefore needs every actuator's force right to
    ``e_max = δ / max_i s_i`` %, i.e. ``e_max / 100 · Γ`` newton for an actuator force ``Γ``
    (seed 003, § sensitivity: "a small error in the force loop gives a large path error").

    Parameters
    ----------
    sensitivity
        The gathered map (``results/hexapod/sensitivity.nc``).
    actuator_force_N
        The actuator force of the move (``forces.nc::vertical_force_N`` at the start).
    tolerances_mm
        Position tolerances δ [mm].

    Returns
    -------
    DataFrame
        One row per tolerance: ``position_tolerance_mm``, ``force_accuracy_pct``,
        ``force_accuracy_mN``, ``worst_actuator``, ``drift_mm_per_pct`` (the worst slope),
        ``duration_s`` (of the move).
    """
    import pandas as pd

    tol = np.asarray(tolerances_mm, float)
    if tol.ndim != 1 or tol.size == 0 or not np.all(tol > 0):
        raise ValueError(f"tolerances_mm must be positive, got {tolerances_mm!r}")
    if not actuator_force_N > 0:
        raise ValueError(f"actuator_force_N must be positive, got {actuator_force_N!r}")
    slope = np.linalg.norm(np.asarray(sensitivity["drift_components_per_pct"].values), axis=-1)
    worst = int(np.argmax(slope))
    pct = tol / slope[worst]
    return pd.DataFrame({
        "position_tolerance_mm": tol,
        "force_accuracy_pct": pct,
        "force_accuracy_mN": pct / 100 * float(actuator_force_N) * 1e3,
        "worst_actuator": int(sensitivity["actuator"].values[worst]),
        "drift_mm_per_pct": float(slope[worst]),
        "duration_s": float(sensitivity.attrs.get("duration_s", np.nan)),
    })


def drift_antisymmetry(sensitivity: Any) -> tuple[float, float] | None:
    """How far the drift map is from first-order antisymmetry.

    For the smallest error ``e`` present with both signs, ``max_i |d_i(+e) + d_i(−e)| /
    |d_i(+e)|`` (zero for a map linear in the error). Returns ``(e, fraction)``, or None
    when no error is present with both signs.
    """
    e = np.asarray(sensitivity["force_error_pct"].values, float)
    both = e[(e > 0) & np.isin(-e, e)]
    if both.size == 0:
        return None
    ep = float(both.min())
    pair = sensitivity["drift_components_mm"]
    plus = pair.sel(force_error_pct=ep).values
    minus = pair.sel(force_error_pct=-ep).values
    frac = np.linalg.norm(plus + minus, axis=-1) / np.linalg.norm(plus, axis=-1)
    return ep, float(frac.max())
