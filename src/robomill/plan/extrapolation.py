"""Where the study does not reach: which candidates are extrapolated, why, and how their
intervals widen with the distance from the evidence.

A candidate is *extrapolated* when (bit of ``extrapolation_code``):

* 1 ``spindle speed``: its speed lies outside the identifying cuts' speeds;
* 2 ``feed per tooth``: its chip load lies outside the range the cutting coefficients were
  identified on;
* 4 ``radial immersion``: the request's immersion lies outside theirs;
* 8 ``pose``: its placement lies farther than the request's
  ``extrapolation.max_pose_distance_mm`` from every study cut's midpoint;
* 32, 64, 128 ``direction not measured: X`` (``Y``, ``Z``): the impact test gave no mode
  along that base axis (its mode-shape components are empty in ``modes.csv``) and the
  candidate's cut frame (feed, wall normal, tool axis: the directions of its cutting force
  and of its predicted deflections) has a component along it. The stability and deflection
  models then carry the modes' shapes restricted to the measured axes
  (:func:`robomill.plan.tooltip.modes_arrays`): no identified mode along the unmeasured
  one. These bits widen nothing (there is no distance from the evidence to measure along an
  axis never excited); the flag and its reason say the prediction is extrapolated.

(Bit 16, ``modal band``, is no longer set: the modes above the impact test's band enter the
stability model as a stated prior with its interval, :mod:`robomill.plan.stability`.)

**The stated widening law.** Inside the covered range nothing widens. Outside, the relative
distance from the evidence is e = (x − x_max)/x_max above the range, (x_min − x)/x_min below
it (speed, chip load, immersion), and e = (d − d_lim)/d_lim for a placement at distance d from
the nearest study cut beyond d_lim = ``max_pose_distance_mm``; every interval's half-widths
are multiplied by

.. math:: w = 1 + e

e the largest relative distance of the candidate (force, deflection: every reason; the
critical depth: the speed and the pose, which the linear stability model depends on; its
members' log deviations from the nominal are multiplied by w,
:func:`robomill.plan.stability.widen_members`). The law is continuous: a speed 0.07 % beyond
the study's widens by 0.07 %.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from robomill.xrvars import var

AXIS_BITS = {"X": 32, "Y": 64, "Z": 128}
"""Bit of ``extrapolation_code`` for a base axis the impact test did not measure."""

REASONS = {1: "spindle speed", 2: "feed per tooth", 4: "radial immersion", 8: "pose",
           16: "modal band", **{b: f"direction not measured: {a}" for a, b in AXIS_BITS.items()}}
"""Bit of ``extrapolation_code`` → its reason."""

_AXIS_TOL = 1e-9
"""A cut-frame vector's component along an axis below this counts as none (cos 90°)."""


@dataclass(frozen=True)
class StudyReach:
    """What the study measured: ranges of the identifying cuts' spindle speed [rpm], feed per
    tooth [mm] and radial immersion, the study cuts' midpoints [mm] (base frame; None when
    not placed), the impact test's band [Hz] (None without one) and the base axes it did
    not measure (``"YZ"``; empty when every axis was measured or there is no test)."""

    spindle_rpm: tuple[float, float] | None = None
    feed_per_tooth_mm: tuple[float, float] | None = None
    radial_immersion: tuple[float, float] | None = None
    midpoints_mm: np.ndarray | None = None
    modal_band_hz: tuple[float, float] | None = None
    axes_not_measured: str = ""


def axes_not_measured(modes) -> str:
    """The base axes (``"YZ"``) along which ``modes.csv`` ``modes`` has no mode-shape
    component: its ``shape_x``/``shape_y``/``shape_z`` column missing or empty (NaN) for
    every mode, as the modal stage writes it for an axis the impact test did not both hit
    and measure (:func:`robomill.modal.layout.measured_directions`). Empty without modes."""
    if modes is None or not len(modes):
        return ""
    out = ""
    for a in "XYZ":
        col = f"shape_{a.lower()}"
        if col not in modes or not np.isfinite(np.asarray(modes[col], float)).any():
            out += a
    return out


def direction_axis_bits(direction_deg, not_measured: str) -> np.ndarray:
    """Bits (:data:`AXIS_BITS`) per feed direction ``(D,)``: the unmeasured axes of
    ``not_measured`` along which the cut frame's feed, wall normal or tool axis
    (:func:`robomill.plan.poses.cut_frames`) has a component."""
    from robomill.plan.poses import cut_frames

    frames = cut_frames(np.atleast_1d(np.asarray(direction_deg, float)))   # (D, 3, 3)
    touch = (np.abs(frames) > _AXIS_TOL).any(-1)                            # (D, axis)
    bits = np.zeros(len(frames), np.int64)
    for i, a in enumerate("XYZ"):
        if a in not_measured:
            bits |= np.where(touch[:, i], AXIS_BITS[a], 0)
    return bits


def reach_from_means(means, experiment: dict, midpoints_mm=None, modal_band_hz=None,
                     not_measured: str = "") -> StudyReach:
    """:class:`StudyReach` of ``results/forces/mean_forces.csv`` (its own ``spindle_rpm`` and
    ``radial_immersion`` columns, else the experiment's speed and slots); ``not_measured``
    the base axes the impact test did not measure (:func:`axes_not_measured`)."""
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
    return StudyReach(sp, fpt, ae, mids, band, str(not_measured or ""))


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
                       ) -> tuple[xr.DataArray, xr.DataArray, xr.DataArray]:
    """``extrapolation_code`` (bits of :data:`REASONS`), the largest relative distance ``e``
    from the evidence and that of the stability model (speed and pose only), each over
    ``(placement, spindle_rpm, feed_mm_s)``; with axes not measured the code is over
    ``(placement, direction, spindle_rpm, feed_mm_s)`` (their bits depend on the feed
    direction; the distances do not)."""
    n = ds["spindle_rpm"].values
    c = ds["feed_per_tooth_mm"].transpose("spindle_rpm", "feed_mm_s").values
    P = ds.sizes["placement"]
    e_n = _excess(n, reach.spindle_rpm, rtol)[:, None] + 0 * c
    e_c = _excess(c, reach.feed_per_tooth_mm, rtol)
    e_a = float(_excess(req.radial_immersion, reach.radial_immersion, rtol))
    code = (1 * (e_n > 0) + 2 * (e_c > 0) + 4 * (e_a > 0)).astype(np.int64)
    code = np.broadcast_to(code, (P,) + code.shape).copy()
    e_p = np.zeros(P)
    if reach.midpoints_mm is not None and len(reach.midpoints_mm):
        pts = np.stack([ds[f"placement_{a}_mm"].values for a in "xyz"], -1)
        d = np.linalg.norm(pts[:, None] - reach.midpoints_mm[None], axis=-1).min(1)
        lim = req.extrapolation.get("max_pose_distance_mm")
        if lim is not None:
            code |= np.where(d > lim, 8, 0)[:, None, None]
            e_p = np.where(d > lim, (d - lim) / max(float(lim), 1e-9), 0.0)
    e_p = e_p[:, None, None]
    excess = np.maximum(np.maximum(np.maximum(e_n, e_c), e_a)[None], e_p)
    excess_stab = np.broadcast_to(np.maximum(e_n[None], e_p), code.shape)
    dims = ("placement", "spindle_rpm", "feed_mm_s")
    if reach.axes_not_measured:
        bits = direction_axis_bits(ds["direction_deg"].values, reach.axes_not_measured)
        code_d = code[:, None] | bits[None, :, None, None]
        return (xr.DataArray(code_d, dims=("placement", "direction", "spindle_rpm",
                                           "feed_mm_s")),
                xr.DataArray(excess.copy(), dims=dims),
                xr.DataArray(excess_stab.copy(), dims=dims))
    return (xr.DataArray(code, dims=dims), xr.DataArray(excess.copy(), dims=dims),
            xr.DataArray(excess_stab.copy(), dims=dims))


def reason_text(code: int) -> str:
    """``"spindle speed; direction not measured: Y, Z"`` for a code (empty for 0)."""
    parts = [v for b, v in REASONS.items() if int(code) & b and b not in AXIS_BITS.values()]
    axes = [a for a, b in AXIS_BITS.items() if int(code) & b]
    if axes:
        parts.append("direction not measured: " + ", ".join(axes))
    return "; ".join(parts)


def _np(da: xr.DataArray, dims) -> np.ndarray:
    """``da``'s values ordered and shaped to broadcast against ``dims`` (its dims among
    them)."""
    v = da.transpose(*[d for d in dims if d in da.dims]).values
    return v.reshape([da.sizes[d] if d in da.dims else 1 for d in dims])


def widen(ds: xr.Dataset, code: xr.DataArray, excess: xr.DataArray,
          excess_stability: xr.DataArray | None = None) -> xr.Dataset:
    """Apply the stated widening law (module docstring) to the candidates' intervals and add
    ``extrapolation`` (bool), ``extrapolation_code``, ``extrapolation_excess`` and
    ``interval_widening`` (the factor 1 + e). The critical depth: its members widened
    (``a_crit_members_mm`` present: interval and ``p_stable`` recomputed from them), else
    its half-widths multiplied by the speed and pose factor."""
    from robomill.plan.stability import p_stable, summary, widen_members

    flagged = code > 0
    w = 1.0 + excess
    w_stab = 1.0 + (excess if excess_stability is None else excess_stability)
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
    wa = _np(w_stab.max("feed_mm_s"), adims)
    if "a_crit_members_mm" in ds and "member_weight" in ds:
        mem = widen_members(ds["a_crit_members_mm"].values, wa[None])
        wts = ds["member_weight"].values
        level = float(ds.attrs["interval_level"])  # predict_grid states the level it used
        sm = summary(mem, wts, level)
        out["a_crit_members_mm"] = ds["a_crit_members_mm"].copy(data=mem)
        reach_ok = np.isfinite(ds["a_crit_mm"].values)
        out["a_crit_low_mm"] = ds["a_crit_low_mm"].copy(data=np.where(reach_ok, sm["low"],
                                                                      np.nan))
        out["a_crit_high_mm"] = ds["a_crit_high_mm"].copy(data=np.where(reach_ok, sm["high"],
                                                                        np.nan))
        if "p_stable" in ds:
            pdims = ds["p_stable"].dims
            p = p_stable(mem[..., None], wts, ds["depth_mm"].values)
            p = np.where(np.isfinite(ds["a_crit_mm"].values)[..., None], p, np.nan)
            out["p_stable"] = ds["p_stable"].copy(data=p.reshape(ds["p_stable"].shape)
                                                  if pdims[-1] == "depth_mm" else p)
    else:
        a_nom, a_lo, a_hi = (ds[k].values for k in ("a_crit_mm", "a_crit_low_mm",
                                                     "a_crit_high_mm"))
        with np.errstate(invalid="ignore"):
            lo = np.where(np.isfinite(a_lo) & np.isfinite(a_nom), a_nom - (a_nom - a_lo) * wa,
                          a_lo)
            hi = np.where(np.isfinite(a_hi) & np.isfinite(a_nom), a_nom + (a_hi - a_nom) * wa,
                          a_hi)
        out["a_crit_low_mm"] = ds["a_crit_low_mm"].copy(data=np.maximum(lo, 0.0))
        out["a_crit_high_mm"] = ds["a_crit_high_mm"].copy(data=hi)
    for key in ("low", "high"):
        name = f"stability_margin_{key}"
        dims = ds[name].dims
        a = _np(out[f"a_crit_{key}_mm"], dims)
        with np.errstate(divide="ignore", invalid="ignore"):
            m = np.broadcast_to(a / _np(ds["depth_mm"], dims) - 1, ds[name].shape)
        out[name] = ds[name].copy(data=np.array(m))
    if excess.dims != code.dims:  # the directions' bits: the distances broadcast over them
        excess = excess.broadcast_like(code).transpose(*code.dims)
        w = (1.0 + excess)
    out["extrapolation"] = var(code.dims, flagged.values, "1", "prediction outside what the "
                               "study measured (extrapolation_code says why)")
    out["extrapolation_code"] = var(code.dims, code.values, "1", "bits: " + ", ".join(
        f"{b} {r}" for b, r in REASONS.items()))
    out["extrapolation_excess"] = var(code.dims, excess.values, "1", "largest relative "
                                      "distance beyond the identified ranges")
    out["interval_widening"] = var(code.dims, w.values, "1", "factor on the interval "
                                   "half-widths, 1 + the relative distance from the evidence")
    return ds.assign(out)


def reach_values(chosen, attrs: dict) -> dict:
    """The values chapter 7 states about the plan's reach: the intervals' nominal level [%],
    the impact test's band [Hz], the chosen cuts' tooth-passing frequencies [Hz] (from
    ``plan.csv``: ``tooth_passing_hz``), how many of the chosen cuts are extrapolated and
    for which reasons, how many reach above the band (``band_case``: ``above``, ``inside``
    or ``unknown`` without an impact test), the widening rule, and ``axes_not_measured`` /
    ``n_direction_not_measured``: the base axes the impact test measured no mode along that
    some chosen cut's frame has a component along, and how many chosen cuts that is."""
    band = np.atleast_1d(np.asarray(attrs.get("modal_band_hz", []), float))
    out = {"level_percent": 100 * float(attrs.get("interval_level", np.nan)),
           "n_cuts": len(chosen), "harmonics": int(attrs.get("extrapolation_harmonics", 1))}
    flagged = chosen["extrapolation"].astype(bool) if "extrapolation" in chosen else None
    out["n_extrapolated"] = int(flagged.sum()) if flagged is not None else 0
    reasons = sorted({x for r in chosen.get("extrapolation_reason", []) if isinstance(r, str)
                      for x in r.split("; ") if x})
    out["reasons"] = ", ".join(reasons) if reasons else "none"
    # the base axes along which some chosen cut's frame lies unmeasured (bits 32-128)
    out["axes_not_measured"] = ", ".join(sorted({a.strip() for r in reasons
                                                 if r.startswith("direction not measured: ")
                                                 for a in r.split(": ", 1)[1].split(",")}))
    out["n_direction_not_measured"] = sum(
        1 for r in chosen.get("extrapolation_reason", [])
        if isinstance(r, str) and "direction not measured" in r)
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
