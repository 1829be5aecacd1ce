"""The ``config.yaml: surface`` settings of the profile analysis, with their defaults."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

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
    "local_prominence_ratio": 1.0,
    "local_floor_halfwidth_bins": 10,
    "match_tolerance": 0.2,
    "min_feed_ratio": 1.5,
    "min_peak_cycles": 2.5,
    "mechanism_share_min": 0.5,
    "temporal_quantiles": [0.1, 0.9],
    "waviness_plot_max_per_mm": 1.0,
    "roughness_plot_max_per_mm": 30.0,
}
"""Defaults of ``config.yaml: surface`` (the schema fills the same values)."""


def settings(section: Mapping[str, Any] | None) -> dict[str, Any]:
    """``surface`` settings with defaults filled."""
    return {**DEFAULTS, **dict(section or {})}
