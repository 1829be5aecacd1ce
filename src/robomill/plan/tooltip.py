"""The tool tip's structure at a pose: the impact test's modes moved with the joints, and the
static compliance the plan predicts deflection with.

**Modes at a pose.** The impact test measures the modes at the tool tip at its own pose q_ref.
Elsewhere the arm is stiffer or softer as its joints see the tool-tip load through other lever
arms; each robot mode (below ``robot_mode_max_hz``) keeps its shape φ_r and has its
stiffness scaled by the joint model's stiffness along its shape,

.. math:: k_r(q) = k_r \\frac{k_φ(q)}{k_φ(q_{ref})}, \\qquad k_φ = 1/(φ^T C_J(q) φ),
          \\qquad C_J(q) = J(q) K_θ^{-1} J(q)^T

(the joint-stiffness model of the load tests; Dumas et al. 2011, Robotics and
Computer-Integrated Manufacturing 27(5), 881–888). The modal mass moves too where the cell
file documents the robot's masses (``mass_model``): by the ratio of the kinetic energies of
the joint motion that a unit tool-tip motion along φ_r asks of the joints (Rayleigh's quotient
of the joints' eigenproblem [Géradin & Rixen 2015], :func:`mass_ratios`), so that

.. math:: f_r(q) = f_r \\sqrt{\\frac{k_r(q)/k_r}{m_r(q)/m_r}};

without documented masses it is held (f_r ∝ √k_r). Holding it is not neutral: on the virtual
cell's arm, whose mass at the tool tip moves with the pose, the held mass put the first mode
at 14–19 Hz where the arm has 20–23 Hz at the same cuts, and the critical depth 1.2–1.7 times
the arm's own (``benchmarks/modes_at_cuts.py``). The shapes are held: a real arm's may turn
and mix (the virtual cell's do under ``synth.process.robot_modes: eigen``: the eigenproblem of
its joints and mass matrix at each pose), so far from q_ref this law is one source of a missed
prediction. Modes above the robot's band (spindle, tool) are the same at every pose. q_ref is
where the impact files say the test was made (their ``tcp_mm``).

**Static compliance.** The impact test sees the whole structure at the tool tip (joints, links,
flange, spindle, tool); its frequency response at ω → 0 is the modal compliance

.. math:: C(q) = \\sum_r \\frac{φ_r φ_r^T}{k_r(q)}

(the receptance's modal sum Σ_r φ_r φ_rᵀ / (k_r (1 − ω²/ω_r² + 2iζ_r ω/ω_r)) at ω = 0;
Ewins 2000, *Modal Testing: Theory, Practice and Application*; the residual flexibility of
modes above the test's band left out). The plan predicts the static
deflection δ = C(q) F̄ with it, the same structure its stability prediction uses. The joint
model alone (C_J: the load tests measure the joints only) is the fallback where the study has
no impact test; with modes and no load tests, C(q_ref) holds at every pose. Why not C_J where
both were measured: the joints are one part of the structure in series with the rest, so the
joint model alone leaves out the compliance of the links, flange, spindle and tool; the plan's
check (``check.csv``: deflection from the tracker's loaded minus air passes) states how far
each prediction lies from what was measured.

Géradin, M.; Rixen, D. J. *Mechanical Vibrations: Theory and Application to Structural
Dynamics*, 3rd ed. Wiley, 2015.
"""

from __future__ import annotations

import numpy as np

from robomill.plan.measured import Measured, compliance_bounds
from robomill.plan.poses import compliance_grid, directional_ratio

ENDS = ("nominal", "low", "high")


def modes_arrays(modes, end: str = ""):
    """Frequencies, damping ratios, stiffnesses and unit shapes of the modes with a positive
    stiffness; ``end`` ``"_low"``/``"_high"`` takes that end of the interval columns of
    ``modes.csv`` (the value where a column is missing or NaN). A shape component left
    empty (NaN: an axis the impact test did not measure) counts as 0: the shapes restricted
    to the measured axes, no identified mode along the other
    (:mod:`robomill.plan.extrapolation` flags what depends on it)."""
    ok = modes["k_modal_N_m"].to_numpy(float) > 0
    m = modes[ok]
    shapes = np.nan_to_num(m[["shape_x", "shape_y", "shape_z"]].to_numpy(float))

    def col(name):
        v = m[name].to_numpy(float)
        if end and f"{name}{end}" in m:
            e = m[f"{name}{end}"].to_numpy(float)
            v = np.where(np.isfinite(e) & (e > 0), e, v)
        return v
    return col("f_n_hz"), col("zeta"), col("k_modal_N_m"), shapes


def mode_scalings(measured: Measured, cell, q_rad: np.ndarray, robot_mode: np.ndarray,
                  shapes: np.ndarray, *, corners: bool = True) -> dict[str, np.ndarray]:
    """k_r(q)/k_r ``(B, M)`` at postures ``q_rad`` ``(B, n)`` for each end of the joint
    stiffness (``nominal``, and ``low``/``high`` with ``corners``), and ``mass``: the modal
    mass ratio m_r(q)/m_r (:func:`mass_ratios`, at the nominal joint stiffness) where the cell
    file documents the robot's masses; 1 for the modes above the robot's band and where the
    study has no load tests or the test pose has no solution."""
    B = len(q_rad)
    scalings = {"nominal": np.ones((B, len(shapes)))}
    if not measured.has("joints"):
        return scalings
    from robomill.stiffness import solve_poses

    cset = compliance_bounds(measured.joints)
    q_ref, ok = solve_poses(cell.robot, cell.reference_point_mm[None], cell.R0, cell.q_seed_rad)
    for key in (ENDS if corners else ("nominal",)):
        C = compliance_grid(cell.robot, q_rad, cset[key])
        C_ref = compliance_grid(cell.robot, q_ref[0], cset[key])
        ratio = directional_ratio(C, C_ref, shapes) if ok[0] else np.ones((B, len(shapes)))
        scalings[key] = np.where(robot_mode, ratio, 1.0)
    rigid = getattr(cell, "rigid_body", None)
    if rigid is not None and ok[0]:
        ratio = mass_ratios(cell.robot, rigid, cset["nominal"], np.asarray(q_rad, float),
                            q_ref[0], shapes)
        scalings["mass"] = np.where(robot_mode, ratio, 1.0)
    return scalings


def mass_ratios(robot, rigid_body, compliance: np.ndarray, q_rad: np.ndarray,
                q_ref_rad: np.ndarray, shapes: np.ndarray) -> np.ndarray:
    """Each robot mode's modal mass at postures ``q_rad`` ``(B, n)`` relative to the impact
    test's pose, μ_r(q)/μ_r(q_ref) ``(B, M)`` (module docstring): the kinetic energy of the
    joint motion that a unit tool-tip motion along the mode's shape φ_r asks of the elastic
    joints (the static deflection under a load along φ_r, scaled),

    .. math:: ψ_r(q) = \\frac{C_θ J_v(q)^T φ_r}{φ_r^T C_J(q) φ_r}, \\qquad
              μ_r(q) = ψ_r^T M(q)\\, ψ_r

    (C_θ the joint compliances ``compliance`` [rad/(N·m)], M(q) the documented masses' mass
    matrix): Rayleigh's quotient of the joints' eigenproblem on that motion
    (:func:`robomill.inertia.rayleigh_stiffness_mass`, the routine the virtual cell's planted
    law uses with its own joints and masses). 1 where the motion moves no mass at either
    pose."""
    from robomill.inertia import rayleigh_stiffness_mass

    def mu(q):
        return np.array([rayleigh_stiffness_mass(robot, compliance, rigid_body, q, phi)[1]
                         for phi in np.asarray(shapes, float)])

    mu_ref = mu(np.asarray(q_ref_rad, float))
    q = np.asarray(q_rad, float).reshape(-1, len(np.asarray(compliance)))
    out = np.ones((len(q), len(mu_ref)))
    for b, qb in enumerate(q):
        with np.errstate(divide="ignore", invalid="ignore"):
            r = mu(qb) / mu_ref
        out[b] = np.where(np.isfinite(r) & (r > 0), r, 1.0)
    return out


def static_compliance_m_N(measured: Measured, cell, q_rad: np.ndarray, robot_mode_max_hz: float,
                          *, corners: bool = True) -> dict[str, np.ndarray] | None:
    """Static tool-tip compliance ``(B, 3, 3)`` [m/N] at postures ``q_rad`` ``(B, n)``: the
    modal compliance at the pose (module docstring) for every end of the modes' stiffness
    (``modes.csv`` ``k_modal_N_m_low/high``) and of the joint stiffness, keyed
    ``"<modes end>/<joints end>"`` (``"nominal/nominal"`` the nominal); the joint model's
    ``C_J`` keyed by its ends where the study has no impact test; None with neither."""
    if measured.has("modes"):
        fn, _, _, shapes = modes_arrays(measured.modes)
        if fn.size:
            scal = mode_scalings(measured, cell, q_rad, fn < robot_mode_max_hz, shapes,
                                 corners=corners)
            out = {}
            for mend in (ENDS if corners else ("nominal",)):
                k = modes_arrays(measured.modes, "" if mend == "nominal" else f"_{mend}")[2]
                for jend, s in ((k, v) for k, v in scal.items() if k in ENDS):
                    out[f"{mend}/{jend}"] = np.einsum("mi,mj,bm->bij", shapes, shapes,
                                                      1.0 / (k[None] * s))
            return out
    if measured.has("joints"):
        cset = compliance_bounds(measured.joints)
        return {f"joints/{key}": compliance_grid(cell.robot, q_rad, cset[key])
                for key in (ENDS if corners else ("nominal",))}
    return None


def nominal_key(compliance: dict[str, np.ndarray]) -> str:
    """The key of the nominal compliance of :func:`static_compliance_m_N`'s mapping."""
    return "nominal/nominal" if "nominal/nominal" in compliance else "joints/nominal"
