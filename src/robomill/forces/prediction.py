"""Prediction intervals of the mean cutting force of a new cut, from the regression that
identified the cutting coefficients.

The mean force of a cut is linear in the six coefficients (Altintas 2012, eq. 2.25;
:func:`robomill.forces.model.mean_milling_forces`): ``F̄_xy = A_xy θ_xy`` with θ_xy = (K_tc,
K_rc, K_te, K_re) and ``F̄_z = A_z θ_z`` with θ_z = (K_ac, K_ae). The identifying cuts give
the ordinary least-squares estimate θ̂ with covariance ``s² (AᵀA)⁻¹`` (``s²`` the residual
variance, ``n − p`` degrees of freedom). For a new cut with rows ``a₀`` the standard
prediction interval of the regression (Montgomery, Peck & Vining 2012, §3.5, eq. 3.54) is

.. math:: a₀ θ̂ ± t_{1−α/2,\\,n−p}\\, s \\sqrt{1 + a₀ (AᵀA)^{-1} a₀ᵀ}

so it carries both the coefficients' uncertainty (the term under the root that grows away
from the identifying cuts' chip loads and engagements) and the scatter of a new cut's mean
force about the law (the ``1``), which a confidence band of the coefficients leaves out.
The magnitude ``|F̄|`` gets the interval of its linearisation (delta method): variance
``gᵀ Σ g`` with ``g = F̄/|F̄|`` and Σ the 3 × 3 prediction covariance of the three means.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from robomill.forces.model import _window_integrals
from robomill.settings import schema_default


def design_rows(feed_per_tooth_mm, depth_mm, flutes, entry_rad, exit_rad
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Regression rows of eq. 2.25 for cuts (all arguments broadcast to one shape ``(...)``):
    ``A_x, A_y`` ``(..., 4)`` in (K_tc, K_rc, K_te, K_re) and ``A_z`` ``(..., 2)`` in
    (K_ac, K_ae), so that the mean forces in the cut frame are ``A_x θ_xy, A_y θ_xy, A_z θ_z``."""
    c, a, z, st, ex = np.broadcast_arrays(*(np.asarray(x, float) for x in
                                            (feed_per_tooth_mm, depth_mm, flutes, entry_rad,
                                             exit_rad)))
    w = z * a / (2 * np.pi)
    Ig = _window_integrals(st, ex)
    Ax = np.stack([-w * c * Ig["SC"], -w * c * Ig["S2"], -w * Ig["C1"], -w * Ig["S1"]], -1)
    Ay = np.stack([w * c * Ig["S2"], -w * c * Ig["SC"], w * Ig["S1"], -w * Ig["C1"]], -1)
    Az = np.stack([w * c * Ig["S1"], w * Ig["E"]], -1)
    return Ax, Ay, Az


@dataclass(frozen=True)
class ForceRegression:
    """The coefficient regression of the identifying cuts: estimates, ``(AᵀA)⁻¹``, residual
    variances [N²] and degrees of freedom of the feed/cross-feed and of the axial problem,
    and the range of the cuts' feed per tooth [mm] (what was identified)."""

    theta_xy: np.ndarray
    xtx_inv_xy: np.ndarray
    s2_xy_N2: float
    dof_xy: int
    theta_z: np.ndarray
    xtx_inv_z: np.ndarray
    s2_z_N2: float
    dof_z: int
    n_cuts: int

    @property
    def dof(self) -> int:
        """Degrees of freedom of the t quantile (the smaller of the two problems')."""
        return int(min(self.dof_xy, self.dof_z))


def fit_force_regression(feed_per_tooth_mm, depth_mm, mean_forces_N, *, flutes,
                         entry_rad=0.0, exit_rad=np.pi) -> ForceRegression:
    """Ordinary least squares of eq. 2.25 over the identifying cuts (the regression of
    :func:`robomill.forces.coefficients.identify_cutting_coefficients_general`).

    Parameters
    ----------
    feed_per_tooth_mm, depth_mm, flutes, entry_rad, exit_rad
        Per cut ``(m,)`` or scalars.
    mean_forces_N
        ``(m, 3)`` mean force per cut in the cut frame (feed, cross-feed, axial).

    Raises
    ------
    ValueError
        Fewer equations than coefficients plus one.
    """
    F = np.asarray(mean_forces_N, float).reshape(-1, 3)
    m = F.shape[0]
    Ax, Ay, Az = design_rows(*(np.broadcast_to(np.asarray(x, float), (m,)) for x in
                               (feed_per_tooth_mm, depth_mm, flutes, entry_rad, exit_rad)))

    def ols(A, y):
        dof = A.shape[0] - A.shape[1]
        if dof < 1:
            raise ValueError(f"{A.shape[0]} equations for {A.shape[1]} cutting coefficients: "
                             "need more cuts")
        theta, *_ = np.linalg.lstsq(A, y, rcond=None)
        return theta, np.linalg.pinv(A.T @ A), float(np.sum((y - A @ theta) ** 2)) / dof, dof

    t_xy, inv_xy, s2_xy, d_xy = ols(np.vstack([Ax, Ay]), np.concatenate([F[:, 0], F[:, 1]]))
    t_z, inv_z, s2_z, d_z = ols(Az, F[:, 2])
    return ForceRegression(t_xy, inv_xy, s2_xy, d_xy, t_z, inv_z, s2_z, d_z, m)


def predict_mean_force(reg: ForceRegression, feed_per_tooth_mm, depth_mm, *, flutes,
                       entry_rad=0.0, exit_rad=np.pi,
                       level: float = schema_default("plan", "interval_level")
                       ) -> dict[str, np.ndarray]:
    """Mean force of new cuts and its prediction interval (module docstring).

    Returns
    -------
    dict
        ``mean_N`` ``(..., 3)`` (cut frame), ``magnitude_N``, ``magnitude_sd_N`` (standard
        deviation of a new cut's |F̄| about the prediction), ``low_N``, ``high_N`` (the
        two-sided ``level`` prediction interval of |F̄|; the low end not below 0) and
        ``component_low_N``, ``component_high_N`` ``(..., 3)`` (each component's own).
    """
    from scipy import stats

    Ax, Ay, Az = design_rows(feed_per_tooth_mm, depth_mm, flutes, entry_rad, exit_rad)
    mean = np.stack([Ax @ reg.theta_xy, Ay @ reg.theta_xy, Az @ reg.theta_z], -1)
    cov = np.zeros(mean.shape + (3,))
    A2 = np.stack([Ax, Ay], -2)                                          # (..., 2, 4)
    cov[..., :2, :2] = (reg.s2_xy_N2 * (A2 @ reg.xtx_inv_xy @ np.swapaxes(A2, -1, -2))
                        + reg.s2_xy_N2 * np.eye(2))
    cov[..., 2, 2] = reg.s2_z_N2 * (1.0 + np.einsum("...i,ij,...j->...", Az, reg.xtx_inv_z,
                                                    Az))
    mag = np.linalg.norm(mean, axis=-1)
    g = mean / np.where(mag > 0, mag, 1.0)[..., None]
    sd = np.sqrt(np.maximum(np.einsum("...i,...ij,...j->...", g, cov, g), 0.0))
    t = float(stats.t.ppf(0.5 + level / 2, reg.dof))
    sd_c = np.sqrt(np.maximum(np.diagonal(cov, axis1=-2, axis2=-1), 0.0))
    return {"mean_N": mean, "magnitude_N": mag, "magnitude_sd_N": sd,
            "low_N": np.maximum(mag - t * sd, 0.0), "high_N": mag + t * sd,
            "component_low_N": mean - t * sd_c, "component_high_N": mean + t * sd_c}


def regression_from_means(means, flutes: int) -> ForceRegression | None:
    """:func:`fit_force_regression` over ``results/forces/mean_forces.csv`` (each cut's
    ``feed_per_tooth_mm``, ``depth_mm``, ``F_feed_N, F_cross_feed_N, F_axial_N`` and, for a
    design other than the thesis', its ``flutes, entry_deg, exit_deg``; else slots of
    ``flutes`` teeth). None when the table cannot identify the coefficients (fewer
    equations than coefficients plus one, or one feed per tooth). Rows whose ``in_fit`` is
    False (a cut that chattered, :func:`robomill.forces.study.gather_force_study`) are left
    out, as they are of the coefficients."""
    from robomill.forces.coefficients import not_identified_reason

    need = ("feed_per_tooth_mm", "depth_mm", "F_feed_N", "F_cross_feed_N", "F_axial_N")
    if means is None or len(means) == 0 or not set(need) <= set(means.columns):
        return None
    if "in_fit" in means:
        means = means[means["in_fit"].astype(str).str.lower().isin(["true", "1"])]
    c = means["feed_per_tooth_mm"].to_numpy(float)
    if not_identified_reason(c) is not None:
        return None
    z = means["flutes"].to_numpy(float) if "flutes" in means else float(flutes)
    st = np.radians(means["entry_deg"].to_numpy(float)) if "entry_deg" in means else 0.0
    ex = np.radians(means["exit_deg"].to_numpy(float)) if "exit_deg" in means else np.pi
    try:
        return fit_force_regression(c, means["depth_mm"].to_numpy(float),
                                    means[["F_feed_N", "F_cross_feed_N",
                                           "F_axial_N"]].to_numpy(float),
                                    flutes=z, entry_rad=st, exit_rad=ex)
    except ValueError:
        return None
