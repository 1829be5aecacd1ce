"""Peaks of a spectrum: local maxima that stand out of their neighbourhood (never a side lobe
or the skirt of a stronger line), their frequency refined within the bin, and the local floor
they are judged against; shared by the force, surface, straightness and modal analyses.

Re-exported by :mod:`robomill.spectra` (``spectra.find_peaks_spectrum`` etc.).
"""

from __future__ import annotations

import warnings

import numpy as np


def find_peaks_spectrum(f: np.ndarray, power: np.ndarray, *, fmin: float = 0.0,
                        fmax: float | None = None, n: int = 5,
                        prominence_ratio: float = 3.0, floor: float | None = None,
                        local_ratio: float = 0.0, halfwidth_points: int = 0,
                        search_from: float | None = None, envelope_points: int = 1,
                        interpolate: bool = False,
                        one_sided_below: float | None = None) -> list[tuple[float, float]]:
    """The ``n`` strongest peaks of ``power`` within [fmin, fmax], as (f, power), by frequency.

    A peak is a local maximum (:func:`scipy.signal.find_peaks`) that

    * exceeds ``prominence_ratio`` × ``floor`` (default: the median power of the band, so that
      noise floors give no peaks), and
    * stands out of its neighbourhood: its prominence (:func:`scipy.signal.peak_prominences`
      within ±``halfwidth_points``: its height above the higher of the lowest points on either
      side before a higher point) is at least ``local_ratio`` × the *local floor*, the median
      power over the ``2 halfwidth_points + 1`` points around it (shifted inwards at the ends
      of the grid). Both are taken on the running maximum of the power over
      ``envelope_points`` points (one resolution bin of a zero-padded spectrum: it fills the
      nulls between a window's side lobes). A side lobe, or a bump on the skirt of a
      stronger line, has no prominence on that envelope, or little against the skirt's power
      around it: it is no peak.

    Local maxima are looked for from ``search_from`` (default ``fmin``; lower lets a peak at
    the band edge count as a local maximum) and kept from ``fmin`` up. None qualifying: an
    empty list.

    ``one_sided_below``: below this frequency the spectrum holds no signal of interest (e.g.
    what a removed trend leaks under ``fmin``); a peak whose ±``halfwidth_points``
    neighbourhood reaches below it, and whose left side climbs to a summit there (it stands on
    that leakage's skirt, not on a line of the band), is judged on its
    upper side alone: its height above the lowest point within ``halfwidth_points`` above it
    and before a higher point (the right base of its prominence: a side lobe on a stronger
    line's lower skirt has none), against the median over the ``2 halfwidth_points + 1``
    points from it upwards.

    With ``interpolate`` the frequency is refined within the bin (:func:`interpolate_peak`,
    parabolic on the log power); the power stays the bin's.
    """
    f = np.asarray(f, float)
    power = np.asarray(power, float)
    hi = fmax if fmax is not None else f.max()
    lo = fmin if search_from is None else min(search_from, fmin)
    band = (f >= fmin) & (f <= hi)
    sel = np.flatnonzero((f >= lo) & (f <= hi))
    if sel.size < 3:
        return []
    import scipy.ndimage
    import scipy.signal

    floor = float(np.median(power[band])) if floor is None else float(floor)
    idx, _ = scipy.signal.find_peaks(power[sel], height=prominence_ratio * floor)
    idx = sel[idx]
    if local_ratio > 0 and idx.size:
        h = max(int(halfwidth_points), 1)
        env = scipy.ndimage.maximum_filter1d(power, size=max(int(envelope_points), 1))
        with warnings.catch_warnings():  # a skirt point has no prominence: said, not warned
            warnings.filterwarnings("ignore", message="some peaks have a prominence of 0")
            prom = scipy.signal.peak_prominences(env, idx, wlen=2 * h + 1)[0]
        start = np.clip(idx - h, 0, max(env.size - 2 * h - 1, 0))
        local = np.array([np.median(env[a:a + 2 * h + 1]) for a in start])
        if one_sided_below is not None:
            edge = np.searchsorted(f, one_sided_below)
            for j in np.flatnonzero(idx - h < edge):
                below = env[max(idx[j] - h, 0):idx[j]]
                higher = np.flatnonzero(below > env[idx[j]])
                if not higher.size:
                    continue
                summit = idx[j] - below.size + higher[-1]  # climb to what rises on the left
                while summit > 0 and env[summit - 1] >= env[summit]:
                    summit -= 1
                if summit >= edge:
                    continue  # a line of the band rises on its left: judged on both sides
                above = env[idx[j]:idx[j] + 2 * h + 1]
                upper = above[1:h + 1]  # the right base: lowest point before a higher one
                higher = np.flatnonzero(upper > above[0])
                upper = upper[:higher[0]] if higher.size else upper
                prom[j] = above[0] - upper.min() if upper.size else 0.0
                local[j] = np.median(above)
        idx = idx[prom >= local_ratio * local]
    idx = idx[f[idx] >= fmin]
    idx = idx[np.argsort(power[idx], kind="stable")[::-1][:n]]
    out = [(interpolate_peak(f, power, i) if interpolate else float(f[i]), float(power[i]))
           for i in idx]
    return sorted(out)


def interpolate_peak(f: np.ndarray, power: np.ndarray, k: int) -> float:
    """Frequency of the peak at bin ``k`` refined within the bin: the vertex of the parabola
    through the log powers of bins ``k − 1, k, k + 1``.

    .. math:: δ = \\frac{1}{2} \\frac{\\ln P_{k-1} − \\ln P_{k+1}}
                             {\\ln P_{k-1} − 2 \\ln P_k + \\ln P_{k+1}}, \\qquad
              \\hat f = f_k + δ \\, Δf

    (quadratic interpolation of the log spectrum; exact for a Gaussian peak, within a few
    hundredths of a bin for a Hann-windowed sinusoid: Gasior & Gonzalez 2004, "Improving FFT
    frequency measurement resolution by parabolic and Gaussian spectrum interpolation",
    AIP Conf. Proc. 732). ``|δ| ≤ 1/2`` for a local maximum; at either end of the grid, or
    with a zero power among the three, the bin frequency ``f_k`` is returned.

    Examples
    --------
    >>> f = np.arange(64.0); p = np.exp(-0.5 * ((f - 20.3) / 1.5) ** 2)
    >>> round(interpolate_peak(f, p, 20), 6)
    20.3
    """
    f = np.asarray(f, float)
    p = np.asarray(power, float)
    if k <= 0 or k >= p.size - 1 or np.any(p[k - 1:k + 2] <= 0):
        return float(f[k])
    a, b, c = np.log(p[k - 1:k + 2])
    den = a - 2 * b + c
    delta = 0.5 * (a - c) / den if den < 0 else 0.0
    return float(f[k] + np.clip(delta, -0.5, 0.5) * (f[k + 1] - f[k]))


def peak_offset_bins(power: np.ndarray, i: int, *, window: str = "rect") -> float:
    """Position of the peak at bin ``i`` of a power spectrum within the bin, ``δ`` in
    [−½, ½] bins (the peak lies at ``f[i] + δ Δf``), from bins ``i − 1, i, i + 1``.

    ``window="hann"`` (Welch and other Hann-windowed spectra), and a peak broader than the
    rectangular window's main lobe: the parabola through the logarithms
    ``a, b, c = ln P[i−1], ln P[i], ln P[i+1]`` (Gaussian interpolation; Gasior & Gonzalez
    2004, CERN-AB-2004-023, eq. 6)

    .. math:: δ = \\frac{1}{2} \\frac{a − c}{a − 2 b + c}

    exact for a Gaussian peak and within 0.02 bin for a Hann-windowed line.

    ``window="rect"`` (the thesis power of an unwindowed record, eq. 2.3): a line between bins
    has the Dirichlet amplitude ``|Z(i + m)| ∝ 1/|m − δ|``, which the log-parabola pulls
    towards the bin by up to 0.17 bin (δ = 0.3 comes out 0.13). A peak as narrow as that lobe
    (its smaller neighbour at most half its amplitude; a line has at most a third) is
    interpolated with the two-bin ratio of the rectangular window (Jain, Collins & Davis
    1979, IEEE Trans. Instrum. Meas. 28(2), 113-122): with amplitudes ``A = √P``, the larger
    neighbour ``A_n`` on side ``s = ±1``,

    .. math:: δ = s \\frac{A_n}{A_i + A_n}

    exact for a line; a broader peak (a resonance resolved over several bins) takes the
    log-parabola. An end bin, or a zero neighbour, gives 0.

    Examples
    --------
    >>> k = np.arange(-8, 9)
    >>> round(peak_offset_bins(1.0 / (k - 0.3) ** 2, 8), 3)
    0.3
    """
    p = np.asarray(power, float)
    if i <= 0 or i >= p.size - 1 or not np.all(p[i - 1:i + 2] > 0):
        return 0.0
    lo, mid, hi = p[i - 1], p[i], p[i + 1]
    if window == "rect" and min(lo, hi) <= 0.25 * mid:
        side, near = (1.0, hi) if hi >= lo else (-1.0, lo)
        return float(side * np.sqrt(near) / (np.sqrt(mid) + np.sqrt(near)))
    a, b, c = np.log([lo, mid, hi])
    curv = a - 2.0 * b + c
    return float(np.clip(0.5 * (a - c) / curv, -0.5, 0.5)) if curv < 0 else 0.0


def local_floor(power: np.ndarray, half_width_bins: int) -> np.ndarray:
    """The local floor of a spectrum: the median of ``power`` over ``±half_width_bins``
    around each bin (mirrored at the ends; :func:`scipy.ndimage.median_filter`). A median
    ignores the peak it surrounds, so a line or resonance narrower than the window stands
    out of it."""
    import scipy.ndimage

    w = max(int(half_width_bins), 1)
    return scipy.ndimage.median_filter(np.asarray(power, float), size=2 * w + 1,
                                       mode="reflect")


def prominent_peaks(f: np.ndarray, power: np.ndarray, band: tuple[float, float], *,
                    prominence_db: float, floor_half_width: float,
                    exclude: np.ndarray | tuple = (), exclude_width: float = 0.0
                    ) -> np.ndarray:
    """Bins of the local maxima of ``power`` in ``band`` (inclusive) that stand out of their
    neighbourhood, ordered by decreasing power.

    A bin qualifies when it is a local maximum of the **whole** spectrum
    (:func:`scipy.signal.find_peaks`: its neighbours are lower, so the falling skirt of a
    line never qualifies), lies farther than ``exclude_width`` from every ``exclude``
    frequency, and rises ``prominence_db`` above the local floor ``F``
    (:func:`local_floor`, median over ``±floor_half_width`` in the unit of ``f``): its power
    is at least ``r F`` and its prominence (the height above the higher of the two lowest
    points that separate it from higher peaks) at least ``(r − 1) F``, with
    ``r = 10^(prominence_db/10)``. A ripple on the skirt of a strong line, or a noise bin of
    a flat floor, does not.

    Parameters
    ----------
    f
        Uniform frequency grid (any unit: Hz, 1/mm).
    power
        Power per bin, same length.
    band
        ``(low, high)`` searched, unit of ``f``.
    prominence_db
        Required rise above the local floor [dB of power].
    floor_half_width
        Half-width of the floor's window, unit of ``f``.
    exclude, exclude_width
        Frequencies left out (a spindle's harmonics) and the half-width around each.

    Returns
    -------
    numpy.ndarray
        Integer bin indices (empty when no bin qualifies).
    """
    f = np.asarray(f, float)
    p = np.asarray(power, float)
    if p.size < 3:
        return np.zeros(0, int)
    df = float(f[1] - f[0])
    floor = local_floor(p, int(round(floor_half_width / df)))
    r = 10.0 ** (float(prominence_db) / 10.0)
    import scipy.signal
    idx, _ = scipy.signal.find_peaks(p, height=r * floor, prominence=(r - 1.0) * floor)
    ok = (f[idx] >= band[0]) & (f[idx] <= band[1])
    for fx in np.atleast_1d(np.asarray(exclude, float)):
        ok &= np.abs(f[idx] - fx) > exclude_width
    idx = idx[ok]
    return idx[np.argsort(p[idx], kind="stable")[::-1]]
