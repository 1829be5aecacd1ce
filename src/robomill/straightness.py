"""Path straightness of the robot (thesis §3.2): spatial re-ordering, PSD, gear attribution.

A laser tracker samples the TCP while the robot moves along a straight cut path (no
cutting). The analysis

1. re-orders the time series in space (:func:`spatial_profile`): the best straight line is
   fitted to the points, each point gets its distance ``s`` along that line and its
   deviation perpendicular to it (a *lateral* horizontal and a *vertical* component), and
   the profile is resampled on a uniform grid of ``s``;
2. computes its spectrum in mm⁻¹ (:func:`profile_spectrum`, thesis eqs. 2.1–2.3 on a
   Hann-windowed, zero-padded profile so that peak amplitudes are those of sinusoids);
3. computes the spatial frequency of every rotating gear element during the run
   (:func:`gear_spatial_frequencies`): revolutions per mm of path, from the joint rates along
   the path (Slamani & Bonev 2013): ``f = r · |dq/ds| / 2π`` for the once-per-revolution
   (runout) order and ``z`` times that for the tooth-mesh order. On a straight path the
   joint angles depend on the position only, so this does not depend on the feed;
4. matches spectral peaks to gears within a tolerance tied to the frequency resolution
   ``1/L`` (:func:`match_peaks_to_gears`), and
5. separates constant-*temporal*-frequency peaks (a servo ripple at 13 Hz: its wavelength
   grows with feed) from constant-*spatial*-frequency ones using the runs at several feeds
   (:func:`classify_peaks`).

All functions are pure (numpy / pandas / xarray in, out); readers and writers live in
:mod:`robomill.io`.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
import scipy.signal
import xarray as xr

from robomill import spectra
from robomill.kinematics import SerialRobot

COMPONENTS = ("lateral", "vertical")
"""Perpendicular deviation components: horizontal (Z × path direction) and vertical."""

ORDERS = ("runout", "mesh")
"""Gear error orders: once per revolution (eccentricity) and tooth mesh (teeth per rev)."""

MECHANISMS = ("gear", "temporal", "spatial", "unclassified")
"""Peak mechanisms: matched to a gear; constant temporal frequency across feeds; constant
spatial frequency but no gear; not classifiable (seen at one feed only, no gear)."""


# ---------------------------------------------------------------------------------------------
# 1. spatial re-ordering
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Profile:
    """A straightness profile re-ordered in space.

    Attributes
    ----------
    s_mm
        Uniform abscissa along the best line, from the first sample's projection [mm].
    deviation_um
        ``(2, n)`` perpendicular deviation from the best line [µm], rows ``COMPONENTS``.
    start_mm, end_mm
        The best line's points at the start and the end of the motion [mm] (3-vectors).
    direction
        Unit vector of the motion along the best line.
    ds_mm
        Grid step [mm].
    speed_mm_s
        Median speed along the line (from the raw samples) [mm/s].
    """

    s_mm: np.ndarray
    deviation_um: np.ndarray
    start_mm: np.ndarray
    end_mm: np.ndarray
    direction: np.ndarray
    ds_mm: float
    speed_mm_s: float
    trim_mm: float = 0.0
    """Length dropped at each end [mm] (``trim_mm`` asked, at most
    :data:`TRIM_MAX_FRACTION` of the path)."""

    @property
    def length_mm(self) -> float:
        return float(self.s_mm[-1] - self.s_mm[0] + self.ds_mm)


def fit_line(points_mm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Best (total least squares) straight line through ``points_mm`` ``(n, 3)``.

    Returns the centroid and the unit direction (first right singular vector of the centred
    points), which minimises the sum of squared perpendicular distances.
    """
    p = np.asarray(points_mm, float)
    c = p.mean(axis=0)
    _, _, vt = np.linalg.svd(p - c, full_matrices=False)
    return c, vt[0]


def perpendicular_axes(direction: np.ndarray) -> np.ndarray:
    """``(2, 3)`` unit vectors perpendicular to ``direction``: lateral (horizontal, Z × u) and
    vertical (completing the right-handed set u, lateral, vertical; +Z-ish for a horizontal
    path). For a vertical path the lateral axis falls back to X × u."""
    u = np.asarray(direction, float) / np.linalg.norm(direction)
    lat = np.cross([0.0, 0.0, 1.0], u)
    if np.linalg.norm(lat) < 1e-6:
        lat = np.cross([1.0, 0.0, 0.0], u)
    lat /= np.linalg.norm(lat)
    vert = np.cross(u, lat)
    return np.stack([lat, vert])


def resample_uniform(s: np.ndarray, y: np.ndarray, ds: float,
                     s0: float | None = None, s1: float | None = None) -> tuple[np.ndarray,
                                                                                np.ndarray]:
    """Resample ``y(s)`` (``s`` sorted, ``y`` ``(..., n)``) on a uniform grid of step ``ds``.

    Where the samples are denser than the grid they are averaged per grid cell (a boxcar
    anti-alias filter, so noise is not folded back); empty cells are linearly interpolated
    from their neighbours.
    """
    s = np.asarray(s, float)
    y = np.atleast_2d(np.asarray(y, float))
    s0 = s[0] if s0 is None else s0
    s1 = s[-1] if s1 is None else s1
    n = int(np.floor((s1 - s0) / ds)) + 1
    grid = s0 + ds * np.arange(n)
    idx = np.clip(np.round((s - s0) / ds).astype(int), 0, n - 1)
    count = np.bincount(idx, minlength=n)
    out = np.empty((y.shape[0], n))
    filled = count > 0
    for k in range(y.shape[0]):
        mean = np.bincount(idx, weights=y[k], minlength=n)[filled] / count[filled]
        out[k] = np.interp(grid, grid[filled], mean)
    return grid, out


TRIM_MAX_FRACTION = 0.1
"""The end trim (speed ramps) takes at most this share of the path at each end (assumed:
10 %), so that a short record (a tracker export of a few mm) keeps 80 % of its path instead
of being refused; the 40 mm thesis runs trim the full ``trim_mm``."""


def spatial_profile(t_s: np.ndarray, points_mm: np.ndarray, *, ds_mm: float,
                    trim_mm: float = 0.0, detrend_order: int = 1) -> Profile:
    """Re-order a tracker time series in space (thesis §3.2).

    Parameters
    ----------
    t_s
        Sample times [s], increasing.
    points_mm
        ``(n, 3)`` measured positions [mm].
    ds_mm
        Step of the uniform spatial grid [mm].
    trim_mm
        Length dropped at each end of the path (acceleration/deceleration) [mm], at most
        ``TRIM_MAX_FRACTION`` of the path (a shorter trim is logged by the rule).
    detrend_order
        Degree of the polynomial removed from each resampled component (1: the best line
        only, as the thesis; 3 also removes components with less than about one cycle over
        the record, whose spectral leakage would otherwise raise false low-frequency peaks).

    Returns
    -------
    Profile
        Distance along the best line and the perpendicular deviation (lateral, vertical),
        resampled uniformly after removing the best line (the deviation has zero mean and no
        linear trend in either component by construction of the total-least-squares line).

    Notes
    -----
    ``s_k = (p_k − c)·u`` with c, u the centroid and direction of the best line; the
    deviation is ``(p_k − c) − s_k u`` projected on the two perpendicular axes. The samples
    are sorted by ``s`` (space order), whatever their time order.
    """
    t = np.asarray(t_s, float)
    p = np.asarray(points_mm, float)
    c, u = fit_line(p)
    s = (p - c) @ u
    if np.polyfit(t, s, 1)[0] < 0:  # orient the line along the motion
        u, s = -u, -s
    axes = perpendicular_axes(u)
    dev = ((p - c) @ axes.T).T * 1e3  # (2, n) µm
    order = np.argsort(s, kind="stable")
    s, dev = s[order], dev[:, order]
    trim_mm = min(float(trim_mm), TRIM_MAX_FRACTION * float(s[-1] - s[0]))
    s0, s1 = s[0] + trim_mm, s[-1] - trim_mm
    if s1 - s0 < 4 * ds_mm:
        raise ValueError(f"path of {s[-1] - s[0]:.3g} mm is too short for the grid step "
                         f"{ds_mm} mm after trimming {trim_mm:.3g} mm at each end")
    keep = (s >= s0 - ds_mm) & (s <= s1 + ds_mm)
    grid, dev_u = resample_uniform(s[keep], dev[:, keep], ds_mm, s0, s1)
    # remove what is left of the line on the trimmed span (and, with detrend_order > 1, the
    # slowest curvature), per component
    x = np.linspace(-1.0, 1.0, grid.size)
    V = np.polynomial.legendre.legvander(x, int(detrend_order))
    coef, *_ = np.linalg.lstsq(V, dev_u.T, rcond=None)
    dev_u = dev_u - (V @ coef).T
    speed = _speed(t, (p - c) @ u)
    return Profile(s_mm=grid - grid[0], deviation_um=dev_u, start_mm=c + s0 * u,
                   end_mm=c + s1 * u, direction=u, ds_mm=float(ds_mm), speed_mm_s=speed,
                   trim_mm=trim_mm)


def _speed(t: np.ndarray, s: np.ndarray) -> float:
    """Median speed along the line over lags of 1/50 of the record (robust to noise)."""
    lag = max(1, t.size // 50)
    return float(np.median(np.abs(s[lag:] - s[:-lag]) / (t[lag:] - t[:-lag])))


# ---------------------------------------------------------------------------------------------
# 2. spectrum in mm⁻¹
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ProfileSpectrum:
    """Spectrum of a straightness profile (one-sided)."""

    f_per_mm: np.ndarray
    """Frequency grid (zero-padded: ``pad`` points per resolution bin 1/L) [mm⁻¹]."""
    amplitude_um: np.ndarray
    """``(2, nf)`` sinusoid amplitude per component (Hann, amplitude-corrected) [µm]."""
    power_um2: np.ndarray
    """``(nf,)`` power of the perpendicular deviation, lateral + vertical, A²/2 [µm²]."""
    psd_um2_mm: np.ndarray
    """``(nf,)`` power spectral density of the perpendicular deviation [µm²·mm]."""
    resolution_per_mm: float
    """Frequency resolution 1/L of the record [mm⁻¹]."""


def profile_spectrum(profile: Profile, *, nfft: int | None = None,
                     pad: int = 8) -> ProfileSpectrum:
    """Amplitude and power spectra of a profile in mm⁻¹ (thesis eqs. 2.1–2.3).

    The profile is multiplied by a Hann window, zero-padded to ``nfft`` points (default
    ``pad × n`` rounded up to a power of two) and transformed with
    :func:`robomill.spectra.thesis_spectrum`; the amplitudes are divided by the window's
    coherent gain (mean of the window), so a sinusoid of amplitude ``a`` gives a peak of
    height ``a`` (within 0.1 % with 8× padding). ``power_um2 = Σ_components A²/2`` and the
    PSD is ``power / ENBW`` with the Hann equivalent noise bandwidth ``1.5/L``.
    """
    dev = profile.deviation_um
    n = dev.shape[-1]
    if nfft is None:
        nfft = int(2 ** np.ceil(np.log2(pad * n)))
    if nfft < n:
        raise ValueError(f"nfft={nfft} is shorter than the profile ({n} samples)")
    w = scipy.signal.get_window("hann", n, fftbins=True)
    padded = np.zeros((dev.shape[0], nfft))
    padded[:, :n] = dev * w
    spec = spectra.thesis_spectrum(padded, fs=1.0 / profile.ds_mm)
    amp = spec.amplitude * nfft / n / w.mean()
    power = 0.5 * (amp**2).sum(axis=0)
    length = n * profile.ds_mm
    enbw = n * np.sum(w**2) / np.sum(w) ** 2 / length
    return ProfileSpectrum(spec.f, amp, power, power / enbw, 1.0 / length)


def spectrum_peaks(spec: ProfileSpectrum, *, fmin_per_mm: float, fmax_per_mm: float,
                   threshold: float, n_peaks: int) -> pd.DataFrame:
    """Peaks of the combined perpendicular power within [fmin, fmax].

    A peak must exceed ``threshold`` × the median power of the band (the noise floor; uses
    :func:`robomill.spectra.find_peaks_spectrum`). Local maxima are searched from two
    resolution bins below ``fmin`` (so a peak right at the band edge is still a local
    maximum) and kept from ``fmin`` up. Returns ``f_spatial_per_mm``,
    ``amplitude_um`` (``sqrt(2·power)``: the amplitude of the perpendicular oscillation),
    ``component`` (the larger of lateral/vertical) and ``snr`` (power / floor).
    """
    sel = (spec.f_per_mm >= fmin_per_mm) & (spec.f_per_mm <= fmax_per_mm)
    floor = float(np.median(spec.power_um2[sel])) if sel.any() else np.nan
    low = max(0.0, fmin_per_mm - 2 * spec.resolution_per_mm)
    found = spectra.find_peaks_spectrum(spec.f_per_mm, spec.power_um2, fmin=low,
                                        fmax=fmax_per_mm, n=n_peaks + 2,
                                        prominence_ratio=threshold * floor / np.median(
                                            spec.power_um2[(spec.f_per_mm >= low)
                                                           & (spec.f_per_mm <= fmax_per_mm)]))
    found = [(f, p) for f, p in found if f >= fmin_per_mm][:n_peaks]
    rows = []
    for f, p in found:
        k = int(np.argmin(np.abs(spec.f_per_mm - f)))
        comp = COMPONENTS[int(np.argmax(spec.amplitude_um[:, k]))]
        rows.append({"f_spatial_per_mm": f, "amplitude_um": float(np.sqrt(2 * p)),
                     "component": comp, "snr": p / floor})
    return pd.DataFrame(rows, columns=["f_spatial_per_mm", "amplitude_um", "component", "snr"])


# ---------------------------------------------------------------------------------------------
# 3. gear spatial frequencies
# ---------------------------------------------------------------------------------------------
def _gear_field(g: Any, name: str) -> Any:
    return g[name] if isinstance(g, Mapping) else getattr(g, name)


def gear_orders(gears: Sequence[Any]) -> Iterator[tuple[int, str, str, float]]:
    """``(joint, stage, order, multiplier)`` for every gear and order: ``runout`` turns
    ``r`` times per joint revolution, ``mesh`` ``r z`` times (SPEC §3.2)."""
    for g in gears:
        r = float(_gear_field(g, "rev_per_joint_rev"))
        z = int(_gear_field(g, "teeth"))
        joint, stage = int(_gear_field(g, "joint")), str(_gear_field(g, "stage"))
        yield joint, stage, "runout", r
        yield joint, stage, "mesh", r * z


def joint_path_for_line(robot: SerialRobot, start_mm: np.ndarray, end_mm: np.ndarray,
                        rotation: np.ndarray, q0_rad: np.ndarray,
                        n_points: int = 41) -> tuple[np.ndarray, np.ndarray]:
    """Joint angles ``(n_points, n)`` along a straight TCP line at a fixed tool orientation
    (inverse kinematics, each solution seeding the next); also returns the abscissa [mm]."""
    a, b = np.asarray(start_mm, float), np.asarray(end_mm, float)
    s = np.linspace(0.0, float(np.linalg.norm(b - a)), n_points)
    u = (b - a) / np.linalg.norm(b - a)
    T = np.broadcast_to(np.eye(4), (n_points, 4, 4)).copy()
    T[:, :3, :3] = rotation
    T[:, :3, 3] = a + np.outer(s, u)
    return robot.ik_path(T, q0_rad), s


def gear_spatial_frequencies(q_rad: np.ndarray, s_mm: np.ndarray,
                             gears: Sequence[Any]) -> pd.DataFrame:
    """Spatial frequency of every gear element (both orders) along a path.

    Parameters
    ----------
    q_rad
        ``(m, n_joints)`` joint angles at path abscissae ``s_mm`` ``(m,)``.
    gears
        Gear stages (mappings or objects) with ``joint`` (1-based), ``stage``,
        ``rev_per_joint_rev`` and ``teeth``: any robot, any transmission.

    Returns
    -------
    DataFrame
        One row per gear and order: ``joint, stage, order, f_spatial_per_mm`` (mean over the
        path), ``f_min_per_mm, f_max_per_mm`` (its range along the path) and
        ``rev_per_mm_joint`` (joint revolutions per mm).

    Notes
    -----
    A gear turning ``r`` times per joint revolution makes ``r |dq/ds| / 2π`` revolutions per
    mm of path; its tooth mesh ``z`` times that. The joint angle is a function of the TCP
    position only, so on a given path this is independent of the feed (the temporal
    frequency is this times the feed).
    """
    q = np.asarray(q_rad, float)
    s = np.asarray(s_mm, float)
    dq = np.abs(np.gradient(q, s, axis=0)) / (2 * np.pi)  # joint rev per mm
    mean_rate = np.abs(q[-1] - q[0]) / (s[-1] - s[0]) / (2 * np.pi)
    rows = [{"joint": j, "stage": stage, "order": order,
             "f_spatial_per_mm": mult * mean_rate[j - 1],
             "f_min_per_mm": mult * dq[:, j - 1].min(),
             "f_max_per_mm": mult * dq[:, j - 1].max(),
             "rev_per_mm_joint": mean_rate[j - 1]}
            for j, stage, order, mult in gear_orders(gears)]
    return pd.DataFrame(rows)


def gear_frequencies_from_motion(t_s: np.ndarray, q_rad: np.ndarray, p_mm: np.ndarray,
                                 gears: Sequence[Any], *,
                                 min_speed_fraction: float = 0.99) -> pd.DataFrame:
    """Temporal [Hz] and spatial [mm⁻¹] frequency of every gear from a timed motion.

    ``f_t = r |q̇| / 2π`` (``× z`` for the mesh), ``f_s = f_t / |ṗ|``, averaged over the
    samples where the TCP speed is at least ``min_speed_fraction`` of its maximum (the
    constant-feed part). Used to check numerically that ``f_s`` does not depend on the feed.
    """
    t = np.asarray(t_s, float)
    qd = np.abs(np.gradient(np.asarray(q_rad, float), t, axis=0)) / (2 * np.pi)
    v = np.linalg.norm(np.gradient(np.asarray(p_mm, float), t, axis=0), axis=1)
    sel = v >= min_speed_fraction * v.max()
    rows = []
    for j, stage, order, mult in gear_orders(gears):
        ft = mult * qd[sel, j - 1]
        rows.append({"joint": j, "stage": stage, "order": order,
                     "f_temporal_hz": float(ft.mean()),
                     "f_spatial_per_mm": float(np.mean(ft / v[sel]))})
    return pd.DataFrame(rows)


# ---------------------------------------------------------------------------------------------
# 4. peak → gear matching
# ---------------------------------------------------------------------------------------------
PEAK_COLUMNS = ["direction", "feed_mm_s", "f_spatial_per_mm", "amplitude_um", "mechanism",
                "joint", "stage", "order", "gear_f_spatial_per_mm", "f_temporal_hz",
                "component", "snr", "cut"]
"""peaks.csv columns: the contract's first seven, then supporting detail."""


def element_label(joint: Any, stage: Any, order: Any) -> str:
    """``joint:stage:order`` of a gear element (``2:motor:mesh``), as listed in ``candidates``."""
    return f"{int(joint)}:{stage}:{order}"


def parse_candidates(text: Any) -> list[tuple[int, str, str]]:
    """The ``(joint, stage, order)`` elements of a ``candidates`` cell (``;``-separated
    :func:`element_label` s; empty or NaN → none)."""
    if not isinstance(text, str) or not text:
        return []
    out = []
    for item in text.split(";"):
        joint, stage, order = item.split(":")
        out.append((int(joint), stage, order))
    return out


def match_peaks_to_gears(peaks: pd.DataFrame, gears: pd.DataFrame, *,
                         tolerance_per_mm: float,
                         resolution_per_mm: float | None = None) -> pd.DataFrame:
    """Attribute each peak to the gear element whose spatial frequency is nearest, if
    within ``tolerance_per_mm`` (tie it to the resolution: a fraction of 1/L).

    Two gear lines closer than the spectral resolution ``resolution_per_mm`` (default
    ``tolerance_per_mm``), or both within the match tolerance of the peak, make one peak: the
    run cannot tell them apart. With the Hann window of :func:`profile_spectrum` that
    resolution is the main lobe's −6 dB width, 2/L (Harris 1978, Table 1: two equal lines
    closer than that show one maximum), so :func:`analyse_run` passes ``merge_bins/L`` with
    ``merge_bins`` = 2. Such a peak is attributed to the nearest element as before, and
    lists every element that may have made it.

    Adds ``joint`` (nullable int), ``stage``, ``order``, ``gear_f_spatial_per_mm``,
    ``n_candidates`` (gear elements within the match tolerance of the peak), ``candidates``
    (the attributed element first, then every element within the tolerance of the peak or
    closer than ``max(tolerance, resolution)`` to the attributed element's line, by distance
    from the peak, as ``;``-separated :func:`element_label` s; empty when not attributed)
    and ``merged`` (True when ``candidates`` lists more than one element: merged gear lines).
    """
    out = peaks.copy()
    sep = max(tolerance_per_mm, resolution_per_mm or 0.0)
    joint, stage, order, fg, ncand, cands, merged = [], [], [], [], [], [], []
    gf = gears["f_spatial_per_mm"].to_numpy(float)
    for f in out["f_spatial_per_mm"].to_numpy(float):
        d = np.abs(gf - f)
        within = np.flatnonzero(d <= tolerance_per_mm)
        ncand.append(int(within.size))
        if within.size:
            k = int(within[np.argmin(d[within])])
            joint.append(int(gears["joint"].iloc[k]))
            stage.append(str(gears["stage"].iloc[k]))
            order.append(str(gears["order"].iloc[k]))
            fg.append(float(gf[k]))
            near = set(within.tolist()) | set(np.flatnonzero(np.abs(gf - gf[k]) <= sep).tolist())
            near = [k] + sorted(near - {k}, key=lambda i: (d[i], i))
            cands.append(";".join(element_label(gears["joint"].iloc[i], gears["stage"].iloc[i],
                                                gears["order"].iloc[i]) for i in near))
            merged.append(len(near) > 1)
        else:
            joint.append(pd.NA)
            stage.append("")
            order.append("")
            fg.append(np.nan)
            cands.append("")
            merged.append(False)
    out["joint"] = pd.array(joint, dtype="Int64")
    out["stage"] = stage
    out["order"] = order
    out["gear_f_spatial_per_mm"] = fg
    out["n_candidates"] = ncand
    out["candidates"] = cands
    out["merged"] = np.array(merged, bool)
    return out


# ---------------------------------------------------------------------------------------------
# 5. temporal vs spatial classification across feeds
# ---------------------------------------------------------------------------------------------
def classify_peaks(peaks: pd.DataFrame, resolution_per_mm: Mapping[tuple[str, float], float],
                   *, tol_bins: float = 1.0, min_other_feeds: int = 1) -> pd.DataFrame:
    """Classify every peak as ``gear``, ``temporal``, ``spatial`` or ``unclassified``.

    For a peak at spatial frequency f in the run (direction d, feed v), the other runs of
    the same direction are searched for a peak not attributed to a gear at the same
    *temporal* frequency ``f·v`` (within ``tol_bins`` temporal resolutions ``v/L`` of either
    run) and for any peak at the same *spatial* frequency (within ``tol_bins`` spatial
    resolutions 1/L). Seen at the same temporal frequency, and not at the same spatial
    frequency, in at least ``min_other_feeds`` other feeds (``min_other_feeds + 1`` for a
    peak that itself matches a gear, so that a chance coincidence of slow gear peaks does not
    overrule the gear) ⇒ ``temporal`` (a constant-Hz source such as the 13 Hz servo ripple:
    its wavelength grows with the feed). Otherwise a peak attributed to a gear is ``gear``;
    one seen at the same spatial frequency at other feeds but with no gear is ``spatial``;
    the rest ``unclassified``.

    ``peaks`` needs ``direction, feed_mm_s, f_spatial_per_mm`` and ``joint`` (from
    :func:`match_peaks_to_gears`); ``resolution_per_mm`` maps (direction, feed) to 1/L.
    """
    out = peaks.copy()
    out["f_temporal_hz"] = out["f_spatial_per_mm"] * out["feed_mm_s"]
    mech = []
    for _, p in out.iterrows():
        d, v, f = p["direction"], float(p["feed_mm_s"]), float(p["f_spatial_per_mm"])
        res_p = resolution_per_mm[(d, v)]
        others = out[(out["direction"] == d) & (out["feed_mm_s"] != v)]
        same_t, same_s = set(), set()
        for _, o in others.iterrows():
            vo = float(o["feed_mm_s"])
            res_o = resolution_per_mm[(d, vo)]
            tol_t = tol_bins * max(res_p * v, res_o * vo)
            tol_s = tol_bins * max(res_p, res_o)
            if abs(float(o["f_temporal_hz"]) - f * v) <= tol_t and pd.isna(o["joint"]):
                same_t.add(vo)
            if abs(float(o["f_spatial_per_mm"]) - f) <= tol_s:
                same_s.add(vo)
        only_t = same_t - same_s
        need = min_other_feeds + (0 if pd.isna(p["joint"]) else 1)
        if len(only_t) >= need and len(only_t) >= len(same_s):
            mech.append("temporal")
        elif not pd.isna(p["joint"]):
            mech.append("gear")
        elif len(same_s) >= min_other_feeds:
            mech.append("spatial")
        else:
            mech.append("unclassified")
    out["mechanism"] = mech
    temporal = out["mechanism"] == "temporal"
    out.loc[temporal, "joint"] = pd.NA
    out.loc[temporal, ["stage", "order"]] = ""
    out.loc[temporal, "gear_f_spatial_per_mm"] = np.nan
    if "candidates" in out:  # a temporal peak is attributed to no gear
        out.loc[temporal, "candidates"] = ""
        out.loc[temporal, "merged"] = False
    return out


# ---------------------------------------------------------------------------------------------
# one tracker run, end to end
# ---------------------------------------------------------------------------------------------
def analyse_run(t_s: np.ndarray, points_mm: np.ndarray, *, robot: SerialRobot,
                gears: Sequence[Any], tool_rotation: np.ndarray, q0_rad: np.ndarray,
                ds_mm: float, trim_mm: float, nfft: int, fmin_cycles: float,
                fmax_per_mm: float, threshold: float, n_peaks: int, tol_bins: float,
                detrend_order: int = 1, ik_points: int = 41, merge_bins: float = 2.0
                ) -> tuple[Profile, ProfileSpectrum, pd.DataFrame, pd.DataFrame]:
    """Profile, spectrum, gear frequencies and gear-matched peaks of one tracker run.

    The gear spatial frequencies are computed for the measured path: the best line's ends
    (tracker coordinates are those of the robot base frame) through inverse kinematics at
    the tool orientation ``tool_rotation``. Peaks are searched from ``fmin_cycles/L``
    (fewer cycles than that in the record are indistinguishable from the removed line) up to
    ``fmax_per_mm``; the match tolerance is ``tol_bins/L``, and gear lines closer than
    ``merge_bins/L`` (the Hann window's resolution, 2 bins) are merged: the peak lists every
    candidate (:func:`match_peaks_to_gears`).
    """
    prof = spatial_profile(t_s, points_mm, ds_mm=ds_mm, trim_mm=trim_mm,
                           detrend_order=detrend_order)
    spec = profile_spectrum(prof, nfft=nfft)
    q, s = joint_path_for_line(robot, prof.start_mm, prof.end_mm, tool_rotation, q0_rad,
                               ik_points)
    gears_df = gear_spatial_frequencies(q, s, gears)
    peaks = spectrum_peaks(spec, fmin_per_mm=fmin_cycles * spec.resolution_per_mm,
                           fmax_per_mm=fmax_per_mm, threshold=threshold, n_peaks=n_peaks)
    peaks = match_peaks_to_gears(peaks, gears_df,
                                 tolerance_per_mm=tol_bins * spec.resolution_per_mm,
                                 resolution_per_mm=merge_bins * spec.resolution_per_mm)
    return prof, spec, gears_df, peaks


def profile_dataset(prof: Profile, spec: ProfileSpectrum, *, fmax_store_per_mm: float,
                    attrs: Mapping[str, Any]) -> xr.Dataset:
    """One run's profile and spectrum as a labelled dataset (coordinates ``s``, ``f``)."""
    keep = spec.f_per_mm <= fmax_store_per_mm
    comp = ("component", list(COMPONENTS), {"units": "1",
                                             "long_name": "perpendicular component"})
    return xr.Dataset(
        {
            "deviation_um": (("component", "s"), prof.deviation_um,
                             {"units": "um", "long_name": "deviation perpendicular to the "
                              "best line (re-ordered in space, uniform grid)"}),
            "amplitude_um": (("component", "f"), spec.amplitude_um[:, keep],
                             {"units": "um", "long_name": "sinusoid amplitude spectrum "
                              "(Hann, zero-padded)"}),
            "power_um2": ("f", spec.power_um2[keep],
                          {"units": "um^2", "long_name": "power of the perpendicular "
                           "deviation (lateral + vertical)"}),
            "psd_um2_mm": ("f", spec.psd_um2_mm[keep],
                           {"units": "um^2 mm", "long_name": "power spectral density of the "
                            "perpendicular deviation"}),
        },
        coords={
            "component": comp,
            "s": ("s", prof.s_mm, {"units": "mm", "long_name": "distance along the path"}),
            "f": ("f", spec.f_per_mm[keep], {"units": "1/mm",
                                             "long_name": "spatial frequency"}),
        },
        attrs={**attrs, "resolution_per_mm": spec.resolution_per_mm,
               "length_mm": prof.length_mm, "speed_mm_s": prof.speed_mm_s,
               "ds_mm": prof.ds_mm, "start_mm": list(map(float, prof.start_mm)),
               "end_mm": list(map(float, prof.end_mm))},
    )


# ---------------------------------------------------------------------------------------------
# cross-checks (chapter)
# ---------------------------------------------------------------------------------------------
def surface_cross_check(peaks: pd.DataFrame, surface_peaks: pd.DataFrame, cuts: pd.DataFrame,
                        *, tolerance_per_mm: float) -> pd.DataFrame:
    """Mark every tracker peak present on the surface (yes/no).

    A tracker peak of (direction, feed) is on the surface when a peak of
    ``results/surface/peaks.csv`` (``cut, f_spatial_per_mm, …``) in a cut of the same
    direction and feed (``cuts``: ``cut, direction, feed_mm_s``) lies within
    ``tolerance_per_mm``. Adds ``on_surface`` (bool) and ``surface_f_per_mm`` (nearest).
    """
    # only the contract columns of the surface table (it may carry more, e.g. its own feed)
    sp = surface_peaks[["cut", "f_spatial_per_mm"]].merge(
        cuts[["cut", "direction", "feed_mm_s"]], on="cut", how="left")
    on, fnear = [], []
    for _, p in peaks.iterrows():
        cand = sp[(sp["direction"] == p["direction"])
                  & np.isclose(sp["feed_mm_s"].astype(float), float(p["feed_mm_s"]))]
        if cand.empty:
            on.append(False)
            fnear.append(np.nan)
            continue
        d = np.abs(cand["f_spatial_per_mm"].to_numpy(float) - float(p["f_spatial_per_mm"]))
        k = int(np.argmin(d))
        on.append(bool(d[k] <= tolerance_per_mm))
        fnear.append(float(cand["f_spatial_per_mm"].iloc[k]))
    out = peaks.copy()
    out["on_surface"] = on
    out["surface_f_per_mm"] = fnear
    return out


def band_peak_ratio(f: np.ndarray, power: np.ndarray, band: tuple[float, float],
                    reference: tuple[float, float]) -> float:
    """Largest power in ``band`` divided by the median power in ``reference`` (a peak-to-floor
    ratio: ≈ 5–10 for noise alone, far above for a real peak)."""
    f = np.asarray(f)
    power = np.asarray(power)
    b = (f >= band[0]) & (f <= band[1])
    r = (f >= reference[0]) & (f <= reference[1])
    return float(power[b].max() / np.median(power[r]))


def evaluate_attribution(peaks: pd.DataFrame, planted: pd.DataFrame, runs: pd.DataFrame, *,
                         threshold: float, tol_bins: float, fmax_per_mm: float,
                         margin: float = 2.0) -> pd.DataFrame:
    """Compare the gear attributions with the planted truth (synthetic runs only).

    Every planted gear element of every run (``planted``: ``direction, feed_mm_s, joint,
    stage, order, f_spatial_per_mm, amplitude_um``) is put in one class, from its power
    ``A²/2`` and the run's noise floor ``floor_um2`` (``runs``: ``direction, feed_mm_s,
    resolution_per_mm, fmin_per_mm, floor_um2``):

    * ``out_of_band`` — below ``fmin`` (fewer cycles than the record resolves) or above
      ``fmax_per_mm``;
    * ``above_noise`` — ``A²/2 ≥ margin·threshold·floor``: it must be found;
    * ``below_noise`` — ``A²/2 < threshold·floor/margin``: it must not be attributed;
    * ``marginal`` — in between (either outcome is acceptable).

    ``found`` is true when a ``gear`` peak of the run is attributed to exactly this element;
    ``merged`` when it is not, but a gear peak of the run lists it among its ``candidates``
    (:func:`match_peaks_to_gears`: merged gear lines, closer than the resolution) or lies
    within the match tolerance of its frequency; ``merged_into`` then names the element that
    peak was attributed to (``joint:stage:order``). ``false_attribution`` marks
    attributed elements that are ``below_noise`` or ``out_of_band`` (the attribution then
    names a gear that did not make the peak).
    """
    rows = []
    gear_peaks = peaks[peaks["mechanism"] == "gear"]
    for _, g in planted.iterrows():
        key = (g["direction"], float(g["feed_mm_s"]))
        run = runs[(runs["direction"] == key[0]) & np.isclose(runs["feed_mm_s"], key[1])]
        if run.empty:
            continue
        run = run.iloc[0]
        power = 0.5 * float(g["amplitude_um"]) ** 2
        floor = float(run["floor_um2"])
        f = float(g["f_spatial_per_mm"])
        if f < float(run["fmin_per_mm"]) or f > fmax_per_mm:
            cls = "out_of_band"
        elif power >= margin * threshold * floor:
            cls = "above_noise"
        elif power < threshold * floor / margin:
            cls = "below_noise"
        else:
            cls = "marginal"
        mine = gear_peaks[(gear_peaks["direction"] == key[0])
                          & np.isclose(gear_peaks["feed_mm_s"].astype(float), key[1])]
        exact = mine[(mine["joint"].astype("Int64") == int(g["joint"]))
                     & (mine["stage"] == g["stage"]) & (mine["order"] == g["order"])]
        tol = tol_bins * float(run["resolution_per_mm"])
        near = mine[np.abs(mine["f_spatial_per_mm"].astype(float) - f) <= tol]
        me = (int(g["joint"]), str(g["stage"]), str(g["order"]))
        if "candidates" in mine:
            listed = mine[np.array([me in parse_candidates(c) for c in mine["candidates"]],
                                   dtype=bool)]
            near = pd.concat([listed, near[~near.index.isin(listed.index)]])
        rows.append({"direction": key[0], "feed_mm_s": key[1], "joint": int(g["joint"]),
                     "stage": g["stage"], "order": g["order"], "f_spatial_per_mm": f,
                     "amplitude_um": float(g["amplitude_um"]),
                     "snr_expected": power / floor, "class": cls,
                     "found": not exact.empty, "merged": exact.empty and not near.empty,
                     "merged_into": (element_label(near["joint"].iloc[0], near["stage"].iloc[0],
                                                   near["order"].iloc[0])
                                     if exact.empty and not near.empty else ""),
                     "found_amplitude_um": (float(exact["amplitude_um"].iloc[0])
                                            if not exact.empty else np.nan),
                     "false_attribution": (not exact.empty)
                     and cls in ("below_noise", "out_of_band")})
    return pd.DataFrame(rows)


def attribution_counts(evaluation: pd.DataFrame) -> dict[str, int]:
    """Counts for the report: planted elements above noise, found, merged, missed; false
    attributions."""
    e = evaluation
    above = e["class"] == "above_noise"
    return {
        "planted_elements": int(len(e)),
        "above_noise": int(above.sum()),
        "found": int((above & e["found"]).sum()),
        "merged": int((above & e["merged"]).sum()),
        "missed": int((above & ~e["found"] & ~e["merged"]).sum()),
        "marginal": int((e["class"] == "marginal").sum()),
        "marginal_found": int(((e["class"] == "marginal") & e["found"]).sum()),
        "false_attributions": int(e["false_attribution"].sum()),
    }


def analyse_tracker_run(t_s: np.ndarray, points_mm: np.ndarray, cell: Any, *,
                        data_file: str, **settings: Any
                        ) -> tuple[Profile, ProfileSpectrum, pd.DataFrame, pd.DataFrame]:
    """:func:`analyse_run` for a tracker file in the cell described by ``cell``
    (:class:`robomill.io.cell.Cell`, read from ``cell.yaml``).

    The points are first registered to the robot base frame with the cell's
    ``base_from_instrument.tracker`` (if any); the robot, its home posture (IK seed), the tool
    orientation and the gear trains are the cell's. A path out of the robot's reach raises
    :class:`~robomill.io.errors.RawDataError` naming ``data_file`` and pointing at
    ``base_from_instrument`` (not the inverse kinematics' ``RuntimeError``).
    """
    from robomill.errors import RawDataError

    base = cell.to_base_mm("tracker", points_mm)
    try:
        return analyse_run(t_s, base, robot=cell.robot, gears=cell.transmissions,
                           tool_rotation=cell.tool_rotation, q0_rad=cell.q_home_rad,
                           **settings)
    except RuntimeError:
        prof = spatial_profile(t_s, base, ds_mm=settings["ds_mm"], trim_mm=settings["trim_mm"])
        T = np.broadcast_to(np.eye(4), (2, 4, 4)).copy()
        T[:, :3, :3] = cell.tool_rotation
        T[:, :3, 3] = [prof.start_mm, prof.end_mm]
        cell.joint_path_rad(T, data_file=data_file, instrument="tracker")  # raises RawDataError
        raise RawDataError(data_file, f"the path is not reachable by robot '{cell.robot.name}'",
                           where="tracker points in the robot base frame",
                           expected="points in the base frame of the robot of "
                                    f"{cell.path}: register the tracker frame with "
                                    "base_from_instrument.tracker in cell.yaml") from None


_RUN_COORDS = {  # run coordinate: (units, long name), from each run's attrs
    "direction": ("1", "cut direction"),
    "feed_mm_s": ("mm/s", "commanded feed"),
    "cut": ("1", "cut whose path the run follows"),
    "resolution_per_mm": ("1/mm", "frequency resolution 1/L"),
    "length_mm": ("mm", "analysed path length L"),
    "speed_mm_s": ("mm/s", "measured speed"),
    "fmin_per_mm": ("1/mm", "lowest analysed frequency"),
    "floor_um2": ("um^2", "median power in the band"),
}


def gather_profiles(runs: Sequence[xr.Dataset], run_ids: Sequence[str]) -> xr.Dataset:
    """Stack the per-run :func:`profile_dataset` artefacts along ``run`` (outer join of their
    axes); each run's attrs (direction, feed, resolution, …) become ``run`` coordinates.
    The inputs are not modified."""
    if len(runs) != len(run_ids):
        raise ValueError(f"gather_profiles: {len(runs)} runs but {len(run_ids)} run ids")
    missing = [(r, k) for r, ds in zip(run_ids, runs, strict=True) for k in _RUN_COORDS
               if k not in ds.attrs]
    if missing:
        raise ValueError(f"gather_profiles: run attribute(s) missing: {missing[:5]}")
    coords = {k: ("run", [ds.attrs[k] for ds in runs], {"units": u, "long_name": n})
              for k, (u, n) in _RUN_COORDS.items()}
    parts = []
    for r, ds in zip(run_ids, runs, strict=True):
        part = ds.expand_dims(run=[r])
        part.attrs = {}
        parts.append(part)
    prof = xr.concat(parts, dim="run", join="outer").assign_coords(coords)
    prof["run"].attrs = {"units": "1", "long_name": "tracker run <dir>_f<feed>"}
    return prof


def gather_gears(per_run: Sequence[pd.DataFrame]) -> pd.DataFrame:
    """All runs' gear spatial frequencies, with the temporal frequency f·v they have at the
    run's feed (``f_temporal_hz``)."""
    gears = pd.concat(list(per_run), ignore_index=True)
    gears["f_temporal_hz"] = gears["f_spatial_per_mm"] * gears["feed_mm_s"]
    return gears


def gather_peaks(per_run: Sequence[pd.DataFrame], profiles: xr.Dataset, *,
                 tol_bins: float) -> pd.DataFrame:
    """All runs' peaks, classified across feeds (:func:`classify_peaks`) with each run's
    resolution from ``profiles`` (:func:`gather_profiles`); columns :data:`PEAK_COLUMNS`
    (plus ``n_candidates``, ``candidates``, ``merged`` when present)."""
    peaks = pd.concat(list(per_run), ignore_index=True)
    peaks["joint"] = peaks["joint"].astype("Int64")
    peaks[["stage", "order"]] = peaks[["stage", "order"]].fillna("")
    if "candidates" in peaks:
        peaks["candidates"] = peaks["candidates"].fillna("")
        peaks["merged"] = peaks["merged"].astype(bool)
    res = {(d, float(v)): float(x) for d, v, x in zip(profiles["direction"].values,
                                                      profiles["feed_mm_s"].values,
                                                      profiles["resolution_per_mm"].values,
                                                      strict=True)}
    peaks = classify_peaks(peaks, res, tol_bins=tol_bins)
    extra = [c for c in ("n_candidates", "candidates", "merged") if c in peaks]
    return peaks[PEAK_COLUMNS + extra]


#: results/straightness/truth_check.csv columns
TRUTH_CHECK_COLUMNS = ["direction", "feed_mm_s", "joint", "stage", "order", "f_spatial_per_mm",
                       "amplitude_um", "snr_expected", "class", "found", "merged",
                       "found_amplitude_um", "false_attribution", "merged_into"]


def planted_gear_elements(truth: xr.Dataset) -> pd.DataFrame:
    """Every planted gear element × tracker run of the virtual cell's ``truth.nc``: run,
    direction, feed, joint, stage, order, spatial frequency and amplitude perpendicular to
    the path."""
    rows = []
    for k, run in enumerate(truth["tracker_run"].values):
        for g in truth["gear"].values:
            for o in truth["order"].values:
                at = {"tracker_run": run, "gear": g, "order": o}
                rows.append({
                    "run": str(run), "direction": str(truth["tracker_direction"].values[k]),
                    "feed_mm_s": float(truth["tracker_feed_mm_s"].values[k]),
                    "joint": int(truth["gear_joint"].sel(gear=g)),
                    "stage": str(truth["gear_stage"].sel(gear=g).values), "order": str(o),
                    "f_spatial_per_mm": float(truth["tracker_gear_f_spatial_per_mm"].sel(at)),
                    "amplitude_um": float(truth["tracker_gear_amplitude_um"].sel(at))})
    return pd.DataFrame(rows)


def truth_check(peaks: pd.DataFrame | None, truth: xr.Dataset | None,
                profiles: xr.Dataset | None, options: Mapping[str, Any]) -> pd.DataFrame:
    """The attribution against the planted gears (:func:`evaluate_attribution`), columns
    :data:`TRUTH_CHECK_COLUMNS`; an empty table when there is no truth (real data)."""
    if truth is None:
        return pd.DataFrame(columns=TRUTH_CHECK_COLUMNS)
    peaks = peaks.copy()
    peaks[["stage", "order"]] = peaks[["stage", "order"]].fillna("")
    if "candidates" in peaks:
        peaks["candidates"] = peaks["candidates"].fillna("")
    runs = pd.DataFrame({k: profiles[k].values for k in ("direction", "feed_mm_s",
                                                          "resolution_per_mm", "fmin_per_mm",
                                                          "floor_um2")})
    ev = evaluate_attribution(peaks, planted_gear_elements(truth), runs,
                              threshold=options["threshold"], tol_bins=options["tol_bins"],
                              fmax_per_mm=options["fmax_per_mm"])
    return ev[TRUTH_CHECK_COLUMNS]


def band_floor_table(profiles: xr.Dataset, peaks: pd.DataFrame, band: tuple[float, float],
                     quiet: tuple[float, float], *,
                     floor_from_per_mm: float = 2.0) -> pd.DataFrame:
    """Peak-to-floor ratio of every run's motion spectrum in the surface band and in a quiet
    band of the same width (thesis §3.2: no motion component near the roughness band).

    For each run of ``profiles`` (``power_um2(run, f)`` with coordinates ``direction,
    feed_mm_s`` on ``run``), :func:`band_peak_ratio` against the median power from
    ``floor_from_per_mm`` to the top of the spectrum, in ``band`` and in ``quiet``, and the
    number of ``peaks`` (``direction, feed_mm_s, f_spatial_per_mm``) of that run in ``band``.

    Returns
    -------
    pandas.DataFrame
        ``direction, feed_mm_s, peak_to_floor_in_band, peak_to_floor_noise_band,
        peaks_in_band``, one row per run.
    """
    rows = []
    for r in profiles["run"].values:
        ds = profiles.sel(run=r)
        ok = np.isfinite(ds["power_um2"].values)
        f, pw = ds["f"].values[ok], ds["power_um2"].values[ok]
        direction, feed = str(ds["direction"].values), float(ds["feed_mm_s"].values)
        ref = (floor_from_per_mm, float(f.max()))
        rows.append({"direction": direction, "feed_mm_s": feed,
                     "peak_to_floor_in_band": band_peak_ratio(f, pw, band, ref),
                     "peak_to_floor_noise_band": band_peak_ratio(f, pw, quiet, ref),
                     "peaks_in_band": int(((peaks["direction"] == direction)
                                           & np.isclose(peaks["feed_mm_s"], feed)
                                           & peaks["f_spatial_per_mm"].between(*band)).sum())})
    return pd.DataFrame(rows, columns=["direction", "feed_mm_s", "peak_to_floor_in_band",
                                       "peak_to_floor_noise_band", "peaks_in_band"])


def run_summary_table(profiles: xr.Dataset, peaks: pd.DataFrame) -> pd.DataFrame:
    """One row per tracker run: the RMS deviation from the best line per component, the largest
    peak (amplitude, wavelength 1/f, mechanism) and the number of peaks per mechanism.

    Parameters
    ----------
    profiles
        ``results/straightness/profiles.nc`` (:func:`gather_profiles`): ``deviation_um`` over
        (run, component, s) and the run coordinates ``direction``, ``feed_mm_s``.
    peaks
        ``results/straightness/peaks.csv`` (:func:`gather_peaks`), with ``direction``,
        ``feed_mm_s``, ``amplitude_um``, ``f_spatial_per_mm``, ``mechanism``.

    Returns
    -------
    pandas.DataFrame
        Columns ``run, direction, feed_mm_s``, ``rms_<component>_um`` (RMS over s, NaN
        skipped), ``largest_peak_um``, ``largest_peak_wavelength_mm``,
        ``largest_peak_mechanism`` and ``<mechanism>_peaks``; a run without peaks has NaN
        there and 0 counts.
    """
    table = pd.DataFrame({"run": profiles["run"].values,
                          "direction": profiles["direction"].values,
                          "feed_mm_s": profiles["feed_mm_s"].values.astype(float)})
    dev = profiles["deviation_um"]
    for comp in profiles["component"].values:
        rms = np.sqrt((dev.sel(component=comp) ** 2).mean("s", skipna=True))
        table[f"rms_{comp}_um"] = rms.values
    key = {(str(d), round(float(v), 9)): r for r, d, v in
           zip(table.run, table.direction, table.feed_mm_s, strict=True)}
    pk = peaks.assign(run=[key.get((str(d), round(float(v), 9))) for d, v in
                           zip(peaks.direction, peaks.feed_mm_s, strict=True)])
    pk = pk[pk["run"].notna()]
    top = pk.loc[pk.groupby("run").amplitude_um.idxmax()] if len(pk) else pk
    table = table.merge(pd.DataFrame({
        "run": top["run"], "largest_peak_um": top["amplitude_um"],
        "largest_peak_wavelength_mm": 1.0 / top["f_spatial_per_mm"].astype(float),
        "largest_peak_mechanism": top["mechanism"]}), on="run", how="left")
    counts = pk.groupby(["run", "mechanism"]).size().unstack(fill_value=0)
    counts.columns = [f"{c}_peaks" for c in counts.columns]
    table = table.merge(counts.reset_index(), on="run", how="left")
    table[list(counts.columns)] = table[list(counts.columns)].fillna(0).astype(int)
    return table
