"""Spectral helpers shared by the surface, force and straightness analyses: thesis spectra,
Welch PSDs and the anti-alias decimation of long records; the peak picking lives in
:mod:`robomill.spectral_peaks` and is re-exported here.

The thesis defines its spectra explicitly (thesis eqs. 2.1–2.6):

.. math::

    Z(k) = \\sum_{n=0}^{N-1} z(n) e^{-j 2\\pi k n / N}, \\quad
    A(k) = |Z(k)|/N, \\quad P(k) = |Z(k)|^2 / N^2, \\quad f_k = k f_s / N

and the RMS by Parseval, :math:`R_q = \\sqrt{\\sum_k P(k)}` over all N bins (eq. 2.6). The
one-sided forms fold the negative frequencies onto the positive ones (×2 for 0 < k < N/2),
so the one-sided power still sums to the mean square. ``fs`` is in samples per unit of the
abscissa: mm⁻¹ for profiles (spatial frequency), Hz for time series.

Welch PSDs and chunked accumulation use :func:`scipy.signal.welch`/``csd`` conventions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from robomill.spectral_peaks import (  # noqa: F401  (the peak helpers, re-exported)
    find_peaks_spectrum,
    interpolate_peak,
    local_floor,
    peak_offset_bins,
    prominent_peaks,
)


@dataclass(frozen=True)
class Spectrum:
    """One-sided thesis spectrum of a real signal."""

    f: np.ndarray
    """Frequency of each bin, k·fs/N (mm⁻¹ or Hz)."""
    amplitude: np.ndarray
    """One-sided normalized amplitude (peak amplitude of a sinusoid at its bin)."""
    power: np.ndarray
    """One-sided normalized power (sums to the mean square of the signal)."""


def thesis_dft(z: np.ndarray, fs: float, *, axis: int = -1) -> tuple[np.ndarray, np.ndarray]:
    """Two-sided DFT Z(k) (thesis eq. 2.1) and the bin frequencies k·fs/N (``fftfreq``)."""
    import scipy.fft  # here, as below: `import robomill.spectra` stays free of SciPy

    z = np.asarray(z, dtype=float)
    n = z.shape[axis]
    return scipy.fft.fft(z, axis=axis), scipy.fft.fftfreq(n, d=1.0 / fs)


def thesis_spectrum(z: np.ndarray, fs: float, *, axis: int = -1) -> Spectrum:
    """One-sided normalized amplitude A(k) and power P(k) (thesis eqs. 2.2, 2.3).

    For a sinusoid ``a·sin(2π f0 n/fs)`` with f0 on a bin, ``amplitude`` at f0 is ``a`` and
    ``power`` at f0 is ``a²/2`` (two-sided ``|Z|/N = a/2`` at ±f0, folded). ``power.sum()``
    equals ``mean(z**2)`` (Parseval, eq. 2.6).

    Examples
    --------
    >>> n = np.arange(1000); z = 3.0 * np.sin(2 * np.pi * 50 * n / 1000)
    >>> s = thesis_spectrum(z, fs=1000.0)
    >>> float(s.f[np.argmax(s.amplitude)]), round(float(s.amplitude.max()), 12)
    (50.0, 3.0)
    """
    import scipy.fft

    z = np.moveaxis(np.asarray(z, dtype=float), axis, -1)
    n = z.shape[-1]
    Z = scipy.fft.rfft(z, axis=-1)
    amp = np.abs(Z) / n
    power = amp**2
    fold = np.ones(Z.shape[-1])
    fold[1:] = 2.0
    if n % 2 == 0:
        fold[-1] = 1.0  # Nyquist bin appears once
    f = scipy.fft.rfftfreq(n, d=1.0 / fs)
    amp_1 = amp * np.where(fold == 2.0, 2.0, 1.0)
    return Spectrum(f, np.moveaxis(amp_1, -1, axis), np.moveaxis(power * fold, -1, axis))


def parseval_rms(z: np.ndarray, *, axis: int = -1) -> np.ndarray:
    """RMS from the normalized power spectrum, sqrt(Σ_k P(k)) (thesis eq. 2.6)."""
    import scipy.fft

    z = np.asarray(z, dtype=float)
    Z = scipy.fft.fft(z, axis=axis)
    n = z.shape[axis]
    return np.sqrt(np.sum(np.abs(Z) ** 2, axis=axis) / n**2)


def segment_signal(z: np.ndarray, n_segment: int) -> np.ndarray:
    """Split a 1-D signal into ``len(z) // n_segment`` equal segments ``(m, n_segment)``
    (the remainder at the end is dropped)."""
    z = np.asarray(z, dtype=float)
    m = z.size // n_segment
    if m < 1:
        raise ValueError(f"signal of {z.size} samples is shorter than one segment "
                         f"({n_segment} samples)")
    return z[: m * n_segment].reshape(m, n_segment)


def segment_averaged_spectrum(z: np.ndarray, fs: float, segment_length: float, *,
                              detrend: str | None = "constant") -> Spectrum:
    """The thesis' segment method: equal segments, a spectrum per segment, averaged.

    ``segment_length`` is in the abscissa unit (mm for profiles). Power is averaged; the
    amplitude returned is sqrt of the averaged one-sided power × 2 (a sinusoid's amplitude).
    ``detrend`` removes each segment's mean (``"constant"``) or line (``"linear"``).
    """
    n_seg = int(round(segment_length * fs))
    segs = segment_signal(z, n_seg)
    if detrend:
        import scipy.signal

        segs = scipy.signal.detrend(segs, axis=-1, type=detrend)
    s = thesis_spectrum(segs, fs)
    power = s.power.mean(axis=0)
    amp = np.sqrt(2.0 * power)
    amp[0] = np.sqrt(power[0])
    return Spectrum(s.f, amp, power)


def segment_rms(z: np.ndarray, fs: float, segment_length: float, *,
                detrend: str | None = "constant") -> float:
    """RMS by the segment method: sqrt of the segment-averaged power summed (eq. 2.6)."""
    return float(np.sqrt(segment_averaged_spectrum(z, fs, segment_length,
                                                   detrend=detrend).power.sum()))


def welch_psd(x: np.ndarray, fs: float, *, nperseg: int, axis: int = -1,
              window: str = "hann", detrend: str | bool = "constant") -> tuple[np.ndarray,
                                                                             np.ndarray]:
    """One-sided power spectral density (units²/Hz or units²·mm) by Welch's method."""
    import scipy.signal

    return scipy.signal.welch(x, fs=fs, nperseg=nperseg, axis=axis, window=window,
                              detrend=detrend, scaling="density")


class WelchAccumulator:
    """Welch PSD accumulated chunk by chunk, in memory independent of the record length.

    Feed consecutive chunks with :meth:`add`; segments (``nperseg``, 50 % overlap, Hann)
    straddling chunk boundaries are handled by carrying the tail over, so the result equals
    :func:`scipy.signal.welch` on the whole record (``detrend='constant'``, mean average).
    """

    def __init__(self, fs: float, nperseg: int, n_channels: int = 1, window: str = "hann"):
        import scipy.signal

        self.fs, self.nperseg, self.step = fs, nperseg, nperseg // 2
        self.win = scipy.signal.get_window(window, nperseg)
        self.scale = 1.0 / (fs * np.sum(self.win**2))
        self.sum = np.zeros((n_channels, nperseg // 2 + 1))
        self.count = 0
        self.tail = np.zeros((n_channels, 0))

    def add(self, chunk: np.ndarray) -> None:
        """Add samples ``(n_channels, n)`` (or ``(n,)`` for one channel)."""
        import scipy.fft

        chunk = np.atleast_2d(np.asarray(chunk, dtype=float))
        buf = np.concatenate([self.tail, chunk], axis=1)
        n_seg = 0 if buf.shape[1] < self.nperseg else 1 + (buf.shape[1] - self.nperseg) // self.step
        if n_seg:
            idx = np.arange(n_seg)[:, None] * self.step + np.arange(self.nperseg)[None, :]
            segs = buf[:, idx]  # (channels, n_seg, nperseg)
            segs = segs - segs.mean(axis=-1, keepdims=True)
            X = scipy.fft.rfft(segs * self.win, axis=-1)
            self.sum += np.sum(np.abs(X) ** 2, axis=1)
            self.count += n_seg
        self.tail = buf[:, n_seg * self.step:]

    def result(self) -> tuple[np.ndarray, np.ndarray]:
        """(f, psd ``(n_channels, nfreq)``) — one-sided density."""
        import scipy.fft

        if self.count == 0:
            raise ValueError("fewer samples than one Welch segment")
        psd = self.sum / self.count * self.scale
        psd[:, 1:] *= 2.0
        if self.nperseg % 2 == 0:
            psd[:, -1] /= 2.0
        return scipy.fft.rfftfreq(self.nperseg, 1.0 / self.fs), psd


def below_resolution(f: np.ndarray | float, resolution: np.ndarray | float, *,
                     min_cycles: float) -> np.ndarray:
    """Sanity flag: peaks a record cannot resolve.

    A DFT of a record of length ``T`` has bins ``k/T``; a peak at frequency ``f`` lies in bin
    ``k = f T`` and is known to half a bin, a relative uncertainty ``1/(2 f T)``. A peak with
    fewer than ``min_cycles`` periods in the record (``f < min_cycles × resolution``, the
    resolution being ``1/T``) is flagged, and so is a missing (NaN) peak: 10 cycles means the
    frequency is known to ±5 %. Works in time (Hz, 1/s) and space (1/mm, 1/mm) alike.

    Examples
    --------
    >>> below_resolution([0.5, 0.5], [1 / 40, 1 / 10], min_cycles=10).tolist()
    [False, True]
    """
    f = np.asarray(f, float)
    res = np.asarray(resolution, float)
    return ~(f >= min_cycles * res)


# ---- anti-alias decimation of long records (exact chunk by chunk) -------------------------
def lowpass_fir(fs_hz: float, pass_hz: float, stop_hz: float, atten_db: float = 120.0
                ) -> np.ndarray:
    """Linear-phase anti-alias FIR (Kaiser window method, unit DC gain) passing ``pass_hz``
    and attenuating ``atten_db`` from ``stop_hz`` on (:func:`scipy.signal.kaiserord`)."""
    if not 0 < pass_hz < stop_hz <= fs_hz / 2:
        raise ValueError(f"need 0 < pass ({pass_hz}) < stop ({stop_hz}) <= fs/2 ({fs_hz / 2})")
    import scipy.signal
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
            import scipy.signal
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
    x = np.atleast_2d(np.asarray(x, float))
    import scipy.signal
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
