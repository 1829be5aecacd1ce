"""Path straightness of the robot (thesis §3.2): spatial re-ordering, PSD, gear attribution.

A laser tracker samples the TCP while the robot moves along a straight cut path (no
cutting). The analysis

1. re-orders the time series in space (:func:`spatial_profile`): the best straight line is
   fitted to the points, each point gets its distance ``s`` along that line and its
   deviation perpendicular to it (a *lateral* horizontal and a *vertical* component), and
   the profile is resampled on a uniform grid of ``s``;
2. computes its spectrum in mm⁻¹ (:func:`profile_spectrum`, thesis eqs. 2.1–2.3 on a
   Hann-windowed, zero-padded profile so that peak amplitudes are those of sinusoids);
3. computes the spatial frequency of every rotating gear element during the run
   (:func:`gear_spatial_frequencies`): revolutions per mm of path, from the joint rates along
   the path (Slamani & Bonev 2013): ``f = r · |dq/ds| / 2π`` for the once-per-revolution
   (runout) order and ``z`` times that for the tooth-mesh order. On a straight path the
   joint angles depend on the position only, so this does not depend on the feed;
4. matches spectral peaks to gears within a tolerance tied to the frequency resolution
   ``1/L`` (:func:`match_peaks_to_gears`), and
5. separates constant-*temporal*-frequency peaks (a servo ripple at 13 Hz: its wavelength
   grows with feed) from constant-*spatial*-frequency ones using the runs at several feeds
   (:func:`classify_peaks`).

One subject per submodule: :mod:`~robomill.straightness.profile` (steps 1–2),
:mod:`~robomill.straightness.gears` (3), :mod:`~robomill.straightness.attribution` (4–5),
:mod:`~robomill.straightness.study` (one run end to end, gathering),
:mod:`~robomill.straightness.truth` (against the planted gears),
:mod:`~robomill.straightness.tables` (chapter tables),
:mod:`~robomill.straightness.figures` (chapter figures) and
:mod:`~robomill.straightness.findings` (what chapter 3.2 states, with its verdicts). The
public names are importable from this package, loaded from their submodule on first use
(importing the package imports nothing); rule scripts and notebooks import from the
submodules.
"""



from robomill._lazy import lazy_exports

_EXPORTS = {  # public name → submodule
    "MECHANISMS": "attribution",
    "NO_TIME_BASE": "attribution",
    "PEAK_COLUMNS": "attribution",
    "classify_peaks": "attribution",
    "element_label": "attribution",
    "match_peaks_to_gears": "attribution",
    "parse_candidates": "attribution",
    "ORDERS": "gears",
    "gear_frequencies_from_motion": "gears",
    "gear_orders": "gears",
    "gear_spatial_frequencies": "gears",
    "joint_path_for_line": "gears",
    "COMPONENTS": "profile",
    "Profile": "profile",
    "ProfileSpectrum": "profile",
    "TRIM_MAX_FRACTION": "profile",
    "fit_line": "profile",
    "perpendicular_axes": "profile",
    "profile_dataset": "profile",
    "profile_spectrum": "profile",
    "resample_uniform": "profile",
    "spatial_profile": "profile",
    "spectrum_peaks": "profile",
    "analyse_run": "study",
    "analyse_tracker_run": "study",
    "gather_gears": "study",
    "gather_peaks": "study",
    "gather_profiles": "study",
    "MECHANISM_MARKERS": "figures",
    "THESIS_FIGURES": "figures",
    "deviation_figure": "figures",
    "figure_numbers": "figures",
    "mechanism_figure": "figures",
    "psd_figure": "figures",
    "runs_of": "figures",
    "THESIS_DIRECTIONS": "findings",
    "figure_directions": "findings",
    "quiet_band": "findings",
    "straightness_findings": "findings",
    "ATTRIBUTION_COLUMNS": "tables",
    "attribution_table": "tables",
    "band_floor_table": "tables",
    "band_peak_ratio": "tables",
    "direction_text": "tables",
    "mesh_table": "tables",
    "read_peaks": "tables",
    "run_summary_table": "tables",
    "run_values_table": "tables",
    "surface_cross_check": "tables",
    "surface_tolerance_per_mm": "tables",
    "truth_table": "tables",
    "with_labels": "tables",
    "TRUTH_CHECK_COLUMNS": "truth",
    "attribution_counts": "truth",
    "evaluate_attribution": "truth",
    "planted_gear_elements": "truth",
    "truth_check": "truth",
}

__getattr__, __dir__, __all__ = lazy_exports(__name__, _EXPORTS)
