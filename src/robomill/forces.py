"""Cutting forces of robotic slot milling (thesis §3.1): the mechanistic model, chunked force
spectra in time and spatial frequency, and cutting-coefficient identification.

Model (thesis eq. 3.1, Altintas 2012 §2.4), per tooth in cut, for a small axial depth ``a``:

.. math::

    F_t = K_{tc} a h(φ) + K_{te} a, \\quad F_r = K_{rc} a h(φ) + K_{re} a, \\quad
    F_a = K_{ac} a h(φ) + K_{ae} a, \\qquad h(φ) = c \\sin φ

with φ the immersion angle of the tooth (measured clockwise from the cross-feed axis, the tool
turning clockwise seen from the spindle) and c the feed per tooth. Slotting: a tooth cuts for
0 ≤ φ < π (entry 0, exit π). The forces on the tool in the cut's frame (x along the feed,
y = ẑ × x̂ across it, z up the tool axis) are

.. math:: F_x = −F_t \\cos φ − F_r \\sin φ, \\quad F_y = F_t \\sin φ − F_r \\cos φ, \\quad
          F_z = F_a

summed over the teeth in cut. Sign convention: forces **on the tool** (the dynamometer reading
with its sign inverted), the convention of Altintas (2012).

Everything here is pure numpy/xarray: no file paths (readers are in
:mod:`robomill.io.forces`, the simulator in :mod:`robomill.synth.dynamometer`).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd

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


def feed_per_tooth_mm(feed_mm_s: float, spindle_rpm: float, flutes: int) -> float:
    """Feed per tooth c = v / (N n) [mm] (thesis §2.1: 1.07 µm at 1 mm/s, 28 000 rpm, N = 2)."""
    return float(feed_mm_s) / (int(flutes) * float(spindle_rpm) / 60.0)


def tooth_passing_hz(spindle_rpm: float, flutes: int) -> float:
    """Tooth-passing frequency N n [Hz] (933.3 Hz at 28 000 rpm with two flutes)."""
    return int(flutes) * float(spindle_rpm) / 60.0


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
                np.ndarray, coeffs: CuttingCoefficients, *, flutes: int = 2,
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
                     coeffs: CuttingCoefficients, *, flutes: int = 2) -> np.ndarray:
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
                        flutes=2, entry_rad=0.0, exit_rad=np.pi) -> np.ndarray:
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


# ---- cutting-coefficient identification -------------------------------------------------------
_SLOPE_FACTOR = {"x": -4.0, "y": 4.0, "z": np.pi}
_INTERCEPT_FACTOR = {"x": -np.pi, "y": np.pi, "z": 2.0}
_NAMES = {"y": ("Ktc", "Kte"), "x": ("Krc", "Kre"), "z": ("Kac", "Kae")}

FLAG_COLUMNS = ("negative", "fit_residual_rms_N", "fit_signal_rms_N", "residual_exceeds_signal",
                "physical")
"""Sanity columns of ``cutting_coefficients.csv`` after ``name, value, ci_low, ci_high, unit``
(issue 21 point 5; see :func:`coefficient_flags`)."""


def _fit_rms(fitted_N: np.ndarray, measured_N: np.ndarray, groups: np.ndarray
             ) -> tuple[float, float]:
    """``(residual_rms_N, signal_rms_N)`` of one least-squares fit of mean forces.

    The residual is ``measured − fitted``; the signal is the part of the fitted mean forces
    that the fit explains beyond a constant: the fitted values minus their mean within each
    group of equations (one group per force axis). For ordinary least squares with an
    intercept (the edge term) the two add up to the spread of the measurements, so the
    residual exceeds the signal exactly when the coefficient of determination R² < 1/2.
    """
    fitted = np.asarray(fitted_N, float)
    centred = fitted.copy()
    for g in np.unique(groups):
        sel = groups == g
        centred[sel] -= fitted[sel].mean()
    resid = np.asarray(measured_N, float) - fitted
    return float(np.sqrt(np.mean(resid ** 2))), float(np.sqrt(np.mean(centred ** 2)))


def coefficient_flags(table: pd.DataFrame, fit_rms: Mapping[str, tuple[float, float]]
                      ) -> pd.DataFrame:
    """Add the sanity columns :data:`FLAG_COLUMNS` to an identified-coefficient table.

    Mechanistic cutting and edge coefficients are positive (Altintas 2012, §2.4: the
    tangential, radial and axial forces grow with the chip and the edge rubs against the
    feed), so a negative identified value cannot be physical. A coefficient whose fit leaves
    a residual larger than the signal it explains (:func:`_fit_rms`: the scatter of the mean
    forces about the fit exceeds the change the feed makes) is not resolved by the cuts.

    Parameters
    ----------
    table
        ``name, value, ci_low, ci_high, unit`` (:func:`identify_cutting_coefficients`).
    fit_rms
        Coefficient name → ``(residual_rms_N, signal_rms_N)`` of the fit it comes from.

    Returns
    -------
    pandas.DataFrame
        ``table`` with ``negative`` (value < 0), ``fit_residual_rms_N``, ``fit_signal_rms_N``
        [N], ``residual_exceeds_signal`` and ``physical`` (neither flag set).
    """
    out = table.copy()
    out["negative"] = out["value"].to_numpy(float) < 0
    out["fit_residual_rms_N"] = [fit_rms[n][0] for n in out["name"]]
    out["fit_signal_rms_N"] = [fit_rms[n][1] for n in out["name"]]
    out["residual_exceeds_signal"] = (out["fit_residual_rms_N"].to_numpy()
                                      > out["fit_signal_rms_N"].to_numpy())
    out["physical"] = ~(out["negative"] | out["residual_exceeds_signal"])
    return out


def coefficient_flag_sentence(table: pd.DataFrame) -> str:
    """What the sanity flags of :func:`coefficient_flags` say, in one sentence for a chapter.

    Parameters
    ----------
    table
        ``cutting_coefficients.csv``: ``name, value, unit`` and the columns
        :data:`FLAG_COLUMNS`.

    Returns
    -------
    str
        ``"All N coefficients are physical (positive, resolved by their fit)."`` when every
        row is ``physical``; otherwise ``"Not physical: …"`` naming each coefficient that is
        not and why (negative value; fit residual rms larger than the signal rms, i.e.
        R² < 1/2, Altintas 2012 §2.4 assumes both away). A table without the flag columns
        (an artefact from before issue 21) gives ``""``.
    """
    if not set(FLAG_COLUMNS) <= set(table.columns):
        return ""
    physical = table["physical"].astype(bool)
    if physical.all():
        return f"All {len(table)} coefficients are physical (positive, resolved by their fit)."
    parts = []
    for r in table[~physical].itertuples():
        why = []
        if bool(r.negative):
            why.append(f"negative ({r.value:.3g} {r.unit}): a mechanistic cutting or edge "
                       "coefficient cannot be below zero")
        if bool(r.residual_exceeds_signal):
            why.append(f"not resolved: its fit leaves {r.fit_residual_rms_N:.3g} N rms of "
                       f"residual against {r.fit_signal_rms_N:.3g} N rms of signal (R² < 1/2)")
        parts.append(f"{r.name} is " + ", and ".join(why))
    return "**Not physical:** " + "; ".join(parts) + "."


def identify_cutting_coefficients(feed_per_tooth_mm: np.ndarray, depth_mm: np.ndarray,
                                  mean_forces_N: np.ndarray, *, flutes=2,
                                  confidence: float = 0.95, entry_rad=None,
                                  exit_rad=None) -> pd.DataFrame:
    """Shearing and edge coefficients from the mean forces of slots at several feeds.

    The standard mechanistic calibration (Altintas 2012, §2.4): the mean force per unit
    ``N a`` is linear in the feed per tooth, ``F̄/(N a) = s c + e`` (see
    :func:`mean_slot_forces`); ordinary least squares over all cuts gives slope s and intercept
    e per axis, then ``K_tc = 4 s_y``, ``K_te = π e_y``, ``K_rc = −4 s_x``, ``K_re = −π e_x``,
    ``K_ac = π s_z``, ``K_ae = 2 e_z``. Confidence intervals are Student-t intervals of the
    regression coefficients (``n − 2`` degrees of freedom) scaled the same way.

    Parameters
    ----------
    feed_per_tooth_mm, depth_mm
        Per cut, ``(m,)`` [mm].
    mean_forces_N
        Mean force on the tool per cut in the cut frame, ``(m, 3)`` (feed, cross-feed, axial).
    flutes
        Number of teeth N (scalar, or one per cut).
    confidence
        Two-sided confidence level of the intervals.
    entry_rad, exit_rad
        Per cut (or scalar) engagement window (:func:`engagement_angles_rad`). When given and
        not every cut is a slot of the same tool, the coefficients come from
        :func:`identify_cutting_coefficients_general` (partial immersion, up/down milling,
        several tools).

    Returns
    -------
    pandas.DataFrame
        Columns ``name, value, ci_low, ci_high, unit``; rows Ktc, Krc, Kac (N/mm²), Kte, Kre,
        Kae (N/mm); then the sanity columns ``negative, fit_residual_rms_N,
        fit_signal_rms_N, residual_exceeds_signal, physical`` (:func:`coefficient_flags`; the
        fit of a coefficient is the regression of its force axis).
    """
    from scipy import stats

    if entry_rad is not None or exit_rad is not None or np.ndim(flutes) > 0:
        m = np.size(feed_per_tooth_mm)
        st = np.broadcast_to(np.asarray(0.0 if entry_rad is None else entry_rad, float), (m,))
        ex = np.broadcast_to(np.asarray(np.pi if exit_rad is None else exit_rad, float), (m,))
        z = np.broadcast_to(np.asarray(flutes), (m,))
        if not (np.all(st == 0.0) and np.all(ex == np.pi) and np.all(z == z[0])):
            return identify_cutting_coefficients_general(
                feed_per_tooth_mm, depth_mm, mean_forces_N, flutes=z, entry_rad=st,
                exit_rad=ex, confidence=confidence)
        flutes = int(z[0])

    c = np.asarray(feed_per_tooth_mm, float)
    na = int(flutes) * np.asarray(depth_mm, float)
    F = np.asarray(mean_forces_N, float)
    if c.size < 3 or np.ptp(c) <= 0:
        raise ValueError("need at least 3 cuts at two or more feeds per tooth to identify "
                         f"cutting coefficients (got {c.size} cuts)")
    t = stats.t.ppf(0.5 + confidence / 2, c.size - 2)
    rows = {}
    rms = {}
    for i, ax in enumerate("xyz"):
        fit = stats.linregress(c, F[:, i] / na)
        fitted_N = (fit.intercept + fit.slope * c) * na
        for name in _NAMES[ax]:
            rms[name] = _fit_rms(fitted_N, F[:, i], np.zeros(c.size))
        for kind, val, se, factor in (("c", fit.slope, fit.stderr, _SLOPE_FACTOR[ax]),
                                      ("e", fit.intercept, fit.intercept_stderr,
                                       _INTERCEPT_FACTOR[ax])):
            name = _NAMES[ax][0 if kind == "c" else 1]
            lo, hi = sorted((factor * (val - t * se), factor * (val + t * se)))
            rows[name] = (factor * val, lo, hi)
    table = pd.DataFrame([{"name": n, "value": rows[n][0], "ci_low": rows[n][1],
                           "ci_high": rows[n][2], "unit": u}
                          for n, u in COEFFICIENT_UNITS.items()])
    return coefficient_flags(table, rms)


def identify_cutting_coefficients_general(feed_per_tooth_mm, depth_mm, mean_forces_N, *,
                                          flutes, entry_rad, exit_rad,
                                          confidence: float = 0.95) -> pd.DataFrame:
    """Cutting coefficients from the mean forces of cuts of any immersion and milling mode.

    The mean force of every cut is linear in the six coefficients (Altintas 2012, eq. 2.25;
    :func:`mean_milling_forces`): the feed and cross-feed means of all cuts together are one
    linear least-squares problem in (K_tc, K_rc, K_te, K_re) with ``2 m`` equations, the
    axial means one in (K_ac, K_ae) with ``m``. Intervals are Student-t intervals of the
    ordinary least-squares estimates (covariance ``s² (AᵀA)⁻¹``, ``n − p`` degrees of
    freedom). For slots at several feeds it gives the same values as the per-axis
    regression of :func:`identify_cutting_coefficients`.

    Parameters
    ----------
    feed_per_tooth_mm, depth_mm, flutes, entry_rad, exit_rad
        Per cut, ``(m,)`` (or scalars broadcast to the cuts).
    mean_forces_N
        ``(m, 3)`` mean force on the tool per cut, cut frame (feed, cross-feed, axial).
    confidence
        Two-sided confidence level.

    Returns
    -------
    pandas.DataFrame
        As :func:`identify_cutting_coefficients` (the fit of Ktc, Krc, Kte, Kre is the joint
        feed/cross-feed problem, that of Kac, Kae the axial one).
    """
    from scipy import stats

    F = np.asarray(mean_forces_N, float).reshape(-1, 3)
    m = F.shape[0]
    c, a, z, st, ex = (np.broadcast_to(np.asarray(x, float), (m,)) for x in
                       (feed_per_tooth_mm, depth_mm, flutes, entry_rad, exit_rad))
    if m < 3 or np.ptp(c) <= 0:
        raise ValueError("need at least 3 cuts at two or more feeds per tooth to identify "
                         f"cutting coefficients (got {m} cuts)")
    w = z * a / (2 * np.pi)
    Ig = _window_integrals(st, ex)
    # columns Ktc, Krc, Kte, Kre
    Ax = np.column_stack([-w * c * Ig["SC"], -w * c * Ig["S2"], -w * Ig["C1"], -w * Ig["S1"]])
    Ay = np.column_stack([w * c * Ig["S2"], -w * c * Ig["SC"], w * Ig["S1"], -w * Ig["C1"]])
    Az = np.column_stack([w * c * Ig["S1"], w * Ig["E"]])

    def ols(A, y):
        theta, *_ = np.linalg.lstsq(A, y, rcond=None)
        dof = A.shape[0] - A.shape[1]
        if dof < 1:
            raise ValueError(f"{A.shape[0]} equations for {A.shape[1]} cutting coefficients: "
                             "need more cuts")
        s2 = float(np.sum((y - A @ theta) ** 2)) / dof
        se = np.sqrt(np.diag(s2 * np.linalg.pinv(A.T @ A)))
        return theta, se * stats.t.ppf(0.5 + confidence / 2, dof)

    A_xy, y_xy = np.vstack([Ax, Ay]), np.concatenate([F[:, 0], F[:, 1]])
    t_xy, h_xy = ols(A_xy, y_xy)
    t_z, h_z = ols(Az, F[:, 2])
    rms_xy = _fit_rms(A_xy @ t_xy, y_xy, np.repeat([0, 1], m))
    rms_z = _fit_rms(Az @ t_z, F[:, 2], np.zeros(m))
    rms = {n: rms_xy for n in ("Ktc", "Krc", "Kte", "Kre")} | {"Kac": rms_z, "Kae": rms_z}
    vals = dict(zip(("Ktc", "Krc", "Kte", "Kre", "Kac", "Kae"),
                    zip(np.concatenate([t_xy, t_z]), np.concatenate([h_xy, h_z]), strict=True),
                    strict=True))
    table = pd.DataFrame([{"name": n, "value": float(vals[n][0]),
                           "ci_low": float(vals[n][0] - vals[n][1]),
                           "ci_high": float(vals[n][0] + vals[n][1]), "unit": u}
                          for n, u in COEFFICIENT_UNITS.items()])
    return coefficient_flags(table, rms)


# ---- chunked spectral analysis ------------------------------------------------------------
def lowpass_fir(fs_hz: float, pass_hz: float, stop_hz: float, atten_db: float = 120.0
                ) -> np.ndarray:
    """Linear-phase anti-alias FIR (Kaiser window method, unit DC gain) passing ``pass_hz``
    and attenuating ``atten_db`` from ``stop_hz`` on (:func:`scipy.signal.kaiserord`)."""
    import scipy.signal

    if not 0 < pass_hz < stop_hz <= fs_hz / 2:
        raise ValueError(f"need 0 < pass ({pass_hz}) < stop ({stop_hz}) <= fs/2 ({fs_hz / 2})")
    numtaps, beta = scipy.signal.kaiserord(atten_db, (stop_hz - pass_hz) / (fs_hz / 2))
    h = scipy.signal.firwin(numtaps | 1, (pass_hz + stop_hz) / 2, window=("kaiser", beta),
                            fs=fs_hz)
    return h / h.sum()


class StreamDecimator:
    """Anti-alias filter and downsample by ``factor``, chunk by chunk, exactly as on the whole.

    Output sample m is ``y[m] = Σ_j h[j] x[factor·m − j]`` (``x`` zero before the start), i.e.
    ``scipy.signal.upfirdn(h, x, 1, factor)[:ceil(n / factor)]``; the last ``len(h) − 1``
    input samples are carried over between chunks.
    """

    def __init__(self, h: np.ndarray, factor: int, n_channels: int):
        self.h, self.D = np.asarray(h, float), int(factor)
        self.L = self.h.size
        self.n_in = 0  # samples consumed so far
        self.buf = np.zeros((n_channels, 0))
        self.buf_start = 0  # global index of buf[:, 0]; a multiple of D
        self.out: list[np.ndarray] = []

    def add(self, chunk: np.ndarray) -> None:
        """Add samples ``(n_channels, n)``."""
        import scipy.signal

        chunk = np.atleast_2d(np.asarray(chunk, float))
        if self.n_in == 0:  # zeros before the start: begin the buffer at a multiple of D
            pad = (-(-(self.L - 1) // self.D)) * self.D
            self.buf = np.zeros((chunk.shape[0], pad))
            self.buf_start = -pad
        buf = np.concatenate([self.buf, chunk], axis=1)
        end = self.n_in + chunk.shape[1]  # global end (exclusive)
        m0 = -(-self.n_in // self.D)  # first output index with D m >= n_in
        m1 = -(-end // self.D)  # outputs with D m < end
        if m1 > m0:
            y = scipy.signal.upfirdn(self.h, buf, 1, self.D, axis=-1)
            i0 = m0 - self.buf_start // self.D
            self.out.append(y[:, i0:i0 + (m1 - m0)])
        self.n_in = end
        # keep from the largest multiple of D <= D*m1 - (L-1)
        keep_from = ((self.D * m1 - (self.L - 1)) // self.D) * self.D
        keep_from = min(max(keep_from, self.buf_start), (end // self.D) * self.D)
        self.buf = buf[:, keep_from - self.buf_start:]
        self.buf_start = keep_from

    def result(self) -> np.ndarray:
        """The decimated record ``(n_channels, ceil(n / factor))`` (what was not drained)."""
        return np.concatenate(self.out, axis=1) if self.out else self.buf[:, :0]

    def drain(self) -> np.ndarray:
        """The decimated samples produced since the last drain, and forget them (bounded
        memory for a consumer that processes the output as it comes)."""
        block = self.result()
        self.out = []
        return block


def decimate_whole(x: np.ndarray, h: np.ndarray, factor: int) -> np.ndarray:
    """Reference (unchunked) version of :class:`StreamDecimator` on a whole record ``(c, n)``."""
    import scipy.signal

    x = np.atleast_2d(np.asarray(x, float))
    return scipy.signal.upfirdn(h, x, 1, factor, axis=-1)[:, :-(-x.shape[1] // factor)]


LOWBAND_OVERSAMPLING = 4
"""The decimated low-band record keeps ``fs/D ≥ 4 × lowband_hz`` (:func:`auto_decimation`)."""


def auto_decimation(fs_hz: float, lowband_hz: float) -> int:
    """Decimation factor of the low-band record, from the record's rate and the band.

    The largest integer ``D`` with ``fs/D ≥ 4 × lowband_hz`` (at least 1): the anti-alias FIR
    (:func:`lowpass_fir`) then passes ``lowband_hz`` and stops from ``fs/D − lowband_hz ≥
    3 × lowband_hz``, so nothing folds into the band and the transition is twice the band
    wide (a short filter). 25 at 25 kHz and a 250 Hz band (a 1 kHz low-band record), 10 at
    10 kHz.

    Examples
    --------
    >>> auto_decimation(25_000, 250), auto_decimation(10_000, 250), auto_decimation(815, 250)
    (25, 10, 1)
    """
    if fs_hz <= 0 or lowband_hz <= 0:
        raise ValueError(f"need positive fs ({fs_hz}) and band ({lowband_hz})")
    return max(1, int(np.floor(fs_hz / (LOWBAND_OVERSAMPLING * lowband_hz) + 1e-9)))


@dataclass
class ForceAnalysisSettings:
    """Parameters of the per-cut force analysis (config section ``forces``).

    ``decimation`` ``None`` (the default): derived from each record's rate
    (:func:`auto_decimation`); an integer is used as given and must leave
    ``fs/decimation > 2 × lowband_hz``.
    """

    welch_nperseg: int = 16384
    decimation: int | None = None
    lowband_hz: float = 250.0
    fir_atten_db: float = 120.0
    envelope_blocks: int = 400
    excerpt_samples: int = 1000
    lowband_max_s: float = 300.0

    @classmethod
    def from_mapping(cls, m: Mapping) -> ForceAnalysisSettings:
        keys = cls.__dataclass_fields__
        return cls(**{k: m[k] for k in keys if k in m})


class ForceSpectrumAccumulator:
    """Everything the force chapter needs from one cut, accumulated chunk by chunk.

    Feed consecutive chunks of ``(n, 3)`` forces with :meth:`add`; peak memory is independent of
    the record length (at most ``lowband_max_s`` of the decimated low-band record is held).

    - mean forces (running sums);
    - full-band Welch PSD (:class:`robomill.spectra.WelchAccumulator`, equal to
      :func:`scipy.signal.welch` on the whole record);
    - the low band (0–``lowband_hz``) of the thesis normalized power P(k) = |Z(k)|²/N² of the
      **whole** record (thesis eq. 2.3, resolution 1/T), from an exactly chunked anti-alias
      decimation (:class:`StreamDecimator`) followed by one DFT of the short decimated record:
      the bins k/T below ``lowband_hz`` are those of the full-rate DFT, scaled the same way
      (the filter starts in steady state at the level of the first samples, so the record's
      mean causes no start-up transient). A record longer than ``lowband_max_s`` (a long
      monitoring recording, not a thesis cut) gets the mean of P(k) over consecutive
      ``lowband_max_s`` segments instead (resolution 1/``lowband_max_s``, an unwindowed
      Bartlett average, same scale for a stationary signal; a last partial segment is dropped),
      so that memory stays bounded at any length;
    - a min/max envelope (for the record plot) and a short raw excerpt (the middle of the
      record, for the zoom of thesis Fig 3.3b).
    """

    def __init__(self, fs_hz: float, n_samples: int, settings: ForceAnalysisSettings):
        from robomill.errors import ConfigError
        from robomill.spectra import WelchAccumulator

        self.fs, self.n, self.s = float(fs_hz), int(n_samples), settings
        band = settings.lowband_hz
        if 2 * band >= self.fs:
            raise ConfigError(f"forces.lowband_hz {band:g} Hz is not below the Nyquist "
                              f"frequency of a {self.fs:g} Hz record (expected lowband_hz "
                              f"< {self.fs / 2:g} Hz for this record)")
        self.D = int(settings.decimation or auto_decimation(self.fs, band))
        self.fs_low = self.fs / self.D
        if self.fs_low - band <= band:
            ok = int(np.ceil(self.fs / (2 * band)) - 1)
            raise ConfigError(f"forces.decimation {self.D} leaves fs {self.fs_low:g} Hz of the "
                              f"{self.fs:g} Hz record: too low for a {band:g} Hz band "
                              f"(expected decimation <= {ok} for this record, or null to "
                              "derive it from the record's rate)")
        nper = min(settings.welch_nperseg, self.n)
        self.welch = WelchAccumulator(self.fs, nper, n_channels=3)
        # stop where the decimated record folds back into the band (Nyquist when D = 1)
        h = lowpass_fir(self.fs, band, min(self.fs_low - band, self.fs / 2),
                        settings.fir_atten_db)
        self.dec = StreamDecimator(h, self.D, 3)
        n_low = -(-self.n // self.D)
        seg = max(1, int(round(settings.lowband_max_s * self.fs_low)))
        self.low_segment = n_low if n_low <= seg else seg
        self.low_pending: list[np.ndarray] = []
        self.low_fill = 0
        self.low_power_sum: np.ndarray | None = None
        self.low_f: np.ndarray | None = None
        self.low_segments = 0
        self.sum = np.zeros(3)
        self.count = 0
        nb = max(1, min(settings.envelope_blocks, self.n))
        self.block_edges = np.linspace(0, self.n, nb + 1).astype(int)
        self.env_min = np.full((3, nb), np.inf)
        self.env_max = np.full((3, nb), -np.inf)
        ne = min(settings.excerpt_samples, self.n)
        self.ex_start = (self.n - ne) // 2
        self.excerpt = np.zeros((3, ne))
        self.t0: float | None = None
        self.offset: np.ndarray | None = None

    def add(self, t_s: np.ndarray, force_N: np.ndarray) -> None:
        """Add a chunk: times ``(n,)`` and forces ``(n, 3)``."""
        F = np.asarray(force_N, float).T
        i0, i1 = self.count, self.count + F.shape[1]
        if self.t0 is None and len(t_s):
            self.t0 = float(t_s[0])
        self.sum += F.sum(axis=1)
        self.welch.add(F)
        if self.offset is None:  # start the decimator in steady state at the first level
            self.offset = F[:, : self.D * 8].mean(axis=1, keepdims=True)
        self.dec.add(F - self.offset)
        self._low_band(self.dec.drain())
        # envelope blocks overlapping this chunk
        b0 = np.searchsorted(self.block_edges, i0, side="right") - 1
        b1 = np.searchsorted(self.block_edges, i1, side="left")
        for b in range(max(b0, 0), min(b1, self.env_min.shape[1])):
            lo, hi = max(self.block_edges[b], i0) - i0, min(self.block_edges[b + 1], i1) - i0
            if hi > lo:
                seg = F[:, lo:hi]
                self.env_min[:, b] = np.minimum(self.env_min[:, b], seg.min(axis=1))
                self.env_max[:, b] = np.maximum(self.env_max[:, b], seg.max(axis=1))
        e0, e1 = self.ex_start, self.ex_start + self.excerpt.shape[1]
        lo, hi = max(e0, i0), min(e1, i1)
        if hi > lo:
            self.excerpt[:, lo - e0:hi - e0] = F[:, lo - i0:hi - i0]
        self.count = i1

    def _low_band(self, block: np.ndarray) -> None:
        """Collect decimated samples; each full low-band segment adds its thesis power P(k)."""
        from robomill.spectra import thesis_spectrum

        if block.shape[1]:
            self.low_pending.append(block)
            self.low_fill += block.shape[1]
        while self.low_fill >= self.low_segment:
            buf = np.concatenate(self.low_pending, axis=1)
            seg, rest = buf[:, : self.low_segment], buf[:, self.low_segment:]
            spec = thesis_spectrum(seg + self.offset, self.fs_low)
            if self.low_power_sum is None:
                self.low_power_sum, self.low_f = np.zeros_like(spec.power), spec.f
            self.low_power_sum += spec.power
            self.low_segments += 1
            self.low_pending, self.low_fill = [rest], rest.shape[1]

    def result(self) -> dict[str, np.ndarray]:
        """Arrays of the cut's analysis (see :func:`force_cut_dataset`)."""
        if self.count != self.n:
            raise ValueError(f"accumulated {self.count} samples, expected {self.n}")
        f, psd = self.welch.result()
        power = self.low_power_sum / self.low_segments
        keep = self.low_f <= self.s.lowband_hz
        # the decimated DFT has n/D samples: |Z_low|²/N_low² equals |Z|²/N² of the full record
        return {
            "mean": self.sum / self.n,
            "f_welch": f, "psd": psd,
            "f_low": self.low_f[keep], "power_low": power[:, keep],
            "lowband_segments": self.low_segments,
            "decimation": self.D,
            "lowband_resolution_hz": self.fs_low / self.low_segment,
            "env_t": (self.block_edges[:-1] + self.block_edges[1:]) / 2 / self.fs,
            "env_min": self.env_min, "env_max": self.env_max,
            "excerpt_t": (self.ex_start + np.arange(self.excerpt.shape[1])) / self.fs,
            "excerpt": self.excerpt,
        }


def analyse_force_record(chunks: Iterable[tuple[np.ndarray, np.ndarray]], fs_hz: float,
                         n_samples: int, settings: ForceAnalysisSettings | None = None
                         ) -> dict[str, np.ndarray]:
    """Run :class:`ForceSpectrumAccumulator` over ``(t_s, force_N (n, 3))`` chunks."""
    acc = ForceSpectrumAccumulator(fs_hz, n_samples, settings or ForceAnalysisSettings())
    for t, F in chunks:
        acc.add(t, F)
    return acc.result()


def dominant_peak(f_hz: np.ndarray, power: np.ndarray, band_hz: tuple[float, float], *,
                  exclude_hz: Iterable[float] = (), exclude_width_hz: float = 0.0
                  ) -> tuple[float, float]:
    """Frequency and power of the largest bin of ``power`` within ``band_hz`` (inclusive),
    bins within ``exclude_width_hz`` of any of ``exclude_hz`` left out (the spindle's own
    harmonics, when a slow spindle puts them in the band)."""
    f_hz, power = np.asarray(f_hz), np.asarray(power)
    ok = (f_hz >= band_hz[0]) & (f_hz <= band_hz[1])
    for fx in exclude_hz:
        ok &= np.abs(f_hz - fx) > exclude_width_hz
    sel = np.flatnonzero(ok)
    if sel.size == 0:
        return float("nan"), float("nan")
    i = sel[np.argmax(power[sel])]
    return float(f_hz[i]), float(power[i])


def harmonic_powers(f_hz: np.ndarray, psd: np.ndarray, f0_hz: float, n_harmonics: int, *,
                    half_width_bins: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Power [PSD unit × Hz] of harmonics k·f0 (k = 1..n, below Nyquist) of a Welch PSD
    ``(..., nf)``, integrated over ±``half_width_bins`` around the nearest bin (a Hann window
    spreads a line over about 3 bins). Returns ``(k·f0, power (..., n))``."""
    f_hz = np.asarray(f_hz)
    df = f_hz[1] - f_hz[0]
    ks = np.arange(1, n_harmonics + 1)
    fk = ks * f0_hz
    fk = fk[fk <= f_hz[-1] - half_width_bins * df]
    out = []
    for fh in fk:
        i = int(round(fh / df))
        out.append(psd[..., i - half_width_bins:i + half_width_bins + 1].sum(axis=-1) * df)
    return fk, np.stack(out, axis=-1) if out else np.zeros(psd.shape[:-1] + (0,))


# ---- per-cut artefact and the gathered study ---------------------------------------------------
def _var(dims, data, units, long_name):
    return (dims, np.asarray(data), {"units": units, "long_name": long_name})


def force_cut_dataset(result: Mapping[str, np.ndarray], *, cut: Mapping, fs_hz: float,
                      n_samples: int, spindle_rpm: float, flutes: int,
                      dominant_band_hz: tuple[float, float],
                      kinematic_band_per_mm: tuple[float, float], n_harmonics: int,
                      min_peak_cycles: float = 10.0):
    """The analysis of one cut (from :meth:`ForceSpectrumAccumulator.result`) as a dataset,
    with its peaks: the dominant low-frequency peak (largest bin of the thesis power summed
    over the three axes in ``dominant_band_hz``, the spindle harmonics ±2.5 bins left out),
    the kinematic peak (same, in spatial
    frequency f/v within ``kinematic_band_per_mm``) and the tooth-passing harmonics (Welch).

    Sanity flags (:func:`robomill.spectra.below_resolution`): a peak with fewer than
    ``min_peak_cycles`` periods in the low-band record (resolution 1/T in time, 1/(v T) = 1/L
    in space, L the record's length along the cut) is flagged ``*_below_resolution``: a short
    record (5–25 mm) cannot resolve a kinematic peak near 0.5 1/mm."""
    import xarray as xr

    from robomill.experiment import DIRECTION_VECTORS
    from robomill.spectra import below_resolution

    v = float(cut["feed_mm_s"])
    total_low = np.asarray(result["power_low"]).sum(axis=0)
    f_low = np.asarray(result["f_low"])
    # the spindle's harmonics k n/60 (runout, tooth passing) are tabulated as harmonics, not
    # searched as the dominant peak: with a slow spindle (6000 rpm, 2 teeth: 100, 200 Hz)
    # they fall in the band (at 28 000 rpm they do not: 467 Hz)
    df_hz = float(result.get("lowband_resolution_hz", fs_hz / max(int(n_samples), 1)))
    spindle_hz = float(spindle_rpm) / 60.0
    f_dom, p_dom = dominant_peak(
        f_low, total_low, tuple(dominant_band_hz),
        exclude_hz=spindle_hz * np.arange(1, int(dominant_band_hz[1] / spindle_hz) + 2),
        exclude_width_hz=2.5 * df_hz)
    f_kin, p_kin = dominant_peak(f_low / v, total_low, tuple(kinematic_band_per_mm))
    dom_flag = bool(below_resolution(f_dom, df_hz, min_cycles=min_peak_cycles))
    kin_flag = bool(below_resolution(f_kin, df_hz / v, min_cycles=min_peak_cycles))
    f_tp = tooth_passing_hz(spindle_rpm, flutes)
    fk, hp = harmonic_powers(result["f_welch"], result["psd"], f_tp, n_harmonics)
    R = cut_frame(DIRECTION_VECTORS[cut["direction"]] if cut.get("direction_deg") is None
                  else (np.cos(np.deg2rad(cut["direction_deg"])),
                        np.sin(np.deg2rad(cut["direction_deg"])), 0.0))
    mean = np.asarray(result["mean"])
    ds = xr.Dataset(
        {
            "mean_force": _var("axis", mean, "N", "mean force on the tool, R0 axes"),
            "mean_force_cut": _var("component", R.T @ mean, "N",
                                   "mean force on the tool, cut frame"),
            "psd": _var(("axis", "frequency"), result["psd"], "N^2/Hz",
                        "Welch power spectral density (Hann, 50 % overlap)"),
            "power_low": _var(("axis", "lf_bin"), result["power_low"], "N^2",
                              "thesis normalized power |Z(k)|^2/N^2 of the whole record "
                              "(one-sided, eq. 2.3), low band"),
            "f_low": _var("lf_bin", f_low, "Hz", "frequency of the low-band bin k/T"),
            "f_spatial_low": _var("lf_bin", f_low / v, "1/mm",
                                  "spatial frequency of the low-band bin f/v"),
            "harmonic_power": _var(("axis", "harmonic"), hp, "N^2",
                                   "power of the tooth-passing harmonic (Welch, +-2 bins)"),
            "harmonic_hz": _var("harmonic", fk, "Hz", "tooth-passing harmonic frequency"),
            "envelope_min": _var(("axis", "block"), result["env_min"], "N",
                                 "minimum force in the block"),
            "envelope_max": _var(("axis", "block"), result["env_max"], "N",
                                 "maximum force in the block"),
            "envelope_t": _var("block", result["env_t"], "s", "block centre time"),
            "excerpt": _var(("axis", "sample"), result["excerpt"], "N",
                            "raw force samples from the middle of the record"),
            "excerpt_t": _var("sample", result["excerpt_t"], "s", "time of the raw sample"),
            "dominant_hz": _var((), f_dom, "Hz", "dominant low-frequency peak"),
            "dominant_power": _var((), p_dom, "N^2",
                                   "thesis power at the dominant peak, summed over axes"),
            "kinematic_per_mm": _var((), f_kin, "1/mm", "kinematic (spatial) peak"),
            "kinematic_power": _var((), p_kin, "N^2",
                                    "thesis power at the kinematic peak, summed over axes"),
            "lowband_resolution_hz": _var((), df_hz, "Hz",
                                          "frequency resolution of the low band 1/T"),
            "kinematic_resolution_per_mm": _var((), df_hz / v, "1/mm",
                                                "spatial resolution of the low band 1/(v T)"),
            "dominant_below_resolution": _var((), dom_flag, "1",
                                              f"dominant peak has fewer than {min_peak_cycles:g} "
                                              "periods in the record (or none was found)"),
            "kinematic_below_resolution": _var((), kin_flag, "1",
                                               f"kinematic peak has fewer than "
                                               f"{min_peak_cycles:g} periods in the record "
                                               "(or none was found)"),
        },
        coords={
            "axis": _var("axis", list(AXES), "1", "force channel (R0 axes)"),
            "component": _var("component", ["feed", "cross_feed", "axial"], "1",
                              "cut-frame component"),
            "frequency": _var("frequency", result["f_welch"], "Hz", "Welch frequency"),
            "harmonic": _var("harmonic", np.arange(1, fk.size + 1), "1",
                             "tooth-passing harmonic order"),
        },
        attrs={"cut": cut["id"],
               **{k: int(cut[k]) for k in ("set", "segment") if cut.get(k) is not None},
               "direction": cut.get("direction") or f"{float(cut['direction_deg']):g} deg",
               "feed_mm_s": v, "depth_mm": float(cut["depth_mm"]),
               "fs_hz": float(fs_hz), "n_samples": int(n_samples),
               "feed_per_tooth_mm": feed_per_tooth_mm(v, spindle_rpm, flutes),
               "tooth_passing_hz": f_tp,
               "lowband_segments": int(result.get("lowband_segments", 1)),
               "decimation": int(result.get("decimation", 0)),
               "min_peak_cycles": float(min_peak_cycles)},
    )
    return ds


def gather_force_study(cut_datasets: list, *, flutes: int, confidence: float = 0.95,
                       model_feed_per_tooth_mm: float | None = None,
                       model_depth_mm: float | None = None,
                       processes: Mapping[str, Mapping] | None = None):
    """Combine per-cut datasets into the study's artefacts.

    Returns ``(spectra, peaks, means, harmonics, coefficients)``: the ``spectra.nc`` dataset
    (dims ``cut, axis, frequency, lf_bin, harmonic, block, sample``; the low band is padded
    with NaN to the longest record), the ``peaks.csv`` table (``cut, dominant_hz,
    dominant_power, kinematic_per_mm``), per-cut mean forces, harmonic powers, and the
    identified cutting coefficients (:func:`identify_cutting_coefficients`); ``peaks.csv``
    then carries the sanity flags ``kinematic_resolution_per_mm, kinematic_below_resolution,
    dominant_below_resolution`` (:func:`force_cut_dataset`) and the coefficients theirs
    (:func:`coefficient_flags`: ``negative, fit_residual_rms_N, fit_signal_rms_N,
    residual_exceeds_signal, physical``). The spectra
    dataset also holds the model force shape of thesis Fig 3.2 over one revolution with the
    identified coefficients (``model_force``).

    ``processes`` (cut id → :func:`robomill.experiment.cut_process`), given for a design that
    is not the thesis' (free cut ids, per-cut spindle speed, flutes, immersion, milling mode):
    the cuts keep their given order, ``set``/``segment`` are columns only when every cut has
    them, ``mean_forces.csv`` gains the columns ``spindle_rpm, flutes, radial_immersion,
    milling, entry_deg, exit_deg`` and the coefficients come from each cut's own chip model
    (:func:`identify_cutting_coefficients_general`); the model force is that of the first
    cut's tool and engagement window.
    """
    import xarray as xr

    grouped = all(d.attrs.get("set") is not None and d.attrs.get("segment") is not None
                  for d in cut_datasets)
    if processes is None:
        cut_datasets = sorted(cut_datasets, key=lambda d: (
            d.attrs["set"], d.attrs["segment"], "py px my".split().index(d.attrs["direction"])))
    ids = [d.attrs["cut"] for d in cut_datasets]
    nlow = max(d.sizes["lf_bin"] for d in cut_datasets)
    per_cut = ("psd", "power_low", "f_low", "f_spatial_low", "harmonic_power", "envelope_min",
               "envelope_max", "envelope_t", "excerpt", "excerpt_t", "mean_force",
               "mean_force_cut")
    parts = []
    for d in cut_datasets:
        d = d[list(per_cut)]
        parts.append(d.pad(lf_bin=(0, nlow - d.sizes["lf_bin"])))
    spectra = xr.concat(parts, dim="cut", join="outer", combine_attrs="override",
                        coords="minimal", compat="override")
    spectra.attrs = {}
    attr_vars = {"feed_mm_s": ("mm/s", "feed speed"), "depth_mm": ("mm", "axial depth"),
                 "feed_per_tooth_mm": ("mm", "feed per tooth"), "set": ("1", "set"),
                 "segment": ("1", "segment"), "direction": ("1", "cut direction"),
                 "n_samples": ("1", "samples per axis"),
                 "tooth_passing_hz": ("Hz", "tooth-passing frequency")}
    if not grouped:
        attr_vars = {k: v for k, v in attr_vars.items() if k not in ("set", "segment")}
    for name, (unit, ln) in attr_vars.items():
        spectra[name] = _var("cut", [d.attrs[name] for d in cut_datasets], unit, ln)
    flags = ("lowband_resolution_hz", "kinematic_resolution_per_mm",
             "dominant_below_resolution", "kinematic_below_resolution")
    have_flags = all(name in d for d in cut_datasets for name in flags)
    for name in ("dominant_hz", "dominant_power", "kinematic_per_mm", "kinematic_power",
                 *(flags if have_flags else ())):
        cast = bool if name.endswith("below_resolution") else float
        spectra[name] = _var("cut", [cast(d[name]) for d in cut_datasets],
                             cut_datasets[0][name].attrs["units"],
                             cut_datasets[0][name].attrs["long_name"])
    spectra = spectra.assign_coords(cut=_var("cut", ids, "1", "cut id"))
    if processes is None:
        spectra["harmonic_hz"] = cut_datasets[0]["harmonic_hz"]
    else:  # each cut's own tooth passing (NaN past a cut's last harmonic below Nyquist)
        nh = spectra.sizes["harmonic"]
        hz = np.full((len(cut_datasets), nh), np.nan)
        for i, d in enumerate(cut_datasets):
            hz[i, :d.sizes["harmonic"]] = d["harmonic_hz"].values
        spectra["harmonic_hz"] = _var(("cut", "harmonic"), hz, "Hz",
                                      "tooth-passing harmonic frequency of the cut")
    for name in ("block", "sample"):
        spectra = spectra.assign_coords({name: _var(name, np.arange(spectra.sizes[name]), "1",
                                                    f"{name} index")})
    spectra = spectra.assign_coords(lf_bin=_var("lf_bin", np.arange(nlow), "1",
                                                "low-band bin index k"))
    peaks = pd.DataFrame({"cut": ids,
                          "dominant_hz": spectra["dominant_hz"].values,
                          "dominant_power": spectra["dominant_power"].values,
                          "kinematic_per_mm": spectra["kinematic_per_mm"].values})
    if have_flags:  # sanity flags after the thesis columns
        for name in ("kinematic_resolution_per_mm", "kinematic_below_resolution",
                     "dominant_below_resolution"):
            peaks[name] = spectra[name].values
    means = pd.DataFrame({"cut": ids, **{k: spectra[k].values for k in
                                         ("set", "segment", "direction", "feed_mm_s",
                                          "depth_mm", "feed_per_tooth_mm") if k in spectra}})
    z = np.full(len(ids), int(flutes))
    st, ex = np.zeros(len(ids)), np.full(len(ids), np.pi)
    if processes is not None:
        procs = [processes[c] for c in ids]
        z = np.array([int(p["flutes"]) for p in procs])
        st, ex = np.array([engagement_angles_rad(p["radial_immersion"], p["milling"])
                           for p in procs]).reshape(-1, 2).T
        means["spindle_rpm"] = [float(p["spindle_rpm"]) for p in procs]
        means["flutes"] = z
        means["radial_immersion"] = [float(p["radial_immersion"]) for p in procs]
        means["milling"] = [p["milling"] for p in procs]
        means["entry_deg"] = np.degrees(st)
        means["exit_deg"] = np.degrees(ex)
    for i, a in enumerate(AXES):
        means[f"{a}_N"] = spectra["mean_force"].values[:, i]
    for i, comp in enumerate(("feed", "cross_feed", "axial")):
        means[f"F_{comp}_N"] = spectra["mean_force_cut"].values[:, i]
    hp = spectra["harmonic_power"]
    harmonics = pd.DataFrame([{"cut": c, "harmonic": int(k), "f_hz": float(f),
                               **{f"{a}_power_N2": float(hp.sel(cut=c, axis=a, harmonic=k))
                                  for a in AXES}}
                              for i, c in enumerate(ids)
                              for k, f in zip(spectra["harmonic"].values,
                                              spectra["harmonic_hz"].values if processes is None
                                              else spectra["harmonic_hz"].values[i],
                                              strict=True) if np.isfinite(f)])
    coeffs = identify_cutting_coefficients(
        means["feed_per_tooth_mm"].to_numpy(), means["depth_mm"].to_numpy(),
        means[["F_feed_N", "F_cross_feed_N", "F_axial_N"]].to_numpy(),
        flutes=flutes if processes is None else z, confidence=confidence,
        **({} if processes is None else {"entry_rad": st, "exit_rad": ex}))
    k = CuttingCoefficients(**dict(zip(coeffs["name"], coeffs["value"], strict=True)))
    c_mod = model_feed_per_tooth_mm or float(np.median(means["feed_per_tooth_mm"]))
    a_mod = model_depth_mm or float(np.median(means["depth_mm"]))
    phi = np.linspace(0, 4 * np.pi, 721)
    F = slot_forces(phi, c_mod, a_mod, k, flutes=int(z[0]), entry_rad=float(st[0]),
                    exit_rad=float(ex[0]))
    spectra["model_force"] = _var(("model_angle", "component"), F, "N",
                                  f"eq. 3.1 force on the tool, identified coefficients, "
                                  f"c = {c_mod * 1e3:.2f} um, a = {a_mod:.2f} mm")
    spectra = spectra.assign_coords(model_angle=_var("model_angle", np.degrees(phi), "deg",
                                                     "rotation angle of tooth 1"))
    spectra.attrs.update({"model_feed_per_tooth_mm": c_mod, "model_depth_mm": a_mod})
    return spectra, peaks, means, harmonics, coeffs


def nearest_modes(peaks_hz: np.ndarray, modes: pd.DataFrame) -> pd.DataFrame:
    """The identified mode nearest to each force peak (chapter 3.1, Table 3.1).

    Parameters
    ----------
    peaks_hz
        Peak frequencies [Hz] (the dominant low-frequency peak of each cut).
    modes
        ``results/modal/modes.csv``: columns ``mode`` and ``f_n_hz``.

    Returns
    -------
    DataFrame
        One row per peak: ``nearest_mode``, ``nearest_mode_hz`` and ``offset_hz`` (peak −
        mode); empty columns when there is no mode.
    """
    f = np.asarray(peaks_hz, float)
    f_n = np.asarray(modes["f_n_hz"], float) if len(modes) else np.array([])
    if f_n.size == 0:
        return pd.DataFrame({"nearest_mode": pd.Series([None] * f.size, dtype=object),
                             "nearest_mode_hz": np.full(f.size, np.nan),
                             "offset_hz": np.full(f.size, np.nan)})
    idx = np.abs(f[:, None] - f_n[None, :]).argmin(axis=1)
    return pd.DataFrame({"nearest_mode": modes["mode"].to_numpy()[idx],
                         "nearest_mode_hz": f_n[idx], "offset_hz": f - f_n[idx]})
