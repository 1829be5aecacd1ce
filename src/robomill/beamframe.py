"""Beam-frame stiffness model of a robot arm and the vibration predictor [Cai 2015]
(pneumatic-wheel finishing with a MOTOMAN-HP20).

The arm is a chain of 3-D Euler–Bernoulli beam elements (shear deformation ignored, Cai 2015
eq. 3–7) along its link polyline; every node has 6 DOF (3 displacements, 3 rotations).
Node 1 (the base) is fixed, so for 7 elements / 8 nodes the global stiffness K is 42×42 and
δ = K⁻¹ F [Cai 2015, eqs. 8–9]. Only the tool node is loaded, by the wheel's normal force F_n
(from its compression h) and tangential force F_v = μ F_n (eqs. 10–12); δ_sum is the length
of the tool node's linear displacement (eq. 13), and the fitted vibration predictor is
σ(t) = 1.3·10⁴ (e^{−0.01 t} + 1) δ_sum(t) + 0.6 (eq. 17). SI units throughout.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from robomill.kinematics import SerialRobot
from robomill.settings import schema_defaults
from robomill.xrvars import attrs


@dataclass(frozen=True)
class Section:
    """Beam section and material: E, G [Pa]; A [m²]; I (both bending axes) and J [m⁴]."""

    E_Pa: float
    G_Pa: float
    A_m2: float
    I_m4: float
    J_m4: float

    @classmethod
    def tube(cls, D_mm: float, t_mm: float, E_Pa: float, G_Pa: float) -> Section:
        """Hollow circular section of outer diameter ``D_mm`` and wall ``t_mm`` (*assumed*
        link shape): A = π(D²−d²)/4, I = π(D⁴−d⁴)/64, J = 2I."""
        D, d = D_mm * 1e-3, (D_mm - 2 * t_mm) * 1e-3
        I = np.pi * (D**4 - d**4) / 64
        return cls(E_Pa, G_Pa, np.pi * (D**2 - d**2) / 4, I, 2 * I)


def element_stiffness_local(s: Section, L_m: float) -> np.ndarray:
    """12×12 stiffness of a 3-D beam element in its local frame ([Cai 2015, eqs. 3–7];
    Przemieniecki's matrix without shear). DOF order per node: u, v, w, θx, θy, θz."""
    EA, GJ = s.E_Pa * s.A_m2 / L_m, s.G_Pa * s.J_m4 / L_m
    EI = s.E_Pa * s.I_m4
    a, b, c, d = 12 * EI / L_m**3, 6 * EI / L_m**2, 4 * EI / L_m, 2 * EI / L_m
    k = np.zeros((12, 12))
    k[0, 0] = k[6, 6] = EA
    k[0, 6] = k[6, 0] = -EA
    k[3, 3] = k[9, 9] = GJ
    k[3, 9] = k[9, 3] = -GJ
    # bending in the local x–y plane (v, θz) and x–z plane (w, θy)
    for v, th, sgn in ((1, 5, 1.0), (2, 4, -1.0)):
        v2, th2 = v + 6, th + 6
        k[v, v] = k[v2, v2] = a
        k[v, v2] = k[v2, v] = -a
        k[v, th] = k[th, v] = k[v, th2] = k[th2, v] = sgn * b
        k[v2, th] = k[th, v2] = k[v2, th2] = k[th2, v2] = -sgn * b
        k[th, th] = k[th2, th2] = c
        k[th, th2] = k[th2, th] = d
    return k


def element_rotation(p1: np.ndarray, p2: np.ndarray) -> np.ndarray:
    """Direction cosines λ (3×3, rows = local x, y, z in global axes) of the element p1→p2.
    The section is symmetric (one I), so any local y ⟂ x will do."""
    x = (p2 - p1) / np.linalg.norm(p2 - p1)
    ref = np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    y = np.cross(ref, x)
    y /= np.linalg.norm(y)
    return np.stack([x, y, np.cross(x, y)])


def global_stiffness(nodes_m: np.ndarray, sections: Sequence[Section],
                     *, fix_first: bool = True) -> np.ndarray:
    """Assembled global stiffness of a chain of beam elements between consecutive nodes.

    Parameters
    ----------
    nodes_m
        Node positions ``(N, 3)`` [m]; element e joins nodes e and e+1.
    sections
        One per element (the last is repeated if fewer are given).
    fix_first
        Remove node 1's 6 DOF (fixed base): the result is ``6(N−1)`` square (42×42 for the
        seed's 8 nodes); otherwise ``6N`` (singular).
    """
    P = np.asarray(nodes_m, float)
    n = len(P)
    K = np.zeros((6 * n, 6 * n))
    for e in range(n - 1):
        s = sections[min(e, len(sections) - 1)]
        L = float(np.linalg.norm(P[e + 1] - P[e]))
        lam = element_rotation(P[e], P[e + 1])
        T = np.kron(np.eye(4), lam)
        kg = T.T @ element_stiffness_local(s, L) @ T
        sl = slice(6 * e, 6 * e + 12)
        K[sl, sl] += kg
    return K[6:, 6:] if fix_first else K


def tool_displacement(K: np.ndarray, force_N: np.ndarray) -> np.ndarray:
    """Displacement (6: linear [m], angular [rad]) of the last node under a force ``(3,)``
    there: δ(end−5:end) = K⁻¹(end−5:end, end−5:end−3) F [Cai 2015, eq. 9]."""
    C = np.linalg.inv(K)
    return C[-6:, -6:-3] @ np.asarray(force_N, float)


def tool_compliance_m_N(K: np.ndarray) -> np.ndarray:
    """3×3 translational compliance [m/N] of the last node (the tool)."""
    return np.linalg.inv(K)[-6:-3, -6:-3]


def link_polyline_mm(robot: SerialRobot, q_rad: np.ndarray, *, tol_mm: float = 1e-6
                     ) -> np.ndarray:
    """Beam nodes of a robot at posture ``q_rad``: the base, each link transform's two
    translations (d along z and a along x, in the convention's order), and the TCP;
    coincident points merged. For a MOTOMAN-HP20-like arm this gives the seed's 8 nodes."""
    F = robot.frames(np.asarray(q_rad, float))
    pts = [F[0, :3, 3]]
    for i in range(robot.n_joints):
        o = F[i, :3, 3]
        if robot.convention == "dh":  # Rz(θ) Tz(d) Tx(a) Rx(α): d along z_{i-1} first
            mid = o + robot.d_mm[i] * F[i, :3, 2]
        else:  # Rx(α) Tx(a) Rz(θ) Tz(d): a along x_{i-1} first
            mid = o + robot.a_mm[i] * F[i, :3, 0]
        pts += [mid, F[i + 1, :3, 3]]
    pts.append(robot.fk(np.asarray(q_rad, float))[:3, 3])
    out = [pts[0]]
    for p in pts[1:]:
        if np.linalg.norm(p - out[-1]) > tol_mm:
            out.append(p)
    return np.array(out)


def wheel_normal_force_N(h_mm: float | np.ndarray, pressure_Pa: float,
                         radius_mm: float) -> np.ndarray:
    """Normal force of the pneumatic wheel at compression h ([Cai 2015, eqs. 10–11]; the law is
    not printed, *assumed* here: internal pressure on the flattened contact disc,
    F_n = p π r², r² = 2 R h − h²)."""
    h = np.asarray(h_mm, float) * 1e-3
    R = radius_mm * 1e-3
    return pressure_Pa * np.pi * (2 * R * h - h**2)


def wheel_forces_N(F_n_N: float, mu: float, normal: np.ndarray,
                   wheel_axis: np.ndarray) -> np.ndarray:
    """Force on the tool node [N] [Cai 2015, eq. 12]: F_n along the workpiece's outward normal
    N plus F_v = μ F_n opposing the wheel's surface velocity at the contact, which is along
    −P × N for a wheel spinning about its axis P (contact point at −R N from the centre)."""
    N = np.asarray(normal, float) / np.linalg.norm(normal)
    v = -np.cross(np.asarray(wheel_axis, float), N)
    v /= np.linalg.norm(v)
    return F_n_N * N - mu * F_n_N * v


#: eq. 17's constants, as the schema states them (config ``stiffness.beamframe.sigma``)
SIGMA = schema_defaults("stiffness.beamframe.sigma")


def vibration_sigma(t_s: np.ndarray, delta_sum_m: np.ndarray, *, a: float = SIGMA["a"],
                    decay_per_s: float = SIGMA["decay_per_s"],
                    offset: float = SIGMA["offset"]) -> np.ndarray:
    """Vibration predictor of [Cai 2015, eq. 17]: σ(t) = a (e^{−0.01 t} + 1) δ_sum(t) + 0.6
    (δ_sum in m; σ in the unit of the seed's accelerometer standard deviation)."""
    t = np.asarray(t_s, float)
    return a * (np.exp(-decay_per_s * t) + 1.0) * np.asarray(delta_sum_m, float) + offset


def precession_tool_rotation(tilt_rad: float, phase_rad: np.ndarray) -> np.ndarray:
    """Tool orientations ``(m, 3, 3)`` of a precessing wheel over a horizontal surface
    [Cai 2015, Fig. 2]: the wheel axis P (tool z) tilted by θ from straight down, the tilt
    turning about the surface normal N = +Z by the precession phase ω₂t."""
    ph = np.atleast_1d(np.asarray(phase_rad, float))
    down = np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, -1.0]])
    ct, st = np.cos(tilt_rad), np.sin(tilt_rad)
    Ry = np.array([[ct, 0, st], [0, 1.0, 0], [-st, 0, ct]])
    out = np.empty((len(ph), 3, 3))
    for i, p in enumerate(ph):
        c, s = np.cos(p), np.sin(p)
        Rz = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
        out[i] = Rz @ Ry @ down
    return out


# ---- pipeline helpers (pure) -----------------------------------------------------------------

def sections_from_config(items, E_Pa: float, G_Pa: float) -> list[Section]:
    """Tube sections from ``[{D_mm, t_mm}]`` configuration items."""
    return [Section.tube(float(s["D_mm"]), float(s["t_mm"]), E_Pa, G_Pa) for s in items]


def cantilever_check(section: Section, length_m: float = 1.0, n_elements: int = 3,
                     force_N: float = 1000.0) -> tuple[float, float]:
    """Tip deflection of a straight cantilever split into ``n_elements`` beams, and the
    closed form F L³ / (3 E I)."""
    nodes = np.zeros((n_elements + 1, 3))
    nodes[:, 0] = np.linspace(0.0, length_m, n_elements + 1)
    K = global_stiffness(nodes, [section])
    d = tool_displacement(K, [0.0, 0.0, -force_N])
    return float(-d[2]), force_N * length_m**3 / (3 * section.E_Pa * section.I_m4)


def precession_dataset(robot: SerialRobot, sections: Sequence[Section], *, q_seed_deg,
                       wheel: dict, duration_s: float, dt_s: float, sigma: dict):
    """Cai 2015 reproduced: a precessing pneumatic wheel finishing a horizontal surface.

    At each time t the wheel axis is tilted by ``tilt_deg`` from the normal and turned by
    2π t / period about it; the arm pose comes from IK, its beam frame from
    :func:`link_polyline_mm`, the load from the wheel (eqs. 10–12), the tool displacement
    from δ = K⁻¹F (eq. 9), δ_sum (eq. 13) and σ(t) (eq. 17).
    """
    import xarray as xr

    from robomill.stiffness.poses import solve_poses

    t = np.arange(0.0, duration_s + 1e-9, dt_s)
    phase = 2 * np.pi * t / float(wheel["precession_period_s"])
    R = precession_tool_rotation(np.deg2rad(wheel["tilt_deg"]), phase)
    centre = np.broadcast_to(np.asarray(wheel["centre_mm"], float), (len(t), 3))
    q, ok = solve_poses(robot, centre, R, np.deg2rad(q_seed_deg))
    if not ok.all():
        raise ValueError(f"wheel pose not reachable by {robot.name} at t = "
                         f"{t[~ok][0]:.3g} s: move wheel.centre_mm or change the tilt")
    Fn = float(wheel_normal_force_N(wheel["compression_mm"], wheel["pressure_Pa"],
                                    wheel["radius_mm"]))
    normal = np.array([0.0, 0.0, 1.0])
    forces = np.array([wheel_forces_N(Fn, float(wheel["mu"]), normal, R[i, :, 2])
                       for i in range(len(t))])
    delta = np.empty((len(t), 6))
    K0 = nodes0 = None
    for i in range(len(t)):
        nodes = link_polyline_mm(robot, q[i]) * 1e-3
        K = global_stiffness(nodes, sections)
        if i == 0:
            K0, nodes0 = K, nodes
        delta[i] = tool_displacement(K, forces[i])
    dsum = np.linalg.norm(delta[:, :3], axis=1)
    sig = vibration_sigma(t, dsum, a=float(sigma["a"]), decay_per_s=float(sigma["decay_per_s"]),
                          offset=float(sigma["offset"]))
    tip, closed = cantilever_check(sections[0])
    L = np.linalg.norm(np.diff(nodes0, axis=0), axis=1)
    secs = [sections[min(e, len(sections) - 1)] for e in range(len(L))]
    dof = np.arange(1, K0.shape[0] + 1)
    return xr.Dataset(
        {"q_deg": (("time", "joint"), np.rad2deg(q), attrs("deg", "joint angles")),
         "force_N": (("time", "axis"), forces, attrs("N", "wheel force on the tool node")),
         "delta_m": (("time", "component"), delta,
                     attrs("m or rad", "tool-node displacement (3 linear, 3 angular)")),
         "delta_sum_um": ("time", dsum * 1e6,
                          attrs("um", "delta_sum: linear displacement of the tool node")),
         "sigma_pred": ("time", sig, attrs("1", "predicted vibration standard deviation "
                                                 "([Cai 2015, eq. 17], accelerometer units)")),
         "node_m": (("node", "axis"), nodes0, attrs("m", "beam node positions at t = 0")),
         "element_length_m": ("element", L, attrs("m", "beam element length")),
         "element_A_m2": ("element", [s.A_m2 for s in secs], attrs("m2", "section area")),
         "element_I_m4": ("element", [s.I_m4 for s in secs],
                          attrs("m4", "section second moment of area")),
         "element_J_m4": ("element", [s.J_m4 for s in secs],
                          attrs("m4", "section torsion constant")),
         "K0": (("dof", "dof2"), K0, attrs("SI", "global stiffness at t = 0, node 1 fixed")),
         "F_n_N": ((), Fn, attrs("N", "normal force from the wheel compression")),
         "F_v_N": ((), Fn * float(wheel["mu"]), attrs("N", "tangential force mu F_n")),
         "cantilever_tip_m": ((), tip, attrs("m", "beam-frame tip deflection of a "
                                                    "cantilever (check)")),
         "cantilever_closed_form_m": ((), closed, attrs("m", "closed form F L^3 / (3 E I)"))},
        coords={"time": ("time", t, attrs("s", "time")),
                "joint": ("joint", np.arange(1, robot.n_joints + 1), attrs("1", "joint")),
                "axis": ("axis", ["X", "Y", "Z"], attrs("1", "base axis")),
                "component": ("component", ["dx", "dy", "dz", "rx", "ry", "rz"],
                              attrs("1", "displacement component")),
                "node": ("node", np.arange(1, len(nodes0) + 1), attrs("1", "node number")),
                "element": ("element", np.arange(1, len(L) + 1), attrs("1", "element")),
                "dof": ("dof", dof, attrs("1", "global DOF (node 2 onwards)")),
                "dof2": ("dof2", dof, attrs("1", "global DOF (node 2 onwards)"))},
        attrs={"robot": robot.name})


def slot_stiffness_table(robot: SerialRobot, compliance: np.ndarray, sections: Sequence[Section],
                         cuts, q_mid_rad: np.ndarray):
    """Stiffness of the study's robot along each slot's feed, in-plane normal and axial
    directions, by the joint model (C = J diag(c) Jᵀ), the beam-frame model (links only)
    and both in series (compliances added).

    Parameters
    ----------
    cuts
        :class:`robomill.experiment.Cut` objects.
    q_mid_rad
        ``(len(cuts), n)`` posture at each cut's middle.
    """
    import pandas as pd

    from robomill.experiment import cut_axes
    from robomill.stiffness.model import (
        directional_stiffness_N_m,
        jacobian_m,
        translational_compliance_m_N,
    )

    rows = []
    for cut, q in zip(cuts, q_mid_rad, strict=True):
        U = cut_axes(cut)
        Cj = translational_compliance_m_N(jacobian_m(robot, q), compliance)
        K = global_stiffness(link_polyline_mm(robot, q) * 1e-3, sections)
        Cb = tool_compliance_m_N(K)
        for model, C in (("joint", Cj), ("beam", Cb), ("combined", Cj + Cb)):
            k = directional_stiffness_N_m(C, U)
            rows.append({"cut": cut.id, "set": cut.set, "segment": cut.segment,
                         "direction": cut.direction, "feed_mm_s": cut.feed_mm_s,
                         "model": model, "k_feed_N_m": k[0], "k_normal_N_m": k[1],
                         "k_axial_N_m": k[2]})
    return pd.DataFrame(rows)
