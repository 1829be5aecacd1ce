"""The study's robot in the frame of each slot (the analysis of [Pulatbek 2024, §3.3]; the
open question [Shagniev 2019] leaves): its identified tool-tip modes in that frame, the
mode-coupling check, and chatter-free parameter recommendations.

Slot frames: the feed direction f is the cut's direction in the base XY plane (a unit vector
from the study: ``px`` +X, ``py`` +Y, ``my`` −Y in the thesis, any angle in a free design)
and the normal direction is f turned +90° about the tool axis, n = (−f_Y, f_X). A mode with shape
(φ_X, φ_Y, φ_Z) has the shape (φ·f, φ·n, φ_Z) in that frame: the in-plane part carries the
chip, and φ_Z takes the axial force K_ac a h that the chip drives (the axial row of the
directional matrix, :mod:`robomill.chatter.model`). Reversing the feed reverses both in-plane
axes, so the linear model gives +Y and −Y the same lobes (only a pose change, not modelled
here, could tell them apart).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from robomill.chatter.coupling import coupling_depth
from robomill.chatter.model import (
    CuttingModel,
    LinearTool,
    ModeXY,
    conform_rows,
    tool_from_modes,
)
from robomill.settings import schema_default


def modes_in_slot_frame(modes: pd.DataFrame, feed_xy: tuple[float, float]) -> list[ModeXY]:
    """Modes of ``results/modal/modes.csv`` (``f_n_hz, zeta, k_modal_N_m, shape_x, shape_y``
    and, where the test measured it, ``shape_z``) in the (feed, normal, axis) frame of a cut
    whose unit feed direction in the base XY plane is ``feed_xy``
    (:attr:`robomill.study.StudyCut.feed_xy`); without a ``shape_z`` column, in-plane shapes.
    Modes with a non-positive modal stiffness (flagged non-physical by the modal analysis: a
    negative modal constant) are left out: a negative spring makes no oscillator of the tool. A
    shape component the test did not measure (NaN: e.g. responses along X only) counts as 0 (no
    measured flexibility along it).

    Raises
    ------
    ValueError
        When no mode has a positive modal stiffness.
    """
    f = np.asarray(feed_xy, float)[:2]
    n = np.array([-f[1], f[0]])
    out = []
    ok = np.asarray(modes["k_modal_N_m"], float) > 0
    if not ok.any():
        raise ValueError("no mode of the impact test has a positive modal stiffness "
                         "(every mode flagged non-physical in modes.csv): no tool model")
    for _, r in modes[ok].iterrows():
        phi = np.nan_to_num(np.array([float(r["shape_x"]), float(r["shape_y"])]))
        shape = (float(phi @ f), float(phi @ n))
        if "shape_z" in modes:
            shape += (float(np.nan_to_num(float(r["shape_z"]))),)
        out.append(ModeXY(float(r["f_n_hz"]), float(r["zeta"]), float(r["k_modal_N_m"]),
                          shape))
    return out


def cutting_from_coefficients(coeffs: pd.DataFrame, teeth: int) -> CuttingModel:
    """Slotting model from ``results/forces/cutting_coefficients.csv`` (Ktc, Krc, Kac in
    N/mm²): K_t = Ktc·10⁶ N/m², K_r = Krc/Ktc, K_a = Kac/Ktc where Kac is identified (else the
    planar model), full immersion (thesis: slotting, entry 0, exit π).
    A table whose Ktc or Krc is not finite (not identified: one feed per tooth, fewer than
    three cuts) raises ``ValueError`` with the reason (the workflow leaves chapter 4 out
    before, :func:`robomill.forces.coefficients.design_not_identified`)."""
    v = coeffs.set_index("name")["value"].astype(float)
    if not (np.isfinite(v.get("Ktc", np.nan)) and np.isfinite(v.get("Krc", np.nan))):
        why = coeffs.get("not_identified_reason", pd.Series(["no finite Ktc, Krc"])).iloc[0]
        raise ValueError(f"results/forces/cutting_coefficients.csv: the cutting coefficients "
                         f"are not identified ({why}): the stability lobes need Ktc and Krc")
    kac = float(v.get("Kac", np.nan))
    return CuttingModel(int(teeth), v["Ktc"] * 1e6, v["Krc"] / v["Ktc"], 0.0, float(np.pi),
                        Ka=kac / v["Ktc"] if np.isfinite(kac) else None)


def _max_real(tool: LinearTool, cut: CuttingModel, a: np.ndarray) -> tuple[np.ndarray, list]:
    W = conform_rows(cut.mean_matrix(), tool.n_inputs)
    A = tool.A[None] + np.asarray(a)[:, None, None] * (tool.B @ W @ tool.C)[None]
    lam, V = np.linalg.eig(A)
    i = np.argmax(lam.real, axis=-1)
    return np.take_along_axis(lam.real, i[:, None], -1)[:, 0], [
        (lam[k, i[k]], V[k, :, i[k]]) for k in range(len(a))]


def mode_coupling(modes: list[ModeXY], cut: CuttingModel, *, depth_max_m: float,
                  rtol: float = schema_default("chatter.seed", "rtol")) -> dict:
    """Mode-coupling check: the 2-D model without delay, ṡ = (A + a B W̄ C) s (the oriented
    cutting stiffness a W̄ acting on the current displacement; Tlusty's mode coupling, Pan et
    al. 2006 for robots). The non-symmetric stiffness can merge two modes into a flutter pair
    with a growing oscillation; the smallest such depth a_mc is the one routine's
    (:func:`robomill.chatter.coupling.coupling_depth`, scan + bisection to ``rtol``), and
    the coupled pair is the two modes carrying most of the unstable eigenvector's energy
    (k_r |q_r|²) just above it.

    Returns
    -------
    dict: a_mc_m (nan if stable up to ``depth_max_m``), frequency_hz, pair (indices), pair
    frequencies, participation (per mode).
    """
    tool = tool_from_modes(modes)
    a, hi = coupling_depth([[m.f_hz for m in modes]], [m.zeta for m in modes],
                           [[m.k_N_m for m in modes]], [[m.shape for m in modes]], cut,
                           depth_max_m=depth_max_m, n_scan=60, rtol=rtol, upper=True)
    k = np.array([m.k_N_m for m in modes])
    a_mc = float(a[0]) if np.isfinite(a[0]) else float("nan")
    probe = float(hi[0]) if np.isfinite(hi[0]) else depth_max_m
    _, eig = _max_real(tool, cut, np.array([probe]))
    lam, v = eig[0]
    q = v[0::2]
    energy = k * np.abs(q) ** 2
    part = energy / energy.sum()
    pair = np.argsort(part)[::-1][:2]
    return {"a_mc_m": a_mc, "frequency_hz": abs(lam.imag) / (2 * np.pi),
            "pair": [int(p) for p in pair],
            "pair_hz": [modes[p].f_hz for p in pair], "participation": part}


def recommend(a_crit_m: np.ndarray, spindle_rpm: np.ndarray, chatter_hz: np.ndarray,
              direction: str, *, study_points: list[tuple[float, float]],
              safety_fraction: float, solver: str, a_error_m: np.ndarray | None = None
              ) -> list[dict]:
    """Rows of ``recommendations.csv`` for one slot direction: the study's own (speed [rpm],
    depth [m]) pairs ``study_points`` with their margin, each at the speed of the grid
    nearest the cut's (rows of kind ``thesis``), and the recommended chatter-free point: the
    speed of the grid with the largest pessimistic critical depth a_crit − error, and a depth
    ``safety_fraction`` below that pessimistic depth, (1 − safety_fraction)(a_crit − error).
    The stability margin is a_crit/a − 1 (> 0 stable; 0.25 = 25 % deeper would still be
    stable); ``a_error_m`` is the estimated error of each critical depth (None: taken as exact
    and written as NaN, as for the zero-order method, whose approximation error is a model
    error, not estimated)."""
    rows = []
    a = np.where(np.isfinite(a_crit_m), a_crit_m, np.inf)
    err = (np.zeros_like(a) if a_error_m is None
           else np.where(np.isfinite(a_error_m), a_error_m, 0.0))
    err_mm = err * 1e3 if a_error_m is not None else np.full_like(a, np.nan)
    i_first = int(np.argmin(np.abs(spindle_rpm - study_points[0][0])))
    for rpm_cut, d in study_points:
        i_th = int(np.argmin(np.abs(spindle_rpm - rpm_cut)))
        rows.append({"direction": direction, "kind": "thesis", "solver": solver,
                     "spindle_rpm": float(spindle_rpm[i_th]), "axial_depth_mm": d * 1e3,
                     "a_crit_mm": a[i_th] * 1e3, "a_crit_error_mm": err_mm[i_th],
                     "stability_margin": a[i_th] / d - 1,
                     "chatter_hz": float(chatter_hz[i_th]),
                     "chatter_free": bool(a[i_th] - err[i_th] > d)})
    fin = np.isfinite(a_crit_m)
    i = int(np.argmax(np.where(fin, a_crit_m - err, -1))) if fin.any() else i_first
    a_rec = ((a[i] - err[i]) * (1 - safety_fraction) if np.isfinite(a[i])
             else max(d for _, d in study_points))
    rows.append({"direction": direction, "kind": "recommended", "solver": solver,
                 "spindle_rpm": float(spindle_rpm[i]), "axial_depth_mm": a_rec * 1e3,
                 "a_crit_mm": a[i] * 1e3, "a_crit_error_mm": err_mm[i],
                 "stability_margin": a[i] / a_rec - 1,
                 "chatter_hz": float(chatter_hz[i]), "chatter_free": bool(a[i] - err[i] > a_rec)})
    return rows
