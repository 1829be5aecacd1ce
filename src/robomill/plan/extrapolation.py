"""Where the study does not reach: which candidates are extrapolated, why, and how their
intervals widen.

A candidate is *extrapolated* when (bit of ``extrapolation_code``):

* 1 ``spindle speed``: its speed lies outside the identifying cuts' speeds;
* 2 ``feed per tooth``: its chip load lies outside theirs;
* 4 ``radial immersion``: the request's immersion lies outside theirs;
* 8 ``pose``: its placement lies farther than the request's
  ``extrapolation.max_pose_distance_mm`` from every study cut's midpoint;
* 16 ``modal band``: its tooth-passing frequency or one of its first
  ``extrapolation.harmonics`` harmonics lies above the impact test's band, where the
  structure's modes were not measured.

The stated widening rule: an extrapolated prediction's interval half-widths (force,
deflection, critical depth on each side of the nominal) are multiplied by ``2 (1 + e)``, e the
largest relative excess of speed, chip load or immersion beyond the identified range (0 for a
pose or band reason alone). Above the modal band, the pessimistic critical depth is instead
at most the *absolute* stability limit of the measured modes at that pose (the lowest
point of their lobes at any speed, :func:`absolute_depth_m`, times the lobes' smallest ratio
of pessimistic to nominal depth over the request's speeds at that pose): an unmeasured mode
as flexible as the measured ones may put a lobe's minimum at this speed, so no stable pocket
between lobes (nor "no chatter at any depth") is claimed there; the factor then applies to
the critical depth only for a speed, chip-load, immersion or pose reason beside the band.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from robomill.chatter.lobes_zoa import oriented_eigenvalues
from robomill.chatter.model import CuttingModel
from robomill.plan.lobes import frequency_grid, receptance
from robomill.xrvars import var

REASONS = {1: "spindle speed", 2: "feed per tooth", 4: "radial immersion", 8: "pose",
           16: "modal band"}
"""Bit of ``extrapolation_code`` → its reason."""


@dataclass(frozen=True)
class StudyReach:
    """What the study measured: ranges of the identifying cuts' spindle speed [rpm], feed per
    tooth [mm] and radial immersion, the study cuts' midpoints [mm] (base frame; None when
    not placed) and the impact test's band [Hz] (None without one)."""

    spindle_rpm: tuple[float, float] | None = None
    feed_per_tooth_mm: tuple[float, float] | None = None
    radial_immersion: tuple[float, float] | None = None
    midpoints_mm: np.ndarray | None = None
    modal_band_hz: tuple[float, float] | None = None


def reach_from_means(means, experiment: dict, midpoints_mm=None, modal_band_hz=None
                     ) -> StudyReach:
    """:class:`StudyReach` of ``results/forces/mean_forces.csv`` (its own ``spindle_rpm`` and
    ``radial_immersion`` columns, else the experiment's speed and slots)."""
    def rng(v):
        v = np.asarray(v, float)
        v = v[np.isfinite(v)]
        return (float(v.min()), float(v.max())) if v.size else None

    sp = fpt = ae = None
    if means is not None and len(means):
        fpt = rng(means["feed_per_tooth_mm"])
        sp = rng(means["spindle_rpm"] if "spindle_rpm" in means
                 else [experiment.get("spindle_rpm", np.nan)])
        ae = rng(means["radial_immersion"] if "radial_immersion" in means else [1.0])
    band = None if modal_band_hz is None else tuple(float(b) for b in modal_band_hz)
    mids = None if midpoints_mm is None else np.asarray(midpoints_mm, float).reshape(-1, 3)
    return StudyReach(sp, fpt, ae, mids, band)


def _excess(x, lo_hi, rtol: float = 1e-6):
    """Relative excess of ``x`` beyond ``[lo, hi]`` (0 inside or within ``rtol`` of an end;
    no range: 0)."""
    if lo_hi is None:
        return np.zeros(np.shape(x))
    lo, hi = lo_hi
    x = np.asarray(x, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(x > hi * (1 + rtol), (x - hi) / hi,
                        np.where(x < lo * (1 - rtol), (lo - x) / lo, 0.0))


def extrapolation_code(ds: xr.Dataset, req, reach: StudyReach, *, rtol: float = 1e-6
                       ) -> tuple[xr.DataArray, xr.DataArray]:
    """``extrapolation_code`` (bits of :data:`REASONS`) and the relative excess ``e`` over
    ``(placement, spindle_rpm, feed_mm_s)``."""
    n = ds["spindle_rpm"].values
    c = ds["feed_per_tooth_mm"].transpose("spindle_rpm", "feed_mm_s").values
    P = ds.sizes["placement"]
    e_n = _excess(n, reach.spindle_rpm, rtol)[:, None] + 0 * c
    e_c = _excess(c, reach.feed_per_tooth_mm, rtol)
    e_a = float(_excess(req.radial_immersion, reach.radial_immersion, rtol))
    code = (1 * (e_n > 0) + 2 * (e_c > 0) + 4 * (e_a > 0)).astype(np.int64)
    code = np.broadcast_to(code, (P,) + code.shape).copy()
    if reach.midpoints_mm is not None and len(reach.midpoints_mm):
        pts = np.stack([ds[f"placement_{a}_mm"].values for a in "xyz"], -1)
        d = np.linalg.norm(pts[:, None] - reach.midpoints_mm[None], axis=-1).min(1)
        lim = req.extrapolation.get("max_pose_distance_mm")
        if lim is not None:
            code |= np.where(d > lim, 8, 0)[:, None, None]
    if reach.modal_band_hz is not None:
        top = reach.modal_band_hz[1] * (1 + rtol)
        f_tp = n * req.flutes / 60.0
        above = int(req.extrapolation.get("harmonics", 1)) * f_tp > top
        code |= np.where(above, 16, 0)[None, :, None]
    excess = np.broadcast_to(np.maximum(np.maximum(e_n, e_c), e_a), code.shape)
    dims = ("placement", "spindle_rpm", "feed_mm_s")
    return (xr.DataArray(code, dims=dims), xr.DataArray(excess.copy(), dims=dims))


def reason_text(code: int) -> str:
    """``"spindle speed; modal band"`` for a code (empty for 0)."""
    return "; ".join(v for b, v in REASONS.items() if int(code) & b)


def absolute_depth_m(fn_hz, zeta, k_N_m, shape, cut: CuttingModel) -> np.ndarray:
    """Absolute stability limit ``(B,)`` [m] of B tool models: the lowest point of the
    zero-order lobes at any spindle speed, min over chatter frequencies ω of
    a_lim(ω) = (u² + v²)/(2u), 1/λ = u + jv the eigenvalues of W̄ G(jω) with u > 0 (Altintas &
    Budak 1995; Altintas 2012 §4.3; every lobe k reaches every a_lim(ω) at some speed)."""
    fn = np.atleast_2d(np.asarray(fn_hz, float))
    G = receptance(frequency_grid(fn, n=800, n_fine=150), fn, zeta, np.atleast_2d(k_N_m),
                   shape)
    lam = oriented_eigenvalues(cut.mean_matrix(), G)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / np.where(np.abs(lam) > 0, lam, np.nan)
        u, v = inv.real, inv.imag
        a = np.where(u > 0, (u**2 + v**2) / (2 * u), np.inf)
    return np.nan_to_num(a, nan=np.inf).min(axis=(1, 2))


def _np(da: xr.DataArray, dims) -> np.ndarray:
    """``da``'s values ordered and shaped to broadcast against ``dims`` (its dims among
    them)."""
    v = da.transpose(*[d for d in dims if d in da.dims]).values
    return v.reshape([da.sizes[d] if d in da.dims else 1 for d in dims])


def widen(ds: xr.Dataset, code: xr.DataArray, excess: xr.DataArray,
          a_abs_low_mm: xr.DataArray | None = None) -> xr.Dataset:
    """Apply the stated widening rule (module docstring) to the candidates' intervals and add
    ``extrapolation`` (bool), ``extrapolation_code``, ``extrapolation_excess`` and
    ``interval_widening`` (the factor)."""
    flagged = code > 0
    w = xr.where(flagged, 2.0 * (1.0 + excess), 1.0)
    out: dict[str, xr.DataArray] = {}

    def stretch(nom_name, low_name, high_name, w_):
        dims = ds[low_name].dims
        nom, fac = _np(ds[nom_name], dims), _np(w_, dims)
        lo, hi = ds[low_name].values, ds[high_name].values
        out[low_name] = ds[low_name].copy(data=np.maximum(nom + (lo - nom) * fac, 0.0))
        out[high_name] = ds[high_name].copy(data=nom + (hi - nom) * fac)

    # the force has no placement: the widest factor over the placements
    stretch("force_N", "force_low_N", "force_high_N", w.max("placement"))
    for ax in ("normal", "axial"):
        stretch(f"deflection_{ax}_um", f"deflection_{ax}_low_um", f"deflection_{ax}_high_um", w)
    adims = ds["a_crit_mm"].dims
    a_nom, a_lo, a_hi = (ds[k].values for k in ("a_crit_mm", "a_crit_low_mm", "a_crit_high_mm"))
    # the modal band has its own bound on the critical depth (the absolute limit below): the
    # factor widens it only for the other reasons
    w_depth = w if a_abs_low_mm is None else xr.where((code & ~16) > 0, w, 1.0)
    wa = _np(w_depth.max("feed_mm_s"), adims)
    with np.errstate(invalid="ignore"):
        ok_lo = np.isfinite(a_nom) & np.isfinite(a_lo)
        ok_hi = np.isfinite(a_nom) & np.isfinite(a_hi)
        lo = np.where(ok_lo, a_nom - (np.where(ok_lo, a_nom, 0) - np.where(ok_lo, a_lo, 0))
                      * wa, a_lo)
        hi = np.where(ok_hi, a_nom + (np.where(ok_hi, a_hi, 0) - np.where(ok_hi, a_nom, 0))
                      * wa, a_hi)
    if a_abs_low_mm is not None:
        band = _np((code & 16).max("feed_mm_s") > 0, adims)
        lo = np.where(band, np.minimum(lo, _np(a_abs_low_mm, adims)), lo)
    out["a_crit_low_mm"] = ds["a_crit_low_mm"].copy(data=np.maximum(lo, 0.0))
    out["a_crit_high_mm"] = ds["a_crit_high_mm"].copy(data=hi)
    for key in ("low", "high"):
        name = f"stability_margin_{key}"
        dims = ds[name].dims
        a = _np(out[f"a_crit_{key}_mm"], dims)
        with np.errstate(divide="ignore", invalid="ignore"):
            m = np.broadcast_to(a / _np(ds["depth_mm"], dims) - 1, ds[name].shape)
        out[name] = ds[name].copy(data=np.array(m))
    out["extrapolation"] = var(code.dims, flagged.values, "1", "prediction outside what the "
                               "study measured (extrapolation_code says why)")
    out["extrapolation_code"] = var(code.dims, code.values, "1", "bits: " + ", ".join(
        f"{b} {r}" for b, r in REASONS.items()))
    out["extrapolation_excess"] = var(code.dims, excess.values, "1", "largest relative "
                                      "excess beyond the identified ranges")
    out["interval_widening"] = var(code.dims, w.values, "1", "factor on the interval "
                                   "half-widths, 2 (1 + excess) when extrapolated")
    return ds.assign(out)


def reach_values(chosen, attrs: dict) -> dict:
    """The values chapter 7 states about the plan's reach: the intervals' nominal level [%],
    the impact test's band [Hz], the chosen cuts' tooth-passing frequencies [Hz] (from
    ``plan.csv``: ``tooth_passing_hz``), how many of the chosen cuts are extrapolated and
    for which reasons, how many reach above the band (``band_case``: ``above``, ``inside``
    or ``unknown`` without an impact test), and the widening rule."""
    band = np.atleast_1d(np.asarray(attrs.get("modal_band_hz", []), float))
    out = {"level_percent": 100 * float(attrs.get("interval_level", np.nan)),
           "n_cuts": len(chosen), "harmonics": int(attrs.get("extrapolation_harmonics", 1))}
    flagged = chosen["extrapolation"].astype(bool) if "extrapolation" in chosen else None
    out["n_extrapolated"] = int(flagged.sum()) if flagged is not None else 0
    reasons = sorted({x for r in chosen.get("extrapolation_reason", []) if isinstance(r, str)
                      for x in r.split("; ") if x})
    out["reasons"] = ", ".join(reasons) if reasons else "none"
    tp = chosen["tooth_passing_hz"].to_numpy(float) if "tooth_passing_hz" in chosen else []
    if len(tp):
        out["tooth_passing_min_hz"], out["tooth_passing_max_hz"] = float(min(tp)), float(max(tp))
    if band.size == 2 and np.all(np.isfinite(band)):
        out["band_low_hz"], out["band_high_hz"] = float(band[0]), float(band[1])
        above = [f for f in tp if out["harmonics"] * f > band[1]]
        out["n_above_band"] = len(above)
        out["band_case"] = "above" if above else "inside"
    else:
        out["band_case"] = "unknown"
    return out
