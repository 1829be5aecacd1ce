"""Areal surface scans (focus variation, confocal, white light): form removal, the ISO 25178-2
height parameters, the areal power spectrum (radially averaged, along and across the feed) and
profiles extracted along the feed for the profile analysis of chapter 2.

A scan is a grid ``z_um (y, x)`` with NaN at points the instrument did not measure, its
spacings ``dx_mm``, ``dy_mm`` and the angle of the cut's feed direction in the scan's frame
(``feed_angle_deg``: 0 = feed along the scan's +x, 90 = along +y; the manifest entry's key).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import scipy.ndimage
import xarray as xr

PARAMETERS = ("Sq_um", "Sa_um", "Sz_um", "Sp_um", "Sv_um", "Ssk", "Sku")
"""The ISO 25178-2 height parameters :func:`height_parameters` returns."""


def _design(x: np.ndarray, y: np.ndarray, degree: int) -> np.ndarray:
    """Columns x^i y^j, i + j ≤ degree (coordinates scaled to [-1, 1] for conditioning)."""
    return np.column_stack([x**i * y**j for i in range(degree + 1)
                            for j in range(degree + 1 - i)])


def remove_form(z_um: np.ndarray, dx_mm: float, dy_mm: float, degree: int = 1
                ) -> tuple[np.ndarray, np.ndarray]:
    """Remove the least-squares polynomial surface of total ``degree`` (1: the mean plane,
    ISO 25178-2 F-operator "levelling"; 2: the quadric of a curved part) from a scan.

    .. math:: \\min_c \\sum_{valid} \\Big(z_{ij} - \\sum_{k+l \\le d} c_{kl} x_j^k y_i^l\\Big)^2

    Returns ``(residual, form)``, both NaN where ``z_um`` is.

    Raises
    ------
    ValueError
        Fewer valid points than coefficients.

    Examples
    --------
    >>> y, x = np.mgrid[0:20, 0:30] * 0.01
    >>> r, _ = remove_form(3.0 + 2.0 * x - 1.0 * y, 0.01, 0.01)
    >>> float(np.nanmax(np.abs(r))) < 1e-9
    True
    """
    z = np.asarray(z_um, float)
    ny, nx = z.shape
    yy, xx = np.mgrid[0:ny, 0:nx]
    xs = (xx * dx_mm - 0.5 * (nx - 1) * dx_mm) / max(0.5 * (nx - 1) * dx_mm, 1e-12)
    ys = (yy * dy_mm - 0.5 * (ny - 1) * dy_mm) / max(0.5 * (ny - 1) * dy_mm, 1e-12)
    ok = np.isfinite(z)
    a = _design(xs[ok], ys[ok], degree)
    if ok.sum() < a.shape[1]:
        raise ValueError(f"{int(ok.sum())} valid points, a degree-{degree} form needs "
                         f"{a.shape[1]}")
    coef, *_ = np.linalg.lstsq(a, z[ok], rcond=None)
    form = (_design(xs.ravel(), ys.ravel(), degree) @ coef).reshape(z.shape)
    form[~ok] = np.nan
    return z - form, form


def height_parameters(z_um: np.ndarray) -> dict[str, float]:
    """ISO 25178-2 §4.1 height parameters of a scale-limited surface (valid points; the
    mean is removed first):

    .. math:: S_q = \\sqrt{\\overline{z^2}},\\quad S_a = \\overline{|z|},\\quad
              S_{sk} = \\overline{z^3}/S_q^3,\\quad S_{ku} = \\overline{z^4}/S_q^4,\\quad
              S_z = S_p + S_v = \\max z - \\min z

    Examples
    --------
    >>> y, x = np.mgrid[0:64, 0:64]
    >>> p = height_parameters(np.sin(2 * np.pi * x / 16))
    >>> round(p["Sq_um"], 6), round(p["Sku"], 3)
    (0.707107, 1.5)
    """
    z = np.asarray(z_um, float)
    z = z[np.isfinite(z)]
    z = z - z.mean()
    sq = float(np.sqrt(np.mean(z**2)))
    return {"Sq_um": sq, "Sa_um": float(np.mean(np.abs(z))),
            "Sz_um": float(z.max() - z.min()), "Sp_um": float(z.max()),
            "Sv_um": float(-z.min()),
            "Ssk": float(np.mean(z**3) / sq**3) if sq > 0 else float("nan"),
            "Sku": float(np.mean(z**4) / sq**4) if sq > 0 else float("nan")}


def psd_2d(z_um: np.ndarray, dx_mm: float, dy_mm: float
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Two-sided areal PSD ``C(ky, kx)`` [µm²·mm²] of a scan, frequencies [mm⁻¹].

    Invalid points are set to the mean (zero after removal) and a 2-D Hann window applied;
    the window's power is divided out, so that Parseval holds for the windowed data:
    ``Σ C Δkx Δky ≈ mean(z²)``.

    .. math:: C(k_x, k_y) = \\frac{Δx Δy}{N_x N_y \\overline{w^2}}
              \\left|\\sum_{ij} w_{ij} z_{ij} e^{-2πi(k_x x_j + k_y y_i)}\\right|^2
    """
    z = np.asarray(z_um, float)
    ok = np.isfinite(z)
    z = np.where(ok, z - (z[ok].mean() if ok.any() else 0.0), 0.0)
    ny, nx = z.shape
    w = np.outer(np.hanning(ny), np.hanning(nx))
    f = np.fft.fft2(z * w)
    c = np.abs(f) ** 2 * dx_mm * dy_mm / (nx * ny * np.mean(w**2))
    return np.fft.fftfreq(ny, dy_mm), np.fft.fftfreq(nx, dx_mm), c


def radial_psd(z_um: np.ndarray, dx_mm: float, dy_mm: float, n_bins: int | None = None
               ) -> tuple[np.ndarray, np.ndarray]:
    """The areal PSD averaged over annuli of |k| (ISO 25178's isotropic summary):
    ``(k_mm (m,), C_um2_mm2 (m,))``, bins of width ``max(Δkx, Δky)`` up to the smaller
    Nyquist frequency."""
    ky, kx, c = psd_2d(z_um, dx_mm, dy_mm)
    k = np.hypot(*np.meshgrid(kx, ky))
    dk = max(abs(kx[1] - kx[0]) if kx.size > 1 else 0, abs(ky[1] - ky[0]) if ky.size > 1
             else 0)
    k_max = min(0.5 / dx_mm, 0.5 / dy_mm)
    m = n_bins or max(int(k_max / dk), 1)
    edges = np.linspace(0.0, k_max, m + 1)
    idx = np.digitize(k.ravel(), edges) - 1
    keep = (idx >= 0) & (idx < m)
    sums = np.bincount(idx[keep], c.ravel()[keep], minlength=m)
    counts = np.bincount(idx[keep], minlength=m)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = sums / counts
    centres = 0.5 * (edges[1:] + edges[:-1])
    good = counts > 0
    return centres[good], mean[good]


def extract_lines(z_um: np.ndarray, dx_mm: float, dy_mm: float, angle_deg: float
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Profiles along the direction ``angle_deg`` in the scan's frame (0: +x): ``(s_mm (n,),
    lines_um (m, n))``, NaN where invalid.

    A multiple of 90° takes rows or columns as they are (reversed for 180°, 270°); any other
    angle samples, by bilinear interpolation, lines of that direction every ``min(dx, dy)``
    across the largest square centred on the scan that the rotated lines stay inside, at
    ``min(dx, dy)`` along them (a point is invalid when any of its four neighbours is).
    """
    z = np.asarray(z_um, float)
    a = float(angle_deg) % 360.0
    quarter = round(a / 90.0)
    if abs(a - 90.0 * quarter) < 1e-9:
        q = quarter % 4
        lines, step = (z, dx_mm) if q in (0, 2) else (z.T, dy_mm)
        if q in (2, 3):
            lines = lines[:, ::-1]
        return np.arange(lines.shape[1]) * step, np.array(lines)
    h = min(dx_mm, dy_mm)
    ny, nx = z.shape
    side = min((nx - 1) * dx_mm, (ny - 1) * dy_mm) / (abs(np.cos(np.radians(a)))
                                                       + abs(np.sin(np.radians(a))))
    n = max(int(side / h) + 1, 2)
    s = (np.arange(n) - 0.5 * (n - 1)) * h
    u = np.array([np.cos(np.radians(a)), np.sin(np.radians(a))])
    v = np.array([-u[1], u[0]])
    cx, cy = 0.5 * (nx - 1) * dx_mm, 0.5 * (ny - 1) * dy_mm
    px = cx + s[None, :] * u[0] + s[:, None] * v[0]
    py = cy + s[None, :] * u[1] + s[:, None] * v[1]
    coords = np.array([py / dy_mm, px / dx_mm])
    ok = np.isfinite(z)
    vals = scipy.ndimage.map_coordinates(np.where(ok, z, 0.0), coords, order=1, mode="nearest")
    bad = scipy.ndimage.map_coordinates((~ok).astype(float), coords, order=1, mode="nearest")
    vals[bad > 0] = np.nan
    return s - s[0], vals


def line_psd(lines_um: np.ndarray, step_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """One-sided PSD [µm²·mm] averaged over the lines (each with its mean removed, invalid
    points set to it, a Hann window, Parseval: ``Σ P Δk ≈ mean(z²)``): ``(k_mm, P)``."""
    z = np.asarray(lines_um, float)
    z = z[np.isfinite(z).mean(axis=1) >= 0.5]
    if not len(z):
        return np.array([]), np.array([])
    z = z - np.nanmean(z, axis=1, keepdims=True)
    z = np.where(np.isfinite(z), z, 0.0)
    n = z.shape[1]
    w = np.hanning(n)
    f = np.fft.rfft(z * w, axis=1)
    p = np.abs(f) ** 2 * step_mm / (n * np.mean(w**2))
    p[:, 1:-1 if n % 2 == 0 else None] *= 2
    return np.fft.rfftfreq(n, step_mm), p.mean(axis=0)


def central_profile(s_mm: np.ndarray, lines_um: np.ndarray) -> tuple[np.ndarray, np.ndarray,
                                                                       int]:
    """The profile a stylus would trace: among the lines nearest the middle, the one with
    the longest run of valid points; that run, x from 0: ``(x_mm, z_um, line index)``."""
    m = len(lines_um)
    order = sorted(range(m), key=lambda i: abs(i - (m - 1) / 2))[: max(3, m // 10)]
    best = None
    for i in order:
        ok = np.isfinite(lines_um[i])
        # longest run of True
        edges = np.flatnonzero(np.diff(np.r_[0, ok.astype(int), 0]))
        runs = edges.reshape(-1, 2)
        if not len(runs):
            continue
        j = int(np.argmax(runs[:, 1] - runs[:, 0]))
        a, b = runs[j]
        if best is None or b - a > best[2] - best[1]:
            best = (i, a, b)
    if best is None:
        raise ValueError("no valid point on the central lines")
    i, a, b = best
    return s_mm[a:b] - s_mm[a], np.asarray(lines_um[i, a:b], float), i


def analyse_scan(z_um: np.ndarray, dx_mm: float, dy_mm: float, feed_angle_deg: float,
                 options: Mapping[str, Any]) -> tuple[xr.Dataset, tuple[np.ndarray,
                                                                         np.ndarray]]:
    """Chapter 2's analysis of one scan.

    Form removal (:func:`remove_form`, degree ``options["areal_form_degree"]``), the height
    parameters (:func:`height_parameters`), the radially averaged areal PSD
    (:func:`radial_psd`), the PSDs along and across the feed (:func:`line_psd` of the lines
    of :func:`extract_lines` at ``feed_angle_deg`` and ``feed_angle_deg + 90``), and the
    profile along the feed for the profile analysis (:func:`central_profile` of the
    form-removed scan, with the Rq of every line along the feed for the spread).

    Returns
    -------
    (xarray.Dataset, (x_mm, z_um))
        The dataset: the parameters as scalars, ``psd_radial (k_radial)``, ``psd_along
        (k_along)``, ``psd_across (k_across)``, ``valid_share``, ``profile_line``,
        ``line_rq_um`` (per line along the feed, ``line``); the extracted profile.

    Raises
    ------
    ValueError
        No valid point (the caller names the file).
    """
    z = np.asarray(z_um, float)
    ok = np.isfinite(z)
    if not ok.any():
        raise ValueError("the scan has no valid point")
    degree = int(options["areal_form_degree"])
    resid, _ = remove_form(z, dx_mm, dy_mm, degree)
    params = height_parameters(resid)
    kr, cr = radial_psd(resid, dx_mm, dy_mm)
    s_al, along = extract_lines(resid, dx_mm, dy_mm, feed_angle_deg)
    s_ac, across = extract_lines(resid, dx_mm, dy_mm, feed_angle_deg + 90.0)
    step_al = s_al[1] - s_al[0] if s_al.size > 1 else dx_mm
    step_ac = s_ac[1] - s_ac[0] if s_ac.size > 1 else dy_mm
    ka, pa = line_psd(along, step_al)
    kc, pc = line_psd(across, step_ac)
    x, zp, line = central_profile(s_al, along)
    with np.errstate(invalid="ignore"):
        centred = along - np.nanmean(along, axis=1, keepdims=True)
        rq = np.sqrt(np.nanmean(centred**2, axis=1))
    ds = xr.Dataset(
        {**{k: ((), v, {"units": "um" if k.endswith("_um") else "1",
                        "long_name": f"ISO 25178-2 {k.split('_')[0]} after form removal"})
            for k, v in params.items()},
         "psd_radial": ("k_radial", cr, {"units": "um2 mm2",
                                         "long_name": "areal PSD, radial average"}),
         "psd_along": ("k_along", pa, {"units": "um2 mm", "long_name": "PSD along the feed"}),
         "psd_across": ("k_across", pc, {"units": "um2 mm",
                                         "long_name": "PSD across the feed"}),
         "line_rq_um": ("line", rq, {"units": "um",
                                     "long_name": "RMS of each profile along the feed"}),
         "valid_share": ((), float(ok.mean()), {"units": "1",
                                                 "long_name": "share of valid points"}),
         "profile_line": ((), int(line), {"units": "1",
                                          "long_name": "line taken as the cut's profile"})},
        coords={"k_radial": ("k_radial", kr, {"units": "1/mm",
                                              "long_name": "spatial frequency |k|"}),
                "k_along": ("k_along", ka, {"units": "1/mm",
                                            "long_name": "spatial frequency along the feed"}),
                "k_across": ("k_across", kc, {"units": "1/mm",
                                              "long_name": "spatial frequency across the feed"}),
                "line": ("line", np.arange(len(rq)), {"units": "1",
                                                      "long_name": "profile along the feed"})},
        attrs={"form_degree": degree, "feed_angle_deg": float(feed_angle_deg),
               "dx_mm": float(dx_mm), "dy_mm": float(dy_mm), "nx": int(z.shape[1]),
               "ny": int(z.shape[0])})
    return ds, (x, zp)
