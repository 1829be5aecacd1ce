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

One subject per submodule: :mod:`~robomill.surface.profile` (detrending, Gaussian filter,
amplitude parameters), :mod:`~robomill.surface.psd` (one profile's analysis and spectra),
:mod:`~robomill.surface.peaks` (peaks and mechanisms), :mod:`~robomill.surface.study`
(gathering the cuts), :mod:`~robomill.surface.tables` (chapter tables),
:mod:`~robomill.surface.findings` (what chapter 2 states), :mod:`~robomill.surface.figures`
(chapter 2's figures),
:mod:`~robomill.surface.recovery` (against the planted truth),
:mod:`~robomill.surface.reference` (ours beside the parameters a file states about itself),
:mod:`~robomill.surface.areal` (one areal scan: ISO 25178-2 parameters, areal PSD, profiles
along the feed), :mod:`~robomill.surface.areal_study` (the scans gathered) and
:mod:`~robomill.surface.options` (settings). The public names are importable from this
package, loaded from their submodule on first use (importing the package imports nothing);
rule scripts and notebooks import from the submodules.
"""

from robomill.lazy import lazy_exports

_EXPORTS = {  # submodule → its public names
    "options": ("settings",),
    "peaks": ("MECHANISMS", "attribute_mechanisms", "profile_peaks"),
    "profile": (
        "ALPHA",
        "amplitude_parameters",
        "detrend_profile",
        "gaussian_filter",
        "gaussian_weights",
        "rz_um",
        "split_profile",
    ),
    "psd": ("analyse_profile", "segment_lengths_mm", "spectra_dataset", "common_join"),
    "recovery": ("recovery_table",),
    "findings": ("surface_findings",),
    "figures": (
        "PROFILE_OFFSET_UM",
        "detrend_figure",
        "peak_mechanisms_figure",
        "profiles_figure",
        "rms_vs_feed_figure",
        "roughness_feed_figure",
        "spectra_figure",
        "spectrum_figure",
        "waviness_figure",
        "areal_psd_figure",
    ),
    "study": ("METRIC_COLUMNS", "PEAK_TABLE_COLUMNS", "gather_surface"),
    "tables": (
        "DESIGN_KEYS",
        "DIRECTION_ORDER",
        "compare_with_thesis",
        "comparison_summary",
        "design_table",
        "direction_means",
        "example_cut",
        "figure_directions",
        "path_label",
        "peak_counts",
        "plot_groups",
        "with_directions",
        "feed_correlation",
        "load_thesis_tables",
        "path_direction",
        "rms_table",
        "table_column",
    ),
    "reference": (
        "REFERENCE_COLUMNS",
        "add_reference_findings",
        "profile_parameter",
        "reference_comparison",
    ),
    "areal": (
        "PARAMETERS",
        "analyse_scan",
        "central_profile",
        "extract_lines",
        "height_parameters",
        "line_psd",
        "psd_2d",
        "radial_psd",
        "remove_form",
    ),
    "areal_study": ("AREAL_COLUMNS", "COMPARED", "add_areal_findings", "gather_areal"),
}

__getattr__, __dir__, __all__ = lazy_exports(__name__, _EXPORTS)
