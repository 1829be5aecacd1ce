"""Surface irregularities of the milled slots (thesis ch. 2): profile analysis.

A stylus profile ``z(x)`` [µm] sampled uniformly in ``x`` [mm] is

1. detrended (least-squares line removed: the stylus tilt, thesis §2.3, MATLAB ``detrend``);
2. split into waviness and roughness by the ISO 16610-21 Gaussian profile filter of cut-off
   ``λc`` (:func:`gaussian_filter`; the ends are handled by renormalizing the weights over the
   part of the kernel inside the profile, the zero-order end correction of ISO 16610-28, so
   that every sample is kept and a constant stays constant up to the ends);
3. characterized by the amplitude parameters Wt, Wq (waviness) and Rq, Ra, Rz (roughness)
   (ISO 4287), by the thesis spectra (eqs. 2.1–2.3, :func:`robomill.spectra.thesis_spectrum`)
   and by the RMS of the thesis' segment method (eq. 2.6 on segments averaged:
   :func:`robomill.spectra.segment_rms`): 2.5 mm segments for waviness (Table 2.1), 0.25 mm
   for roughness (Table 2.2);
4. searched for dominant spectral peaks, which :func:`attribute_mechanisms` classifies across
   the feeds of the same set and direction: a peak whose *spatial* frequency stays put when
   the feed changes is kinematic (it follows the joint positions: gears), one whose
   *temporal* frequency ``f_spatial · feed`` stays put is dynamic (it follows time: modes,
   tooth passing).

Everything here is a pure function on numpy / pandas / xarray objects.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from importlib import resources
from typing import Any

import numpy as np
import pandas as pd
import scipy.signal
import xarray as xr
import yaml

from robomill.spectra import (
    below_resolution,
    find_peaks_spectrum,
    segment_averaged_spectrum,
    segment_rms,
    thesis_spectrum,
)

ALPHA = float(np.sqrt(np.log(2.0) / np.pi))
"""ISO 16610-21 constant α = sqrt(ln 2 / π) (50 % transmission at the cut-off)."""

DIRECTION_ORDER = ("px", "py", "my")
"""Column order of the thesis tables within a set: +X, +Y, −Y."""

MECHANISMS = ("kinematic", "dynamic", "unclassified")

DEFAULTS: dict[str, Any] = {
    "lambda_c_mm": 0.5,
    "filter_end": "renormalize",
    "kernel_half_width_cutoffs": 1.0,
    "waviness_segment_mm": 2.5,
    "roughness_segment_mm": 0.25,
    "waviness_band_per_mm": [0.1, 2.0],
    "roughness_band_per_mm": [2.0, 200.0],
    "roughness_peak_segment_mm": 2.5,
    "n_peaks": 3,
    "peak_prominence_ratio": 5.0,
    "match_tolerance": 0.2,
    "min_feed_ratio": 1.5,
    "min_peak_cycles": 2.5,
    "waviness_plot_max_per_mm": 1.0,
    "roughness_plot_max_per_mm": 30.0,
}
"""Defaults of ``config.yaml: surface`` (the schema fills the same values)."""


def settings(section: Mapping[str, Any] | None) -> dict[str, Any]:
    """``surface`` settings with defaults filled."""
    return {**DEFAULTS, **dict(section or {})}


# ---- preprocessing and filtering ---------------------------------------------------------
def detrend_profile(z_um: np.ndarray, x_mm: np.ndarray | None = None
                    ) -> tuple[np.ndarray, float, float]:
    """Remove the least-squares line (stylus tilt) from a profile.

    Returns the detrended profile, the slope [µm/mm] and the offset [µm] removed (thesis
    §2.3: the measured profile is tilted with respect to the stylus path).
    """
    z = np.asarray(z_um, float)
    x = np.arange(z.size, dtype=float) if x_mm is None else np.asarray(x_mm, float)
    slope, offset = np.polyfit(x, z, 1)
    return z - (slope * x + offset), float(slope), float(offset)


def gaussian_weights(lambda_c_mm: float, dx_mm: float, half_width_cutoffs: float = 1.0
                     ) -> np.ndarray:
    """Sampled ISO 16610-21 weighting function, normalized to unit sum.

    .. math:: s(x) = \\frac{1}{α λ_c} \\exp\\left[-π \\left(\\frac{x}{α λ_c}\\right)^2\\right],
              \\quad α = \\sqrt{\\ln 2 / π}

    truncated at ``± half_width_cutoffs · λc`` (at ±λc the weight is 7e-7 of its peak).
    """
    n_half = int(np.ceil(half_width_cutoffs * lambda_c_mm / dx_mm))
    x = np.arange(-n_half, n_half + 1) * dx_mm
    s = np.exp(-np.pi * (x / (ALPHA * lambda_c_mm)) ** 2)
    return s / s.sum()


def gaussian_filter(z_um: np.ndarray, dx_mm: float, lambda_c_mm: float, *,
                    end: str = "renormalize", half_width_cutoffs: float = 1.0) -> np.ndarray:
    """ISO 16610-21 Gaussian mean line (the waviness profile) of ``z_um``.

    The amplitude transmission of the mean line is ``exp(−π (α λc / λ)²)``: 50 % at
    ``λ = λc``, → 1 for long waves. The roughness profile is ``z − mean line``.

    Parameters
    ----------
    end
        ``"renormalize"`` (default): near the ends the weights are renormalized over the part
        of the kernel that lies inside the profile (zero-order end correction, ISO 16610-28),
        so no sample is lost and a constant or slowly varying profile is passed unchanged up
        to the ends. ``"zero"``: the profile is zero-padded (the plain convolution; the mean
        line falls off within λc of each end).

    Examples
    --------
    >>> dx = 0.00125; x = np.arange(12000) * dx
    >>> w = gaussian_filter(np.sin(2 * np.pi * x / 0.25), dx, 0.25)
    >>> round(float(np.abs(w[4000:8000]).max()), 3)
    0.5
    """
    z = np.asarray(z_um, float)
    s = gaussian_weights(lambda_c_mm, dx_mm, half_width_cutoffs)
    if s.size > 2 * z.size:
        raise ValueError(f"profile of {z.size} samples is shorter than the filter kernel "
                         f"({s.size} samples for λc = {lambda_c_mm} mm)")
    num = scipy.signal.oaconvolve(z, s, mode="same")
    if end == "zero":
        return num
    if end != "renormalize":
        raise ValueError(f"end={end!r}: expected 'renormalize' or 'zero'")
    den = scipy.signal.oaconvolve(np.ones_like(z), s, mode="same")
    return num / den


def split_profile(z_um: np.ndarray, dx_mm: float, lambda_c_mm: float, **kw
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Waviness (Gaussian mean line) and roughness (the rest) of a detrended profile."""
    w = gaussian_filter(z_um, dx_mm, lambda_c_mm, **kw)
    return w, np.asarray(z_um, float) - w


def rz_um(r_um: np.ndarray, n_sampling: int) -> float:
    """Rz (ISO 4287): highest peak + deepest valley in each sampling length of
    ``n_sampling`` samples (λc), averaged over all complete sampling lengths."""
    r = np.asarray(r_um, float)
    m = r.size // n_sampling
    if m < 1:
        return float(r.max() - r.min())
    segs = r[: m * n_sampling].reshape(m, n_sampling)
    segs = segs - segs.mean(axis=1, keepdims=True)
    return float(np.mean(segs.max(axis=1) - segs.min(axis=1)))


def amplitude_parameters(waviness_um: np.ndarray, roughness_um: np.ndarray, dx_mm: float,
                         lambda_c_mm: float) -> dict[str, float]:
    """Wt (peak to valley), Wq (RMS) of the waviness; Rq (RMS), Ra (mean absolute), Rz of the
    roughness (ISO 4287, evaluation length = the whole profile) [µm]."""
    w = np.asarray(waviness_um, float) - np.mean(waviness_um)
    r = np.asarray(roughness_um, float) - np.mean(roughness_um)
    return {
        "Wt_um": float(w.max() - w.min()),
        "Wq_um": float(np.sqrt(np.mean(w**2))),
        "Rq_um": float(np.sqrt(np.mean(r**2))),
        "Ra_um": float(np.mean(np.abs(r))),
        "Rz_um": rz_um(r, max(int(round(lambda_c_mm / dx_mm)), 2)),
    }


# ---- one profile -------------------------------------------------------------------------
def _attrs(units: str, long_name: str) -> dict[str, str]:
    return {"units": units, "long_name": long_name}


def profile_peaks(ds: xr.Dataset, opts: Mapping[str, Any]) -> pd.DataFrame:
    """Dominant peaks of one analysed profile: waviness band from the whole-profile thesis
    spectrum (resolution fs/N), roughness band from the segment-averaged spectrum with
    ``roughness_peak_segment_mm`` segments (variance of a random-vibration spectrum reduced by
    averaging). ``amplitude_um`` is the sinusoid amplitude sqrt(2 P) at the peak bin.

    Sanity flag: ``resolution_per_mm`` is the bin spacing of the spectrum the peak was found
    in (1/L for waviness, 1/segment for roughness) and ``below_resolution`` marks a peak with
    fewer than ``min_peak_cycles`` periods in that length
    (:func:`robomill.spectra.below_resolution`)."""
    rows = []
    n, ratio = int(opts["n_peaks"]), float(opts["peak_prominence_ratio"])
    cycles = float(opts.get("min_peak_cycles", DEFAULTS["min_peak_cycles"]))
    for band, f_name, p_name in (("waviness", "f", "power"),
                                 ("roughness", "f_peak", "power_peak")):
        lo, hi = opts[f"{band}_band_per_mm"]
        f_axis = ds[f_name].values
        res = float(f_axis[1] - f_axis[0]) if f_axis.size > 1 else float("nan")
        for f, p in find_peaks_spectrum(f_axis, ds[p_name].values, fmin=lo, fmax=hi, n=n,
                                        prominence_ratio=ratio):
            rows.append({"band": band, "f_spatial_per_mm": f, "power_um2": p,
                         "resolution_per_mm": res,
                         "below_resolution": bool(below_resolution(f, res,
                                                                   min_cycles=cycles))})
    df = pd.DataFrame(rows, columns=["band", "f_spatial_per_mm", "power_um2",
                                     "resolution_per_mm", "below_resolution"])
    df["amplitude_um"] = np.sqrt(2.0 * df["power_um2"].astype(float))
    return df


def analyse_profile(x_mm: np.ndarray, z_um: np.ndarray, options: Mapping[str, Any] | None = None
                    ) -> xr.Dataset:
    """The whole chapter-2 analysis of one profile, as a labelled dataset.

    Variables: the measured, detrended, waviness and roughness profiles over ``x``; the
    whole-profile thesis amplitude/power spectra over ``f`` (eqs. 2.2, 2.3); the
    segment-averaged power of the waviness profile (``f_w``, 2.5 mm segments) and of the
    roughness profile (``f_r``, 0.25 mm segments); the segment-averaged power used for the
    roughness peaks (``f_peak``); scalars Wt, Wq, Rq, Ra, Rz, the segment-method RMS of
    waviness and roughness (Tables 2.1, 2.2), the whole-profile Parseval RMS (eq. 2.6), the
    removed tilt.
    """
    opts = settings(options)
    x = np.asarray(x_mm, float)
    dx = float(np.median(np.diff(x)))
    fs = 1.0 / dx
    lam = float(opts["lambda_c_mm"])
    zd, slope, offset = detrend_profile(z_um, x)
    w, r = split_profile(zd, dx, lam, end=opts["filter_end"],
                         half_width_cutoffs=float(opts["kernel_half_width_cutoffs"]))
    spec = thesis_spectrum(zd, fs)
    seg, capped = segment_lengths_mm(x.size * dx, opts)
    sw = segment_averaged_spectrum(w, fs, seg["waviness_segment_mm"])
    sr = segment_averaged_spectrum(r, fs, seg["roughness_segment_mm"])
    sp = segment_averaged_spectrum(zd, fs, seg["roughness_peak_segment_mm"])
    params = amplitude_parameters(w, r, dx, lam)
    ds = xr.Dataset(
        {
            "z_measured": ("x", np.asarray(z_um, float), _attrs("um", "measured profile")),
            "z": ("x", zd, _attrs("um", "detrended profile")),
            "waviness": ("x", w, _attrs("um", f"waviness profile (Gaussian, λc = {lam} mm)")),
            "roughness": ("x", r, _attrs("um", "roughness profile (detrended − waviness)")),
            "amplitude": ("f", spec.amplitude, _attrs("um", "normalized amplitude A(k), "
                                                          "one-sided (thesis eq. 2.2)")),
            "power": ("f", spec.power, _attrs("um^2", "normalized power P(k), one-sided "
                                                      "(thesis eq. 2.3)")),
            "power_waviness": ("f_w", sw.power, _attrs(
                "um^2", "segment-averaged power of the waviness profile")),
            "power_roughness": ("f_r", sr.power, _attrs(
                "um^2", "segment-averaged power of the roughness profile")),
            "power_peak": ("f_peak", sp.power, _attrs(
                "um^2", "segment-averaged power of the detrended profile (peak search)")),
        },
        coords={
            "x": ("x", x, _attrs("mm", "position along the profile")),
            "f": ("f", spec.f, _attrs("1/mm", "spatial frequency k·fs/N")),
            "f_w": ("f_w", sw.f, _attrs("1/mm", "spatial frequency (waviness segments)")),
            "f_r": ("f_r", sr.f, _attrs("1/mm", "spatial frequency (roughness segments)")),
            "f_peak": ("f_peak", sp.f, _attrs("1/mm", "spatial frequency (peak segments)")),
        },
    )
    scalars = {
        **{k: (v, "um", k.split("_")[0] + " (ISO 4287)") for k, v in params.items()},
        "waviness_rms_um": (segment_rms(w, fs, seg["waviness_segment_mm"]), "um",
                            "RMS of waviness, segment method (Table 2.1)"),
        "roughness_rms_um": (segment_rms(r, fs, seg["roughness_segment_mm"]), "um",
                             "RMS of roughness, segment method (Table 2.2)"),
        "parseval_rms_um": (float(np.sqrt(spec.power.sum())), "um",
                            "RMS of the detrended profile by Parseval (eq. 2.6)"),
        "tilt_um_per_mm": (slope, "um/mm", "stylus tilt removed by detrending"),
        "offset_um": (offset, "um", "offset removed by detrending"),
        "fs_per_mm": (fs, "1/mm", "sampling frequency"),
        "lambda_c_mm": (lam, "mm", "Gaussian filter cut-off"),
    }
    for name, (value, units, long_name) in scalars.items():
        ds[name] = ((), float(value), _attrs(units, long_name))
    if capped:  # sanity flag: a profile shorter than the thesis' segments
        ds.attrs["segment_flag"] = (
            f"profile of {x.size * dx:.3g} mm is shorter than " + ", ".join(
                f"{k} {float(opts[k]):g} mm" for k in capped)
            + ": one segment of the whole profile used (not the thesis' segment method)")
    return ds


def segment_lengths_mm(length_mm: float, opts: Mapping[str, Any]) -> tuple[dict[str, float],
                                                                          list[str]]:
    """The segment lengths of the segment method (``waviness_segment_mm``,
    ``roughness_segment_mm``, ``roughness_peak_segment_mm``), each at most the profile's
    ``length_mm`` (a profile shorter than the thesis' 2.5 mm waviness segment, e.g. a
    microscope scan, is analysed as one segment rather than refused); and the keys that
    were capped (a sanity flag)."""
    keys = ("waviness_segment_mm", "roughness_segment_mm", "roughness_peak_segment_mm")
    asked = {k: float(opts[k]) for k in keys}
    return ({k: min(v, float(length_mm)) for k, v in asked.items()},
            [k for k, v in asked.items() if v > length_mm])


# ---- across cuts ---------------------------------------------------------------------------
def attribute_mechanisms(peaks: pd.DataFrame, cuts: pd.DataFrame, *, tolerance: float = 0.2,
                         min_feed_ratio: float = 1.5,
                         group_by: Sequence[str] = ("set", "direction")) -> pd.DataFrame:
    """Classify each peak as kinematic, dynamic or unclassified, with the evidence.

    For a peak at spatial frequency ``f`` in a cut at feed ``v``, every other cut of the same
    set and direction at a feed ``v'`` differing by at least ``min_feed_ratio`` (so that the
    two hypotheses predict different frequencies) is a witness. The kinematic hypothesis
    predicts a peak at ``f`` there, the dynamic one at ``f·v/v'`` (same temporal frequency).
    A witness supports a hypothesis when a peak of the same band lies within ``tolerance``
    (relative, in log frequency) of its prediction. The class is the hypothesis supported by
    more than half of the witnesses and by more witnesses than the other; otherwise
    ``unclassified`` (also when there is no witness).

    Parameters
    ----------
    peaks
        Columns ``cut, band, f_spatial_per_mm, amplitude_um``.
    cuts
        Columns ``cut, feed_mm_s`` and those of ``group_by``.
    group_by
        The columns a witness shares with the cut (the thesis: same set and direction; a free
        design: the same path direction, :func:`path_direction`).

    Returns
    -------
    DataFrame
        ``peaks`` plus ``feed_mm_s, f_temporal_hz, mechanism, n_witnesses,
        n_kinematic_support, n_dynamic_support``.
    """
    meta = cuts.set_index("cut")
    out = peaks.copy()
    out["feed_mm_s"] = [float(meta.loc[c, "feed_mm_s"]) for c in out["cut"]]
    out["f_temporal_hz"] = out["f_spatial_per_mm"] * out["feed_mm_s"]
    tol = np.log1p(tolerance)
    by_cut = {c: g for c, g in out.groupby("cut")}
    mech, n_w, n_k, n_d = [], [], [], []
    for _, p in out.iterrows():
        same = np.ones(len(meta), bool)
        for col in group_by:
            same &= (meta[col] == meta.loc[p["cut"], col]).to_numpy()
        others = meta[same & (meta.index != p["cut"])]
        w = k = dyn = 0
        for c2, m2 in others.iterrows():
            ratio = p["feed_mm_s"] / float(m2["feed_mm_s"])
            if abs(np.log(ratio)) < np.log(min_feed_ratio):
                continue
            w += 1
            g = by_cut.get(c2)
            if g is None:
                continue
            f2 = g.loc[g["band"] == p["band"], "f_spatial_per_mm"].to_numpy(float)
            if f2.size == 0:
                continue
            f = float(p["f_spatial_per_mm"])
            k += bool(np.min(np.abs(np.log(f2 / f))) <= tol)
            dyn += bool(np.min(np.abs(np.log(f2 / (f * ratio)))) <= tol)
        if w and k > w / 2 and k > dyn:
            mech.append("kinematic")
        elif w and dyn > w / 2 and dyn > k:
            mech.append("dynamic")
        else:
            mech.append("unclassified")
        n_w.append(w)
        n_k.append(k)
        n_d.append(dyn)
    out["mechanism"] = mech
    out["n_witnesses"] = n_w
    out["n_kinematic_support"] = n_k
    out["n_dynamic_support"] = n_d
    return out


def table_column(set_: int, direction: str) -> str:
    """Column name of the thesis tables: ``s{set}_{dir}``."""
    return f"s{int(set_)}_{direction}"


def rms_table(metrics: pd.DataFrame, value: str) -> pd.DataFrame:
    """A thesis-layout table (Table 2.1 / 2.2): rows ``segment`` 1–5, columns
    ``s1_px, s1_py, s1_my, s2_px, …`` (set-major, +X, +Y, −Y), values of column ``value``."""
    df = metrics.copy()
    df["column"] = [table_column(s, d) for s, d in zip(df["set"], df["direction"], strict=True)]
    tab = df.pivot_table(index="segment", columns="column", values=value, aggfunc="first")
    sets = sorted(df["set"].unique())
    cols = [table_column(s, d) for s in sets for d in DIRECTION_ORDER
            if table_column(s, d) in tab.columns]
    tab = tab[cols]
    tab.index = tab.index.astype(int)
    tab.index.name = "segment"
    tab.columns.name = None
    return tab


def load_thesis_tables() -> dict[str, pd.DataFrame]:
    """Thesis Tables 2.1 (waviness) and 2.2 (roughness) from the package data file
    ``robomill/data/thesis_tables_ch2.yaml``, in the layout of :func:`rms_table`."""
    text = resources.files("robomill.data").joinpath("thesis_tables_ch2.yaml").read_text()
    data = yaml.safe_load(text)
    out = {}
    for key in ("table_2_1_waviness_rms_um", "table_2_2_roughness_rms_um"):
        t = data[key]
        df = pd.DataFrame(t["values"], columns=t["columns"],
                          index=pd.Index(t["segments"], name="segment"))
        out[key] = df
    return out


def compare_with_thesis(ours: pd.DataFrame, thesis: pd.DataFrame, table: str,
                        factor: float = 1.5) -> pd.DataFrame:
    """Long comparison table: every cell present in both, ``pipeline_um, thesis_um, ratio``
    and whether the ratio lies within ``[1/factor, factor]``."""
    rows = []
    for seg in ours.index:
        for col in ours.columns:
            if seg in thesis.index and col in thesis.columns:
                a, b = float(ours.loc[seg, col]), float(thesis.loc[seg, col])
                rows.append({"table": table, "segment": int(seg), "column": col,
                             "pipeline_um": a, "thesis_um": b, "ratio": a / b,
                             f"within_{factor:g}x": bool(1 / factor <= a / b <= factor)})
    return pd.DataFrame(rows)


def spectra_dataset(per_cut: Sequence[xr.Dataset], cut_ids: Sequence[str]) -> xr.Dataset:
    """Stack the spectra of every cut along ``cut`` (profiles of equal length and sampling)."""
    keep = ["amplitude", "power", "power_waviness", "power_roughness"]
    ds = xr.concat([d[keep] for d in per_cut], dim="cut", coords="minimal",
                   compat="override", join="override")
    ds = ds.assign_coords(cut=("cut", list(cut_ids), _attrs("1", "cut identifier")))
    return ds


def recovery_table(metrics: pd.DataFrame, truth: xr.Dataset) -> pd.DataFrame:
    """Planted (``truth.nc``: ``surface_planted_*``) vs recovered segment RMS per cut."""
    t = truth[["surface_planted_waviness_rms_um", "surface_planted_roughness_rms_um"]]
    t = t.to_dataframe().reset_index().rename(columns={"surface_cut": "cut"})
    df = metrics[["cut", "waviness_rms_um", "roughness_rms_um"]].merge(t, on="cut")
    df["waviness_ratio"] = df["waviness_rms_um"] / df["surface_planted_waviness_rms_um"]
    df["roughness_ratio"] = df["roughness_rms_um"] / df["surface_planted_roughness_rms_um"]
    return df.rename(columns={"surface_planted_waviness_rms_um": "planted_waviness_rms_um",
                              "surface_planted_roughness_rms_um": "planted_roughness_rms_um"})


#: per-cut scalars gathered into results/surface/metrics.csv (one column each)
METRIC_COLUMNS = ("Wt_um", "Wq_um", "Rq_um", "Ra_um", "Rz_um", "waviness_rms_um",
                  "roughness_rms_um", "parseval_rms_um", "tilt_um_per_mm")
#: results/surface/peaks.csv columns
PEAK_TABLE_COLUMNS = ["cut", "f_spatial_per_mm", "f_temporal_hz", "amplitude_um", "mechanism",
                      "band", "feed_mm_s", "power_um2", "n_witnesses", "n_kinematic_support",
                      "n_dynamic_support", "resolution_per_mm", "below_resolution"]


#: design keys of a cut, in the order the per-design table groups by them
DESIGN_KEYS = ("path_direction", "spindle_rpm", "flutes", "tool_diameter_mm",
               "radial_immersion", "milling", "depth_mm", "feed_mm_s")


def path_direction(direction: str | None, direction_deg: float | None) -> str:
    """One label per feed direction: the name (``px``, ``mx``, ``py``, ``my``) or
    ``"<deg> deg"`` for a ``direction_deg`` cut."""
    if direction_deg is not None and not pd.isna(direction_deg):
        return f"{float(direction_deg):g} deg"
    return str(direction)


def design_table(metrics: pd.DataFrame,
                 values: Sequence[str] = ("waviness_rms_um", "roughness_rms_um", "Wq_um",
                                          "Rq_um")) -> pd.DataFrame:
    """The per-cut table of a design other than the thesis' (``metrics_by_design.csv``).

    The design keys that vary across the cuts (of :data:`DESIGN_KEYS`) come first, in that
    order, and the rows are sorted by them (so the cuts of a spindle-speed series at one
    direction sit together, in increasing speed), then ``cut``, ``feed_per_tooth_mm``,
    ``tooth_passing_hz`` and ``values``. A key that every cut shares is left out (it is one
    value of the experiment).
    """
    varying = [k for k in DESIGN_KEYS if k in metrics and metrics[k].nunique(dropna=False) > 1]
    cols = varying + ["cut", "feed_per_tooth_mm", "tooth_passing_hz", *values]
    tab = metrics[[c for c in cols if c in metrics]]
    return tab.sort_values(varying + ["cut"] if varying else ["cut"], kind="stable"
                           ).reset_index(drop=True)


def gather_surface(per_cut: Sequence[xr.Dataset], cuts: pd.DataFrame,
                   peaks: Sequence[pd.DataFrame], options: Mapping[str, Any], *,
                   processes: Mapping[str, Mapping[str, Any]] | None = None
                   ) -> dict[str, Any]:
    """Gather the per-cut profile analyses into the chapter-2 artefacts.

    Parameters
    ----------
    per_cut
        :func:`analyse_profile` datasets, each with ``attrs["cut"]`` (any order).
    cuts
        The study plan, one row per cut (``cut``, ``set``, ``segment``, ``direction``,
        ``feed_mm_s``, ``depth_mm``, …).
    peaks
        :func:`profile_peaks` tables of the cuts (with a ``cut`` column).
    options
        :func:`settings` (``match_tolerance``, ``min_feed_ratio``).
    processes
        For a design other than the thesis' (:func:`robomill.experiment.is_thesis_design`):
        cut id → :func:`robomill.experiment.cut_process` (the cut's own speed, flutes, feed per
        tooth, tooth passing, immersion, milling mode, direction). Then there are no thesis
        tables and no thesis comparison: ``by_design`` (:func:`design_table`) instead;
        ``metrics`` gains the process columns and ``path_direction``, the peaks are attributed
        among the cuts of the same path direction and gain ``tooth_passing_hz`` and
        ``tooth_passing_order`` (f_temporal / the cut's own tooth passing: an integer for
        feed marks).

    Returns
    -------
    dict
        ``metrics`` (one row per cut, plan order), ``waviness`` and ``roughness`` (Tables
        2.1/2.2 by the segment method, :func:`rms_table`), ``comparison`` (both against the
        thesis, :func:`compare_with_thesis`), ``peaks`` (with mechanism,
        :func:`attribute_mechanisms`), ``spectra`` (:func:`spectra_dataset`) and ``profiles``
        (measured, detrended, waviness and roughness along ``cut``, with the plan's
        ``feed_mm_s``, ``set``, ``segment``, ``direction``).
    """
    by_id = {c: i for i, c in enumerate(cuts["cut"])}
    unknown = [d.attrs.get("cut") for d in per_cut if d.attrs.get("cut") not in by_id]
    if unknown:
        raise ValueError(f"gather_surface: cut(s) {unknown} are not in the plan")
    per_cut = sorted(per_cut, key=lambda d: by_id[d.attrs["cut"]])
    ids = [d.attrs["cut"] for d in per_cut]
    metrics = pd.DataFrame([{"cut": c, **{k: float(d[k]) for k in METRIC_COLUMNS}}
                            for c, d in zip(ids, per_cut, strict=True)])
    grouping = [k for k in ("set", "segment") if k in cuts and cuts[k].notna().all()]
    if processes is None:
        metrics = metrics.merge(cuts[["cut", "set", "segment", "direction", "feed_mm_s",
                                      "depth_mm"]], on="cut")
    else:
        cuts = cuts.copy()
        none = [None] * len(cuts)
        cuts["path_direction"] = [path_direction(d, g) for d, g in
                                  zip(cuts.get("direction", none),
                                      cuts.get("direction_deg", none), strict=True)]
        proc_cols = ("spindle_rpm", "flutes", "tool_diameter_mm", "radial_immersion",
                     "milling", "direction_deg", "feed_per_tooth_mm", "tooth_passing_hz")
        for k in proc_cols:
            cuts[k] = [processes[c][k] for c in cuts["cut"]]
        metrics = metrics.merge(cuts[["cut", *grouping, "path_direction", "feed_mm_s",
                                      "depth_mm", *proc_cols]], on="cut")
    out: dict[str, Any] = {"metrics": metrics}
    if processes is None:
        thesis = load_thesis_tables()
        comparisons = []
        for name, key, value in (("waviness", "table_2_1_waviness_rms_um", "waviness_rms_um"),
                                 ("roughness", "table_2_2_roughness_rms_um",
                                  "roughness_rms_um")):
            out[name] = rms_table(metrics, value)
            comparisons.append(compare_with_thesis(out[name], thesis[key], key))
        out["comparison"] = pd.concat(comparisons, ignore_index=True)
    else:
        out["by_design"] = design_table(metrics)
    found = attribute_mechanisms(pd.concat(list(peaks), ignore_index=True), cuts,
                                 tolerance=float(options["match_tolerance"]),
                                 min_feed_ratio=float(options["min_feed_ratio"]),
                                 group_by=("set", "direction") if processes is None
                                 else ("path_direction",))
    out["peaks"] = found[PEAK_TABLE_COLUMNS]
    if processes is not None:
        tp = np.array([float(processes[c]["tooth_passing_hz"]) for c in found["cut"]])
        out["peaks"] = out["peaks"].assign(tooth_passing_hz=tp,
                                           tooth_passing_order=found["f_temporal_hz"] / tp)
    out["spectra"] = spectra_dataset(per_cut, ids)
    keep = ["z_measured", "z", "waviness", "roughness"]
    profiles = xr.concat([d[keep].astype("float32") for d in per_cut], dim="cut",
                         join="override", compat="override", coords="minimal")
    for k in keep:
        profiles[k].attrs = per_cut[0][k].attrs
    profiles = profiles.assign_coords(cut=("cut", ids, {"units": "1", "long_name": "cut"}))
    plan = cuts.set_index("cut").loc[ids]
    cols = [("feed_mm_s", "mm/s"), ("set", "1"), ("segment", "1"), ("direction", "1")]
    if processes is not None:
        cols = [(c, u) for c, u in cols if c not in ("set", "segment") or c in grouping]
        cols[-1] = ("path_direction", "1")
    for col, units in cols:
        profiles[col] = ("cut", plan[col].to_numpy(), {"units": units, "long_name": col})
    out["profiles"] = profiles
    return out


def direction_means(metrics: pd.DataFrame) -> pd.DataFrame:
    """Mean waviness and roughness RMS per cut direction (thesis §2.3: X smallest, +Y
    largest).

    Parameters
    ----------
    metrics
        ``results/surface/metrics.csv`` (``direction, waviness_rms_um, roughness_rms_um``).

    Returns
    -------
    pandas.DataFrame
        Index ``direction``; ``waviness_rms_um, roughness_rms_um`` (means over the cuts of
        that direction, µm) and ``n_cuts``.
    """
    g = metrics.groupby("direction")
    out = g[["waviness_rms_um", "roughness_rms_um"]].mean()
    out["n_cuts"] = g.size()
    return out


def feed_correlation(metrics: pd.DataFrame) -> pd.Series:
    """Pearson correlation of the waviness and roughness RMS with the feed over every cut
    (thesis §2.3: a higher feed raises the amplitude).

    Returns
    -------
    pandas.Series
        ``waviness`` and ``roughness``: ``r = cov(v, RMS)/(σ_v σ_RMS)``; NaN with fewer than
        two cuts or no spread in the feed.
    """
    def r(col: str) -> float:
        if len(metrics) < 2 or metrics["feed_mm_s"].nunique() < 2:
            return float("nan")
        return float(np.corrcoef(metrics["feed_mm_s"], metrics[col])[0, 1])

    return pd.Series({"waviness": r("waviness_rms_um"), "roughness": r("roughness_rms_um")})


def comparison_summary(comparison: pd.DataFrame) -> pd.DataFrame:
    """How many cells of each thesis table the pipeline reproduces within a factor 1.5.

    Parameters
    ----------
    comparison
        ``results/surface/thesis_comparison.csv`` (``table, ratio, within_1.5x``).

    Returns
    -------
    pandas.DataFrame
        Index ``table``; ``within`` (cells within 1.5×), ``cells`` and ``median_ratio``
        (median of pipeline/thesis).
    """
    g = comparison.groupby("table")
    return pd.DataFrame({"within": g["within_1.5x"].sum().astype(int),
                         "cells": g.size(), "median_ratio": g["ratio"].median()})
