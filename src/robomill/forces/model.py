"""The mechanistic cutting-force model of slot and partial-immersion milling (thesis §3.1,
eq. 3.1): coefficients, engagement window, instantaneous, band-limited and mean forces.

Model (thesis eq. 3.1, Altintas 2012 §2.4), per tooth in cut, for a small axial depth ``a``:

.. math::

    F_t = K_{tc} a h(φ) + K_{te} a, \\quad F_r = K_{rc} a h(φ) + K_{re} a, \\quad
    F_a = K_{ac} a h(φ) + K_{ae} a, \\qquad h(φ) = c \\sin φ

with φ the immersion angle of the tooth (measured clockwise from the cross-feed axis, the tool
turning clockwise seen from the spindle) and c the feed per tooth
(:func:`robomill.experiment.feed_per_tooth_mm`). Slotting: a tooth cuts for 0 ≤ φ < π
(entry 0, exit π). The forces on the tool in the cut's frame (x along the feed, y = ẑ × x̂
across it, z up the tool axis) are

.. math:: F_x = −F_t \\cos φ − F_r \\sin φ, \\quad F_y = F_t \\sin φ − F_r \\cos φ, \\quad
          F_z = F_a

summed over the teeth in cut. Sign convention: forces **on the tool** (the dynamometer reading
with its sign inverted), the convention of Altintas (2012). Pure numpy: no file paths.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np

from robomill.settings import schema_default

AXES = ("Fx", "Fy", "Fz")
"""Force channels of the dynamometer (base / block axes X, Y, Z)."""

COEFFICIENT_UNITS = {"Ktc": "N/mm^2", "Krc": "N/mm^2", "Kac": "N/mm^2",
                     "Kte": "N/mm", "Kre": "N/mm", "Kae": "N/mm"}
"""Cutting coefficients in the order of ``cutting_coefficients.csv`` and their units."""


@dataclass(frozen=True)
class CuttingCoefficients:
    """Mechanistic cutting coefficients of eq. 3.1: shearing ``K*c`` [N/mm²], edge ``K*e``
    [N/mm]."""

    Ktc: float
    Krc: float
    Kac: float
    Kte: float
    Kre: float
    Kae: float

    @classmethod
    def from_mapping(cls, m: Mapping[str, float]) -> CuttingCoefficients:
        """From ``{Ktc_N_mm2: …, Kte_N_mm: …}`` (config ``synth.cutting``) or ``{Ktc: …}``."""
        return cls(**{k: float(m[k] if k in m else m[f"{k}_{'N_mm2' if k[-1] == 'c' else 'N_mm'}"])
                      for k in COEFFICIENT_UNITS})

    def as_dict(self) -> dict[str, float]:
        return {k: getattr(self, k) for k in COEFFICIENT_UNITS}



def cut_frame(direction_vector: Iterable[float]) -> np.ndarray:
    """Rotation ``R`` (3×3) whose columns are the cut frame's feed x, cross-feed y = ẑ × x and
    axial z axes expressed in base axes: ``F_base = R @ F_cut``."""
    x = np.asarray(direction_vector, float)
    x = x / np.linalg.norm(x)
    z = np.array([0.0, 0.0, 1.0])
    y = np.cross(z, x)
    return np.column_stack([x, y, z])


MILLING_MODES = ("slot", "up", "down")
"""Milling modes of :func:`engagement_angles_rad`."""


def engagement_angles_rad(radial_immersion: float = 1.0, milling: str = "slot"
                          ) -> tuple[float, float]:
    """Entry and exit angles (φ_st, φ_ex) of a tooth [rad] (Altintas 2012, §2.2, Fig 2.6).

    φ is measured clockwise from the cross-feed axis (the tool turning clockwise, the same
    convention as eq. 3.1). With the radial immersion ``r = a_e / D``:

    - slot (``r = 1``): φ_st = 0, φ_ex = π;
    - up (conventional) milling: φ_st = 0, φ_ex = arccos(1 − 2 r);
    - down (climb) milling: φ_st = π − arccos(1 − 2 r), φ_ex = π.

    Parameters
    ----------
    radial_immersion
        a_e / D in (0, 1].
    milling
        ``slot``, ``up`` or ``down`` (``slot`` requires ``radial_immersion`` = 1).

    Examples
    --------
    >>> [round(float(x), 4) for x in engagement_angles_rad(0.5, "down")]
    [1.5708, 3.1416]
    """
    r = float(radial_immersion)
    if not 0.0 < r <= 1.0:
        raise ValueError(f"radial_immersion must be in (0, 1], got {r}")
    if milling not in MILLING_MODES:
        raise ValueError(f"milling must be one of {', '.join(MILLING_MODES)}, got {milling!r}")
    if milling == "slot":
        if r != 1.0:
            raise ValueError(f"milling 'slot' needs radial_immersion 1, got {r}")
        return 0.0, float(np.pi)
    sweep = float(np.arccos(1.0 - 2.0 * r))
    return (0.0, sweep) if milling == "up" else (float(np.pi) - sweep, float(np.pi))


def _is_slot(entry_rad: float, exit_rad: float) -> bool:
    return float(entry_rad) == 0.0 and float(exit_rad) == float(np.pi)


def slot_forces(phi_rad: np.ndarray, feed_per_tooth_mm: float | np.ndarray, depth_mm: float |
                np.ndarray, coeffs: CuttingCoefficients, *,
                flutes: int = schema_default("experiment", "flutes"),
                cross_feed_mm: float | np.ndarray = 0.0, entry_rad: float = 0.0,
                exit_rad: float = np.pi) -> np.ndarray:
    """Milling forces on the tool in the cut frame (thesis eq. 3.1, h = c sin φ); a slot by
    default, any radial immersion through the tooth's engagement window.

    Parameters
    ----------
    phi_rad
        Immersion angle of tooth 1, shape ``(n,)``; tooth j lags it by ``2π j / flutes``.
    feed_per_tooth_mm
        Feed per tooth c [mm], scalar or ``(n,)`` (a time-varying chip load: the feed plus the
        tool's displacement along the feed over one tooth period).
    depth_mm
        Axial depth a [mm], scalar or ``(n,)``.
    coeffs
        Cutting coefficients.
    flutes
        Number of teeth N.
    cross_feed_mm
        Displacement across the feed over one tooth period [mm]: chip thickness
        ``h = c sin φ + c_y cos φ`` (zero for the nominal model).
    entry_rad, exit_rad
        Engagement window φ_st ≤ φ < φ_ex of a tooth (:func:`engagement_angles_rad`; Altintas
        2012, eq. 2.19: a tooth cuts only inside it). Default 0, π: a slot.

    Returns
    -------
    numpy.ndarray
        ``(n, 3)``: F_x (feed), F_y (cross-feed), F_z (axial) [N]. Negative chip thickness
        (the tooth leaves the material) is clipped to zero; the edge forces act whenever a
        tooth is engaged (φ_st ≤ φ < φ_ex).

    Examples
    --------
    >>> k = CuttingCoefficients(796, 168, 222, 27.7, 30.8, 6.7)
    >>> phi = np.linspace(0, 2 * np.pi, 100_000, endpoint=False)
    >>> F = slot_forces(phi, 0.005, 0.25, k).mean(axis=0)
    >>> bool(np.allclose(F, mean_slot_forces(0.005, 0.25, k), rtol=1e-4))
    True
    """
    phi = np.asarray(phi_rad, float)
    c = np.asarray(feed_per_tooth_mm, float)
    cy = np.asarray(cross_feed_mm, float)
    a = np.asarray(depth_mm, float)
    out = np.zeros(phi.shape + (3,))
    for j in range(int(flutes)):
        pj = np.mod(phi - 2 * np.pi * j / flutes, 2 * np.pi)
        engaged = (pj >= entry_rad) & (pj < exit_rad)
        s, co = np.sin(pj), np.cos(pj)
        h = np.maximum(c * s + cy * co, 0.0) * engaged
        ae = a * engaged
        ft = coeffs.Ktc * a * h + coeffs.Kte * ae
        fr = coeffs.Krc * a * h + coeffs.Kre * ae
        out[..., 0] += -ft * co - fr * s
        out[..., 1] += ft * s - fr * co
        out[..., 2] += coeffs.Kac * a * h + coeffs.Kae * ae
    return out


def mean_slot_forces(feed_per_tooth_mm: float | np.ndarray, depth_mm: float | np.ndarray,
                     coeffs: CuttingCoefficients, *,
                     flutes: int = schema_default("experiment", "flutes")) -> np.ndarray:
    """Closed-form mean forces of a full slot (φ from 0 to π), cut frame, on the tool [N].

    Averaging eq. 3.1 over a revolution (Altintas 2012, eq. 2.25 for φ_st = 0, φ_ex = π):

    .. math::
        \\bar F_x = −N a (K_{rc} c/4 + K_{re}/π), \\quad
        \\bar F_y = N a (K_{tc} c/4 + K_{te}/π), \\quad
        \\bar F_z = N a (K_{ac} c/π + K_{ae}/2)

    Returns ``(..., 3)`` for broadcast ``c`` and ``a``.
    """
    c = np.asarray(feed_per_tooth_mm, float)
    na = int(flutes) * np.asarray(depth_mm, float)
    return np.stack([-na * (coeffs.Krc * c / 4 + coeffs.Kre / np.pi),
                     na * (coeffs.Ktc * c / 4 + coeffs.Kte / np.pi),
                     na * (coeffs.Kac * c / np.pi + coeffs.Kae / 2)], axis=-1)


def _window_integrals(entry_rad, exit_rad) -> dict[str, np.ndarray]:
    """∫ g(φ) dφ over φ_st..φ_ex of the basis g = sin², sin·cos, cos², sin, cos, 1."""
    a, b = np.asarray(entry_rad, float), np.asarray(exit_rad, float)

    def F(p):
        return {"S2": (2 * p - np.sin(2 * p)) / 4, "SC": np.sin(p) ** 2 / 2,
                "C2": (2 * p + np.sin(2 * p)) / 4, "S1": -np.cos(p), "C1": np.sin(p), "E": p}

    fa, fb = F(a), F(b)
    return {k: fb[k] - fa[k] for k in fa}


def mean_milling_forces(feed_per_tooth_mm, depth_mm, coeffs: CuttingCoefficients, *,
                        flutes: int = schema_default("experiment", "flutes"), entry_rad=0.0,
                        exit_rad=np.pi) -> np.ndarray:
    """Closed-form mean forces of a cut engaged from φ_st to φ_ex, cut frame, on the tool [N].

    Altintas 2012, eq. 2.25: the force of eq. 3.1 averaged over one revolution,

    .. math::
        \\bar F_x = \\frac{N a}{2π}\\left[c\\left(-K_{tc} I_{sc} - K_{rc} I_{s^2}\\right)
                     - K_{te} I_c - K_{re} I_s\\right], \\quad
        \\bar F_y = \\frac{N a}{2π}\\left[c\\left(K_{tc} I_{s^2} - K_{rc} I_{sc}\\right)
                     + K_{te} I_s - K_{re} I_c\\right], \\quad
        \\bar F_z = \\frac{N a}{2π}\\left[K_{ac} c I_s + K_{ae} (φ_{ex} − φ_{st})\\right]

    with I the integrals of sin φ cos φ, sin² φ, cos φ, sin φ over the window. For φ_st = 0,
    φ_ex = π it equals :func:`mean_slot_forces`. All arguments broadcast (one value per cut).

    Examples
    --------
    >>> k = CuttingCoefficients(796, 168, 222, 27.7, 30.8, 6.7)
    >>> bool(np.allclose(mean_milling_forces(0.005, 0.25, k), mean_slot_forces(0.005, 0.25, k)))
    True
    """
    c = np.asarray(feed_per_tooth_mm, float)
    na = np.asarray(flutes, float) * np.asarray(depth_mm, float) / (2 * np.pi)
    Ig = _window_integrals(entry_rad, exit_rad)
    k = coeffs
    fx = c * (-k.Ktc * Ig["SC"] - k.Krc * Ig["S2"]) - k.Kte * Ig["C1"] - k.Kre * Ig["S1"]
    fy = c * (k.Ktc * Ig["S2"] - k.Krc * Ig["SC"]) + k.Kte * Ig["S1"] - k.Kre * Ig["C1"]
    fz = k.Kac * c * Ig["S1"] + k.Kae * Ig["E"]
    return np.stack(np.broadcast_arrays(na * fx, na * fy, na * fz), axis=-1)


BASIS = ("S2", "SC", "C2", "S1", "C1", "E")
"""Periodic basis of eq. 3.1 summed over the teeth in cut: Σ_j g_j(φ_j) with g = sin², sin·cos,
cos², sin, cos, 1 on 0 ≤ φ_j < π."""


def _basis_exact(phi: np.ndarray, flutes: int, entry_rad: float = 0.0,
                 exit_rad: float = np.pi) -> np.ndarray:
    out = np.zeros((len(BASIS),) + np.shape(phi))
    for j in range(int(flutes)):
        pj = np.mod(phi - 2 * np.pi * j / flutes, 2 * np.pi)
        e = (pj >= entry_rad) & (pj < exit_rad)
        s, c = np.sin(pj) * e, np.cos(pj) * e
        out += np.stack([s * s, s * c, c * c, s, c, e.astype(float)])
    return out


@dataclass(frozen=True)
class SlotForceTables:
    """Band-limited periodic basis of eq. 3.1 (see :func:`slot_force_tables`)."""

    phi: np.ndarray  # (M + 1,) grid over one revolution, closed
    table: np.ndarray  # (6, M + 1)
    flutes: int

    def __call__(self, phi_rad: np.ndarray) -> np.ndarray:
        """Basis values ``(6, n)`` at angles ``phi_rad`` (linear interpolation)."""
        p = np.mod(np.asarray(phi_rad, float), 2 * np.pi)
        x = p * ((self.phi.size - 1) / (2 * np.pi))
        i = np.minimum(x.astype(np.int64), self.phi.size - 2)
        w = x - i
        return self.table[:, i] * (1 - w) + self.table[:, i + 1] * w


def slot_force_tables(flutes: int, max_harmonic: int, n_grid: int = 8192, *,
                      entry_rad: float = 0.0, exit_rad: float = np.pi) -> SlotForceTables:
    """The periodic basis of eq. 3.1 band-limited to spindle harmonics ``≤ max_harmonic``.

    A sampled record of the slot force aliases: the edge force jumps at tooth entry/exit, so
    its harmonics fall off only as 1/k. A data-acquisition system low-pass filters before it
    samples; this table is that ideal anti-alias filter applied to the force's periodic shape
    (Fourier series truncated; the mean of every basis function is kept exactly). The force
    with slowly varying chip load and depth is then ``F = Σ_i w_i(t) B_i(φ(t))``
    (:func:`slot_forces_band_limited`). ``entry_rad``, ``exit_rad``: the tooth's engagement
    window (:func:`engagement_angles_rad`; default a slot), the means then those of Altintas
    2012 eq. 2.25 (:func:`mean_milling_forces`).
    """
    phi_mid = (np.arange(n_grid) + 0.5) * 2 * np.pi / n_grid
    B = _basis_exact(phi_mid, flutes, entry_rad, exit_rad)
    spec = np.fft.rfft(B, axis=-1)
    spec[:, max_harmonic + 1:] = 0.0
    # the half-sample shift of the grid: evaluate the truncated series on the closed grid
    k = np.arange(spec.shape[-1])
    spec *= np.exp(-1j * k * np.pi / n_grid)  # shift by half a sample back to φ = 0
    if _is_slot(entry_rad, exit_rad):
        mean = {"S2": 0.5, "SC": 0.0, "C2": 0.5, "S1": 2 / np.pi, "C1": 0.0, "E": 1.0}
        spec[:, 0] = [mean[b] * flutes / 2 * n_grid for b in BASIS]
    else:
        Ig = _window_integrals(entry_rad, exit_rad)
        spec[:, 0] = [float(Ig[b]) * flutes / (2 * np.pi) * n_grid for b in BASIS]
    table = np.fft.irfft(spec, n=n_grid, axis=-1)
    table = np.concatenate([table, table[:, :1]], axis=-1)
    return SlotForceTables(np.linspace(0, 2 * np.pi, n_grid + 1), table, int(flutes))


def slot_forces_band_limited(phi_rad: np.ndarray, feed_per_tooth_mm, depth_mm,
                             coeffs: CuttingCoefficients, tables: SlotForceTables, *,
                             cross_feed_mm=0.0) -> np.ndarray:
    """Eq. 3.1 with the linear chip thickness ``h = c sin φ + c_y cos φ`` (no clipping),
    from band-limited basis tables: ``(n, 3)`` on the tool, cut frame [N].

    Equals :func:`slot_forces` (up to the truncated harmonics) whenever the chip thickness
    stays positive, which holds when the vibration per tooth is smaller than the feed.
    """
    S2, SC, C2, S1, C1, E = tables(phi_rad)
    a = np.asarray(depth_mm, float)
    ac = a * np.asarray(feed_per_tooth_mm, float)
    ay = a * np.asarray(cross_feed_mm, float)
    k = coeffs
    fx = ac * (-k.Ktc * SC - k.Krc * S2) + ay * (-k.Ktc * C2 - k.Krc * SC) + a * (
        -k.Kte * C1 - k.Kre * S1)
    fy = ac * (k.Ktc * S2 - k.Krc * SC) + ay * (k.Ktc * SC - k.Krc * C2) + a * (
        k.Kte * S1 - k.Kre * C1)
    fz = ac * k.Kac * S1 + ay * k.Kac * C1 + a * k.Kae * E
    return np.stack([fx, fy, fz], axis=-1)

