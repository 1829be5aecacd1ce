"""Mode shapes over the measured points, modal masses from a driving point, and the modal
assurance criterion (MAC)."""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from robomill.modal.layout import driving_points, point_label


def _mac(a: np.ndarray, b: np.ndarray) -> float:
    """Modal assurance criterion of two complex vectors (sdypy-EMA's ``MAC``)."""
    from sdypy.EMA import MAC

    with warnings.catch_warnings():  # MAC stores |a^H b|^2/(a^H a b^H b) in a real array
        warnings.simplefilter("ignore", np.exceptions.ComplexWarning)
        return float(np.real(MAC(a, b)))


def _unit_phase(v: np.ndarray) -> np.ndarray:
    """A complex vector scaled to unit norm and turned so that its largest component is real
    and positive."""
    v = np.asarray(v, complex)
    k = int(np.nanargmax(np.abs(v)))
    return v / np.linalg.norm(v) * np.exp(-1j * np.angle(v[k]))


@dataclass
class ModeShapes:
    """Complex unit mode shapes over the measured points (see :func:`mode_shapes`)."""

    points: list[tuple[int, int]]
    """``(node, direction code)`` of each component."""
    shapes: np.ndarray
    """``(n_modes, n_points)`` complex, unit norm, largest component real positive."""
    m_modal_kg: np.ndarray
    """Modal mass of the unit shape (NaN without a driving point)."""
    driving_point: str
    """Label of the driving point used for the scaling ('' when none)."""


def mode_shapes(poles: np.ndarray, residues: np.ndarray,
                outputs: Sequence[tuple[int, int]],
                inputs: Sequence[tuple[int, int]]) -> ModeShapes:
    """Mode shapes over the measured points and, where a driving point exists, modal masses.

    With ``R = 2jω_d A_r`` ≈ ``u uᵀ`` (``u`` the mass-normalised shape; Ewins, *Modal
    Testing*, 2000, §4.4: residue ``A_jk = u_j u_k/(2jω_d)`` for a lightly damped mode):

    * one reference point: the shape over the response points is the column ``R[:, ref]``;
    * one response point (roving hammer): the row ``R[resp, :]`` over the reference points;
    * several of both: the column of the driving-point reference (the reference with the
      largest residues when there is none).

    The shape is normalised to unit norm (complex; :func:`_unit_phase`). With a driving point
    ``p`` (same node and axis in response and reference), ``u_p² = R_pp`` scales it: the
    modal mass of the unit shape is ``m = |R_pp| / ‖ψ‖²`` with the sign of ``Re R_pp``
    (negative: non-physical). Without one the shape stays unscaled and ``m`` is NaN.
    """
    outputs = [tuple(p) for p in outputs]
    inputs = [tuple(p) for p in inputs]
    dps = driving_points(outputs, inputs)
    if len(inputs) == 1:
        pts, axis = outputs, "column"
    elif len(outputs) == 1:
        pts, axis = inputs, "row"
    else:
        pts, axis = outputs, "column"
    shapes = np.full((len(poles), len(pts)), np.nan + 0j)
    masses = np.full(len(poles), np.nan)
    dp_label = ""
    for r, p in enumerate(np.asarray(poles, complex)):
        R = 2j * p.imag * residues[:, :, r]
        if dps:
            i, j, sgn = max(dps, key=lambda d: np.abs(np.nan_to_num(R[d[0], d[1]])))
            dp_label = point_label(*outputs[i])
        else:
            i = j = None
            sgn = 1
        if axis == "column":
            jj = j if j is not None else int(np.nanargmax(np.nansum(np.abs(R), axis=0)))
            psi = R[:, jj]
        else:
            ii = i if i is not None else 0
            psi = R[ii, :]
        # points with an unmeasured pair get NaN; the shape over the others is normalised
        ok = np.isfinite(psi)
        if ok.any():
            shapes[r, ok] = _unit_phase(psi[ok])
        if i is not None and ok.any():
            Rpp = sgn * R[i, j]
            masses[r] = np.sign(Rpp.real) * np.abs(Rpp) / np.sum(np.abs(psi[ok]) ** 2)
    return ModeShapes(list(pts), shapes, masses, dp_label)


def mac_matrix(shapes: np.ndarray) -> np.ndarray:
    """Modal assurance criterion between every pair of (complex) mode shapes ``(n_modes,
    n_points)``: ``MAC_rs = |φ_rᴴ φ_s|² / ((φ_rᴴ φ_r)(φ_sᴴ φ_s))`` (Allemang & Brown 1982),
    over the points where both are measured."""
    phi = np.nan_to_num(np.asarray(shapes, complex))
    num = np.abs(phi.conj() @ phi.T) ** 2
    nrm = np.real(np.sum(phi.conj() * phi, axis=1))
    with np.errstate(divide="ignore", invalid="ignore"):
        return num / np.outer(nrm, nrm)
