"""Settings of the per-cut force analysis (config section ``forces``): the streaming
spectra's parameters and those of the peak search. Their defaults are the schema's
(``src/robomill/data/schemas/config/forces.schema.yaml``; :func:`robomill.settings.schema_default`).
"""

from __future__ import annotations

from dataclasses import dataclass

from robomill.settings import FromMapping, schema_default


@dataclass
class ForceAnalysisSettings(FromMapping):
    """Parameters of the per-cut force analysis (config section ``forces``).

    ``decimation`` ``None`` (the default): derived from each record's rate
    (:func:`robomill.spectra.auto_decimation`); an integer is used as given and must leave
    ``fs/decimation > 2 × lowband_hz``.
    """

    welch_nperseg: int = schema_default("forces", "welch_nperseg")
    decimation: int | None = schema_default("forces", "decimation")
    lowband_hz: float = schema_default("forces", "lowband_hz")
    fir_atten_db: float = schema_default("forces", "fir_atten_db")
    envelope_blocks: int = schema_default("forces", "envelope_blocks")
    excerpt_samples: int = schema_default("forces", "excerpt_samples")
    lowband_max_s: float = schema_default("forces", "lowband_max_s")


@dataclass
class ForcePeakSettings(FromMapping):
    """How the dominant and kinematic peaks of a cut are searched (config section
    ``forces``; :func:`robomill.forces.peaks.cut_peaks`).

    A peak is a local maximum of the low-band power (summed over the axes) inside its band
    that rises ``*_prominence_db`` above the local floor, the median power within
    ``±*_floor_halfwidth`` of it (:func:`robomill.spectra.prominent_peaks`).
    """

    dominant_band_hz: tuple[float, float] = tuple(schema_default("forces", "dominant_band_hz"))
    kinematic_band_per_mm: tuple[float, float] = tuple(
        schema_default("forces", "kinematic_band_per_mm"))
    dominant_prominence_db: float = schema_default("forces", "dominant_prominence_db")
    dominant_floor_halfwidth_hz: float = schema_default("forces", "dominant_floor_halfwidth_hz")
    kinematic_prominence_db: float = schema_default("forces", "kinematic_prominence_db")
    kinematic_floor_halfwidth_per_mm: float = schema_default(
        "forces", "kinematic_floor_halfwidth_per_mm")
    min_peak_cycles: float = schema_default("forces", "min_peak_cycles")
