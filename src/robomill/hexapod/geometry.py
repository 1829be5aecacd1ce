"""Geometry and inverse kinematics of the Stewart–Gough hexapod [Rybak n.d.].

The machine: six UPS legs (universal joint on the base, prismatic actuator, spherical joint on
the platform). Base joints ``B_i`` lie on a circle in the base plane, platform joints ``P_i`` on
a circle in the platform plane (:func:`joint_circle`); each leg is two axisymmetric bodies, a
cylinder hinged at ``B_i`` and a piston ending at ``P_i`` (:class:`Leg`), and the actuator
force ``Γ_i`` acts between them.

Inverse kinematics (:func:`inverse_kinematics`) gives per leg ``a_i = R p_i``, the tip, length
``ℓ_i`` and unit vector ``u_i``; the kinematic Jacobian ``J_r`` (:func:`jacobian`) has row *i*
``[u_iᵀ, (a_i × u_i)ᵀ]`` (``ℓ̇ = J_r V_p``) and the tip velocity of leg *i* is
``v_i = J_vi V_p`` with ``J_vi = [E_3, −â_i]`` (seed eq. 4, :func:`tip_jacobian`).

Units: SI throughout (m, kg, s, N, rad).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial.transform import Rotation

G0_M_S2 = 9.80665
"""Standard gravity (m/s²)."""


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


def vdot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a · b`` over the last axis (broadcasting)."""
    return np.einsum("...k,...k->...", a, b)


def vcross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
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


def euler_to_matrix(euler_rad: Sequence[float]) -> np.ndarray:
    """Rotation ``R = Rz(φ) Ry(θ) Rx(ψ)`` from Euler angles ``(ψ, θ, φ)`` (rad)."""
    return Rotation.from_euler("xyz", euler_rad).as_matrix()


def matrix_to_euler(R: np.ndarray) -> np.ndarray:
    """Euler angles ``(ψ, θ, φ)`` (rad) of ``R = Rz(φ) Ry(θ) Rx(ψ)``."""
    return Rotation.from_matrix(R).as_euler("xyz")


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
    return np.hstack([legs.u, vcross(legs.a, legs.u)])


def tip_jacobian(a_i: np.ndarray) -> np.ndarray:
    """``J_vi = [E_3, −â_i]`` (seed eq. 4): tip velocity of leg *i* from the platform twist."""
    return np.hstack([np.eye(3), -skew(a_i)])
