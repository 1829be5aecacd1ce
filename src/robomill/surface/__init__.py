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

from robomill._lazy import lazy_exports

_EXPORTS = {  # public name → submodule
    "settings": "options",
    "MECHANISMS": "peaks",
    "attribute_mechanisms": "peaks",
    "profile_peaks": "peaks",
    "ALPHA": "profile",
    "amplitude_parameters": "profile",
    "detrend_profile": "profile",
    "gaussian_filter": "profile",
    "gaussian_weights": "profile",
    "rz_um": "profile",
    "split_profile": "profile",
    "analyse_profile": "psd",
    "segment_lengths_mm": "psd",
    "spectra_dataset": "psd",
    "recovery_table": "recovery",
    "surface_findings": "findings",
    "PROFILE_OFFSET_UM": "figures",
    "detrend_figure": "figures",
    "peak_mechanisms_figure": "figures",
    "profiles_figure": "figures",
    "rms_vs_feed_figure": "figures",
    "roughness_feed_figure": "figures",
    "spectra_figure": "figures",
    "spectrum_figure": "figures",
    "waviness_figure": "figures",
    "METRIC_COLUMNS": "study",
    "PEAK_TABLE_COLUMNS": "study",
    "gather_surface": "study",
    "DESIGN_KEYS": "tables",
    "DIRECTION_ORDER": "tables",
    "compare_with_thesis": "tables",
    "comparison_summary": "tables",
    "design_table": "tables",
    "direction_means": "tables",
    "example_cut": "tables",
    "figure_directions": "tables",
    "path_label": "tables",
    "peak_counts": "tables",
    "plot_groups": "tables",
    "with_directions": "tables",
    "feed_correlation": "tables",
    "load_thesis_tables": "tables",
    "path_direction": "tables",
    "rms_table": "tables",
    "common_join": "psd",
    "areal_psd_figure": "figures",
    "REFERENCE_COLUMNS": "reference",
    "add_reference_findings": "reference",
    "profile_parameter": "reference",
    "reference_comparison": "reference",
    "PARAMETERS": "areal",
    "analyse_scan": "areal",
    "central_profile": "areal",
    "extract_lines": "areal",
    "height_parameters": "areal",
    "line_psd": "areal",
    "psd_2d": "areal",
    "radial_psd": "areal",
    "remove_form": "areal",
    "AREAL_COLUMNS": "areal_study",
    "COMPARED": "areal_study",
    "add_areal_findings": "areal_study",
    "gather_areal": "areal_study",
    "table_column": "tables",
}

__getattr__, __dir__, __all__ = lazy_exports(__name__, _EXPORTS)
