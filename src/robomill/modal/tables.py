"""The mode table (frequency, damping, tool-tip shape, modal mass and stiffness, sanity
flags) and the long table of the complex mode shapes."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from robomill.modal.layout import TOOLTIP, _is_tooltip, point_label
from robomill.modal.lscf import pole_f_zeta
from robomill.modal.shapes import ModeShapes, mode_shapes
from robomill.settings import schema_default

MODE_COLUMNS = ["mode", "f_n_hz", "zeta", "k_modal_N_m", "m_modal_kg", "shape_x", "shape_y",
                "shape_z", "zeta_windowed", "rank1", "n_stable", "driving_point", "coherence",
                "physical", "flags"]
"""Columns of the mode table (``results/modal/modes.csv``)."""


def modes_table(poles: np.ndarray, residues: np.ndarray, *,
                poles_measured: np.ndarray | None = None,
                n_stable: Sequence[int] | None = None,
                outputs: Sequence[tuple[int, int]] = TOOLTIP,
                inputs: Sequence[tuple[int, int]] = TOOLTIP,
                coherence: Sequence[float] | None = None,
                coherence_min: float = schema_default("modal", "coherence_min")
                ) -> tuple[pd.DataFrame, ModeShapes]:
    """Modal parameters from (window-corrected) poles and residues, and the mode shapes.

    The 3×3 tool-tip matrix (outputs = inputs = node 1 +X, +Y, +Z): ``R = 2jω_d A_r`` ≈
    ``φφᵀ/m`` (real, symmetric, rank one for a proportionally damped mode); its largest
    eigenpair ``(λ, v)`` of the symmetric real part gives the unit shape ``φ = v`` (largest
    component positive), ``m = 1/λ`` and ``k = m ω_n²``; ``rank1`` = λ / Σ|eigenvalues|.
    Any other layout: :func:`mode_shapes` (``rank1`` NaN); ``m`` and ``k`` only with a
    driving point.

    Sanity flags (column ``flags``, ``physical`` False when any): a negative modal mass or
    stiffness (the driving-point residue has the wrong sign: a sign or direction mix-up, or a
    computational pole); no driving point (no modal mass or stiffness); the mean coherence of
    the measured FRFs at the natural frequency below ``coherence_min``.

    Returns
    -------
    pandas.DataFrame
        :data:`MODE_COLUMNS`; ``shape_x, shape_y, shape_z`` are the real unit shape at node 1
        where those points were measured (NaN otherwise).
    ModeShapes
        The complex shapes over all measured points.
    """
    f, z = pole_f_zeta(poles)
    tooltip = _is_tooltip(outputs, inputs)
    general = mode_shapes(poles, residues, outputs, inputs)
    shapes = general.shapes.copy()
    rows = []
    for r, p in enumerate(np.asarray(poles, complex)):
        wn = 2 * np.pi * f[r]
        flags = []
        if tooltip:
            R = 2j * p.imag * residues[:, :, r]
            S = np.real(R + R.T) / 2
            lam, vec = np.linalg.eigh(S)
            i = int(np.argmax(np.abs(lam)))
            v = vec[:, i] * np.sign(vec[np.argmax(np.abs(vec[:, i])), i])
            m = 1.0 / lam[i]
            rank1 = float(np.abs(lam[i]) / np.sum(np.abs(lam)))
            comp = {d: v[d - 1] for d in (1, 2, 3)}
            shapes[r] = v
            dp = "X, Y, Z"
        else:
            m = general.m_modal_kg[r]
            rank1 = np.nan
            comp = {abs(d): (np.sign(d) * shapes[r, k]).real
                    for k, (n, d) in enumerate(general.points) if n == 1}
            dp = general.driving_point
            if not dp:
                flags.append("no driving point: shape unscaled, no modal mass or stiffness")
        if np.isfinite(m) and m <= 0:
            flags.append(f"negative modal mass {m:.3g} kg and stiffness {m * wn**2:.3g} N/m "
                         "(non-physical: sign or direction mix-up, or a computational pole)")
        coh = float(coherence[r]) if coherence is not None else np.nan
        if np.isfinite(coh) and coh < coherence_min:
            flags.append(f"coherence {coh:.2f} at {f[r]:.4g} Hz below {coherence_min:g}")
        row = {"mode": r + 1, "f_n_hz": f[r], "zeta": z[r], "k_modal_N_m": m * wn**2,
               "m_modal_kg": m, "shape_x": comp.get(1, np.nan),
               "shape_y": comp.get(2, np.nan), "shape_z": comp.get(3, np.nan)}
        row["zeta_windowed"] = (pole_f_zeta(poles_measured)[1][r]
                                if poles_measured is not None else z[r])
        row["rank1"] = rank1
        row["n_stable"] = int(n_stable[r]) if n_stable is not None else 0
        row["driving_point"] = dp
        row["coherence"] = coh
        row["physical"] = not any(fl.startswith("negative") for fl in flags)
        row["flags"] = "; ".join(flags)
        rows.append(row)
    pts = list(TOOLTIP) if tooltip else general.points
    ms = ModeShapes(pts, shapes, np.array([row["m_modal_kg"] for row in rows], float)
                    if rows else np.array([]), "X, Y, Z" if tooltip else general.driving_point)
    return pd.DataFrame(rows, columns=MODE_COLUMNS), ms


def shapes_table(shapes: ModeShapes) -> pd.DataFrame:
    """Long table of the complex mode shapes: ``mode, point, node, direction, shape_real,
    shape_imag, shape_abs, shape_phase_deg`` (``results/modal/mode_shapes.csv``)."""
    rows = []
    for r in range(shapes.shapes.shape[0]):
        for k, (n, d) in enumerate(shapes.points):
            v = shapes.shapes[r, k]
            rows.append({"mode": r + 1, "point": point_label(n, d), "node": n, "direction": d,
                         "shape_real": v.real, "shape_imag": v.imag, "shape_abs": abs(v),
                         "shape_phase_deg": float(np.degrees(np.angle(v)))})
    return pd.DataFrame(rows, columns=["mode", "point", "node", "direction", "shape_real",
                                       "shape_imag", "shape_abs", "shape_phase_deg"])
