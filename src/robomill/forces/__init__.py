"""Cutting forces of robotic slot milling (thesis §3.1), one subject per module:

- :mod:`~robomill.forces.model`: the mechanistic force model (eq. 3.1), engagement window,
  mean and band-limited forces;
- :mod:`~robomill.forces.coefficients`: cutting-coefficient identification and its sanity
  flags;
- :mod:`~robomill.forces.stream`: the chunked analysis of one record (mean, Welch PSD,
  low-band thesis power, envelope);
- :mod:`~robomill.forces.peaks`: dominant, kinematic and harmonic peaks, nearest modes;
- :mod:`~robomill.forces.study`: the per-cut dataset and the gathered study;
- :mod:`~robomill.forces.settings`: the ``forces`` config section's dataclasses;
- :mod:`~robomill.forces.findings`: every number and verdict chapter 3.1 states (the
  dominant peak against the identified modes, ``forces.mode_match_hz``; the kinematic peak's
  resolution flag, ``forces.min_peak_cycles``; the records, force levels and coefficients);
- :mod:`~robomill.forces.tables`: the tables chapter 3.1 shows and the cuts of its figures;
- :mod:`~robomill.forces.figures`: chapter 3.1's figures (matplotlib).

Decimation and FIR design live in :mod:`robomill.spectra`, feed per tooth and tooth passing
in :mod:`robomill.experiment`. Importing this package imports none of them: each public name
is loaded from its module on first use (PEP 562). Rule scripts and notebooks import from the
modules themselves, so that the workflow ties a rule only to the modules it uses.
"""

from __future__ import annotations

from robomill.lazy import lazy_exports

_EXPORTS = {  # module → its public names
    "model": ("AXES", "BASIS", "COEFFICIENT_UNITS", "MILLING_MODES", "CuttingCoefficients",
              "SlotForceTables", "cut_frame", "engagement_angles_rad", "mean_milling_forces",
              "mean_slot_forces", "slot_force_tables", "slot_forces",
              "slot_forces_band_limited"),
    "coefficients": ("FLAG_COLUMNS", "coefficient_flag_sentence", "coefficient_flags",
                     "identify_cutting_coefficients", "identify_cutting_coefficients_general",
                     "not_physical_reasons"),
    "stream": ("ForceSpectrumAccumulator", "analyse_force_record"),
    "peaks": ("cut_peaks", "dominant_peak", "harmonic_powers", "nearest_modes"),
    "study": ("force_cut_dataset", "gather_force_study"),
    "settings": ("ForceAnalysisSettings", "ForcePeakSettings"),
    "findings": ("forces_findings",),
    "tables": ("FigureCuts", "coefficient_table", "direction_text", "figure_cuts",
               "harmonic_table", "peak_table", "planted_coefficients", "process_table"),
    "figures": ("direction_figure", "full_band_figure", "mean_forces_figure",
                "model_shape_figure", "record_figure"),
    "robomill.spectra": ("LOWBAND_OVERSAMPLING", "StreamDecimator", "auto_decimation",
                         "decimate_whole", "lowpass_fir"),
    "robomill.experiment": ("feed_per_tooth_mm", "tooth_passing_hz"),
}
__getattr__, __dir__, __all__ = lazy_exports(__name__, _EXPORTS)
