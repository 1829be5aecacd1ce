"""Cutting-coefficient identification from mean forces (thesis §3.1, Altintas 2012 §2.4),
with the sanity flags of each identified coefficient (negative value, fit residual larger
than the signal it explains) and the chapter's sentence about them.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from robomill.forces.model import COEFFICIENT_UNITS, _window_integrals
from robomill.settings import schema_default

_SLOPE_FACTOR = {"x": -4.0, "y": 4.0, "z": np.pi}
_INTERCEPT_FACTOR = {"x": -np.pi, "y": np.pi, "z": 2.0}
_NAMES = {"y": ("Ktc", "Kte"), "x": ("Krc", "Kre"), "z": ("Kac", "Kae")}

FLAG_COLUMNS = ("negative", "fit_residual_rms_N", "fit_signal_rms_N", "residual_exceeds_signal",
                "physical")
"""Sanity columns of ``cutting_coefficients.csv`` after ``name, value, ci_low, ci_high, unit``
(see :func:`coefficient_flags`)."""

IDENTIFICATION_NEED = "need ≥ 3 cuts at ≥ 2 feeds per tooth"
"""What the mechanistic calibration needs from the design (Altintas 2012, §2.4: a straight
line per axis through the mean forces against the feed per tooth, with one residual degree of
freedom at least)."""

NOT_IDENTIFIED = {
    "few_cuts": "not identified: fewer than 3 force cuts",
    "one_feed_per_tooth": "not identified: the cuts have one feed per tooth",
    "unknown": "not identified: the table holds no coefficient value",
}
"""Reason code of ``not_identified_reason`` (``cutting_coefficients.csv``) → its sentence,
completed by :data:`IDENTIFICATION_NEED` (:func:`not_identified_sentence`). Three cuts or more
also give the general least squares of :func:`identify_cutting_coefficients_general` enough
equations (``2 m − 4 ≥ 2`` and ``m − 2 ≥ 1`` degrees of freedom)."""

IDENTIFIED_COLUMNS = ("identified", "not_identified_reason")
"""Columns appended to ``cutting_coefficients.csv`` only when the design cannot identify the
coefficients (:func:`not_identified_table`); a table without them is identified."""


def not_identified_reason(feed_per_tooth_mm) -> str | None:
    """Why the force cuts cannot identify the cutting coefficients, as a code of
    :data:`NOT_IDENTIFIED`, or ``None`` when they can.

    The mean force per unit ``N a`` is a straight line in the feed per tooth (Altintas 2012,
    eq. 2.25): its slope (the cutting coefficients) needs two feeds per tooth or more, and
    its interval a residual degree of freedom, so at least three cuts (``few_cuts`` before
    ``one_feed_per_tooth``).

    Parameters
    ----------
    feed_per_tooth_mm
        Feed per tooth of each force cut [mm] (the design alone decides: the workflow asks
        before any record is read).
    """
    c = np.asarray(feed_per_tooth_mm, float).ravel()
    if c.size < 3:
        return "few_cuts"
    if np.ptp(c) <= 1e-12 * max(float(np.abs(c).max()), 1e-300):
        return "one_feed_per_tooth"
    return None


def design_not_identified(cuts, experiment: Mapping, force_cuts) -> str | None:
    """Whether a study's design can identify the cutting coefficients, before any record
    is read: ``None``, or the sentence of :func:`not_identified_sentence` for its force cuts.

    Parameters
    ----------
    cuts
        The manifest's cuts (:class:`robomill.experiment.Cut`).
    experiment
        The manifest's experiment defaults (spindle speed, flutes) of :func:`cut_process`.
    force_cuts
        The ids of the cuts that have a force record; none gives ``None`` (the study has no
        forces to identify anything from, which the workflow says on its own).
    """
    from robomill.experiment import cut_process

    ids = set(force_cuts)
    if not ids:
        return None
    try:
        feeds = [cut_process(c, experiment)["feed_per_tooth_mm"] for c in cuts if c.id in ids]
    except (TypeError, KeyError, ZeroDivisionError):
        return None  # a feed or spindle speed missing: the manifest's own check names it
    why = not_identified_reason(feeds)
    return None if why is None else not_identified_sentence(why)


def not_identified_sentence(reason: str) -> str:
    """``"not identified: the cuts have one feed per tooth (need ≥ 3 cuts at ≥ 2 feeds per
    tooth)"``: the reason code of :func:`not_identified_reason` in words."""
    return f"{NOT_IDENTIFIED.get(reason, NOT_IDENTIFIED['unknown'])} ({IDENTIFICATION_NEED})"


def not_identified_table(reason: str) -> pd.DataFrame:
    """``cutting_coefficients.csv`` of a design that cannot identify the coefficients: the
    columns of an identified table (:func:`identify_cutting_coefficients`) with NaN value,
    interval and fit rms, the flags ``negative`` and ``residual_exceeds_signal`` False and
    ``physical`` False, then :data:`IDENTIFIED_COLUMNS`: ``identified`` False and
    ``not_identified_reason`` the code of :data:`NOT_IDENTIFIED`."""
    nan = float("nan")
    return pd.DataFrame([{"name": n, "value": nan, "ci_low": nan, "ci_high": nan, "unit": u,
                          "negative": False, "fit_residual_rms_N": nan,
                          "fit_signal_rms_N": nan, "residual_exceeds_signal": False,
                          "physical": False, "identified": False,
                          "not_identified_reason": reason}
                         for n, u in COEFFICIENT_UNITS.items()])


def identification_status(table: pd.DataFrame) -> str | None:
    """The reason code of a ``cutting_coefficients.csv`` whose coefficients were not
    identified (:func:`not_identified_table`), or ``None`` for an identified table (one
    without the :data:`IDENTIFIED_COLUMNS`, or with ``identified`` true). A table without a
    finite value and without a code reads ``"unknown"``."""
    if "identified" in table and not table["identified"].astype(str).str.lower().isin(
            ["true", "1"]).all():
        codes = table.get("not_identified_reason", pd.Series(dtype=object)).dropna()
        return str(codes.iloc[0]) if len(codes) else "unknown"
    if len(table) and not np.isfinite(pd.to_numeric(table["value"], errors="coerce")).any():
        return "unknown"
    return None


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
        (an artefact written before the flags existed) gives ``""``.
    """
    if not set(FLAG_COLUMNS) <= set(table.columns):
        return ""
    parts = not_physical_reasons(table)
    if not parts:
        return f"All {len(table)} coefficients are physical (positive, resolved by their fit)."
    return "**Not physical:** " + "; ".join(parts) + "."


def not_physical_reasons(table: pd.DataFrame) -> list[str]:
    """Each coefficient of ``cutting_coefficients.csv`` that is not ``physical``, and why:
    ``"Krc is negative (-3 N/mm^2): …"`` (a mechanistic cutting or edge coefficient cannot be
    below zero) and/or ``"… not resolved: its fit leaves … N rms of residual against … N rms
    of signal (R² < 1/2)"``; empty when every row is physical."""
    parts = []
    for r in table[~table["physical"].astype(bool)].itertuples():
        why = []
        if bool(r.negative):
            why.append(f"negative ({r.value:.3g} {r.unit}): a mechanistic cutting or edge "
                       "coefficient cannot be below zero")
        if bool(r.residual_exceeds_signal):
            why.append(f"not resolved: its fit leaves {r.fit_residual_rms_N:.3g} N rms of "
                       f"residual against {r.fit_signal_rms_N:.3g} N rms of signal (R² < 1/2)")
        parts.append(f"{r.name} is " + ", and ".join(why))
    return parts


def identify_cutting_coefficients(feed_per_tooth_mm: np.ndarray, depth_mm: np.ndarray,
                                  mean_forces_N: np.ndarray, *,
                                  flutes: int = schema_default("experiment", "flutes"),
                                  confidence: float = schema_default("forces", "confidence"),
                                  entry_rad=None,
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
    if not_identified_reason(c) is not None:
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
                                          confidence: float = schema_default("forces", "confidence")
                                          ) -> pd.DataFrame:
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
    if not_identified_reason(c) is not None:
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



def direction_heterogeneity(means: pd.DataFrame, *,
                            flutes: int = schema_default("experiment", "flutes"),
                            confidence: float = schema_default("forces", "confidence")
                            ) -> pd.DataFrame | None:
    """Whether the feed directions share the cutting coefficients: each coefficient identified
    from each direction's cuts alone (:func:`identify_cutting_coefficients` on the rows of
    ``mean_forces.csv`` in the fit, grouped by ``direction``), and Cochran's test of
    homogeneity across the directions [Cochran 1954; Higgins & Thompson 2002]:

    .. math:: Q = \\sum_d w_d (K_d − \\bar K)^2, \\quad w_d = 1/s_d^2, \\quad
              \\bar K = \\frac{\\sum_d w_d K_d}{\\sum_d w_d}, \\quad
              I^2 = \\max(0, (Q − (D − 1))/Q)

    with s_d the standard error of direction d's estimate (its interval's half-width over the
    Student-t quantile of its fit) and p the χ² tail of Q with D − 1 degrees of freedom. The
    mechanistic model has one set of coefficients for every direction; ``disagree`` marks the
    coefficients whose p Holm's test rejects at the family-wise level ``1 − confidence`` over
    the six (:func:`holm_rejects`): the mean forces depend on the direction too, which the
    pooled interval of :func:`identify_cutting_coefficients` (the scatter about one line) does
    not hold. (χ² is the reference of Q for known standard errors; each direction's is
    estimated from its own fit, so with few cuts per direction the test is somewhat liberal.)

    Returns
    -------
    pandas.DataFrame or None
        One row per coefficient: ``name, unit, directions`` (``"px, py, …"``), per direction
        ``value_<d>, ci_low_<d>, ci_high_<d>``, ``q, dof, p_value, i2_pct, disagree``; None
        with fewer than two directions whose cuts identify the coefficients on their own
        (:func:`not_identified_reason`) or without a ``direction`` column.

    Cochran 1954: Cochran, W. G. The combination of estimates from different experiments.
    *Biometrics* **10**(1), 101–129. Higgins & Thompson 2002: Higgins, J. P. T.; Thompson,
    S. G. Quantifying heterogeneity in a meta-analysis. *Statistics in Medicine* **21**(11),
    1539–1558.
    """
    from scipy import stats

    if "direction" not in means:
        return None
    rows = means[means["in_fit"].astype(bool)] if "in_fit" in means else means
    fits = {}
    for d, g in rows.groupby(rows["direction"].astype(str), sort=True):
        c = g["feed_per_tooth_mm"].to_numpy(float)
        if not_identified_reason(c) is not None:
            continue
        general = {}
        if {"entry_deg", "exit_deg", "flutes"} <= set(g.columns):
            general = {"entry_rad": np.radians(g["entry_deg"].to_numpy(float)),
                       "exit_rad": np.radians(g["exit_deg"].to_numpy(float))}
        z = g["flutes"].to_numpy(int) if "flutes" in g else flutes
        try:
            table = identify_cutting_coefficients(
                c, g["depth_mm"].to_numpy(float),
                g[["F_feed_N", "F_cross_feed_N", "F_axial_N"]].to_numpy(float), flutes=z,
                confidence=confidence, **general).set_index("name")
        except (ValueError, np.linalg.LinAlgError):
            continue  # a direction whose cuts do not identify the six alone (general fit)
        slot = not general or (np.allclose(general["entry_rad"], 0.0)
                               and np.allclose(general["exit_rad"], np.pi)
                               and np.all(np.asarray(z) == np.ravel(z)[0]))
        m = c.size
        dof = {n: m - 2 if slot or n in ("Kac", "Kae") else 2 * m - 4 for n in table.index}
        fits[d] = (table, dof)
    if len(fits) < 2:
        return None
    out = []
    for name, unit in COEFFICIENT_UNITS.items():
        row = {"name": name, "unit": unit, "directions": ", ".join(fits)}
        v, s = [], []
        for d, (table, dof) in fits.items():
            r = table.loc[name]
            row |= {f"value_{d}": float(r["value"]), f"ci_low_{d}": float(r["ci_low"]),
                    f"ci_high_{d}": float(r["ci_high"])}
            v.append(float(r["value"]))
            s.append((float(r["ci_high"]) - float(r["ci_low"]))
                     / (2 * stats.t.ppf(0.5 + confidence / 2, dof[name])))
        v, s = np.array(v), np.array(s)
        if np.all(np.isfinite(s) & (s > 0)):
            w = 1.0 / s**2
            q = float(np.sum(w * (v - np.sum(w * v) / np.sum(w)) ** 2))
            p = float(stats.chi2.sf(q, len(v) - 1))
            i2 = 100 * max(0.0, (q - (len(v) - 1)) / q) if q > 0 else 0.0
        else:  # an exact fit has no standard error to weigh it by
            q = p = i2 = float("nan")
        out.append(row | {"q": q, "dof": len(v) - 1, "p_value": p, "i2_pct": i2})
    table = pd.DataFrame(out)
    table["disagree"] = holm_rejects(table["p_value"].to_numpy(float), 1 - confidence)
    return table


def holm_rejects(p_values: np.ndarray, level: float) -> np.ndarray:
    """Holm's step-down test of several hypotheses at the family-wise ``level`` [Holm 1979]:
    the i-th smallest p (i = 1…m over the finite ones) is rejected while
    p₍ᵢ₎ ≤ level/(m − i + 1); the first that is not stops it. Six coefficients tested one by
    one at 5 % would flag a study whose directions agree about a quarter of the time; Holm's
    test keeps that at most ``level``. NaN is never rejected.

    Holm 1979: Holm, S. A simple sequentially rejective multiple test procedure.
    *Scandinavian Journal of Statistics* **6**(2), 65–70."""
    p = np.asarray(p_values, float)
    out = np.zeros(p.shape, bool)
    idx = np.flatnonzero(np.isfinite(p))
    m = idx.size
    for i, k in enumerate(idx[np.argsort(p[idx], kind="stable")]):
        if p[k] > level / (m - i):
            break
        out[k] = True
    return out
