"""Settings of the per-cut force analysis (config section ``forces``): the streaming
spectra's parameters and those of the peak search.
"""

from __future__ import annotations

from dataclasses import dataclass

from robomill.settings import FromMapping


@dataclass
class ForceAnalysisSettings(FromMapping):
    """Parameters of the per-cut force analysis (config section ``forces``).

    ``decimation`` ``None`` (the default): derived from each record's rate
    (:func:`robomill.spectra.auto_decimation`); an integer is used as given and must leave
    ``fs/decimation > 2 × lowband_hz``.
    """

    welch_nperseg: int = 16384
    decimation: int | None = None
    lowband_hz: float = 250.0
    fir_atten_db: float = 120.0
    envelope_blocks: int = 400
    excerpt_samples: int = 1000
    lowband_max_s: float = 300.0


@dataclass
class ForcePeakSettings(FromMapping):
    """How the dominant and kinematic peaks of a cut are searched (config section
    ``forces``; :func:`robomill.forces.peaks.cut_peaks`).

    A peak is a local maximum of the low-band power (summed over the axes) inside its band
    that rises ``*_prominence_db`` above the local floor, the median power within
    ``±*_floor_halfwidth`` of it (:func:`robomill.spectra.prominent_peaks`).
    """

    dominant_band_hz: tuple[float, float] = (15.0, 250.0)
    kinematic_band_per_mm: tuple[float, float] = (0.3, 1.0)
    dominant_prominence_db: float = 12.0
    dominant_floor_halfwidth_hz: float = 25.0
    kinematic_prominence_db: float = 10.0
    kinematic_floor_halfwidth_per_mm: float = 0.25
    min_peak_cycles: float = 10.0
