"""The streaming analysis of one cut's force record: mean forces, Welch PSD, the low-band
thesis power of the whole record, envelope and excerpt, accumulated chunk by chunk in bounded
memory (thesis §3.1, eq. 2.3).
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from robomill.forces.settings import ForceAnalysisSettings
from robomill.spectra import StreamDecimator, auto_decimation, lowpass_fir


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

