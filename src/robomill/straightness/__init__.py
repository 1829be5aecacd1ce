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



from robomill.lazy import lazy_exports

_EXPORTS = {  # submodule → its public names
    "attribution": ("MECHANISMS", "NO_TIME_BASE", "PEAK_COLUMNS", "classify_peaks", "element_label",
                    "match_peaks_to_gears", "parse_candidates"),
    "gears": ("ORDERS", "gear_frequencies_from_motion", "gear_orders", "gear_spatial_frequencies",
              "joint_path_for_line"),
    "profile": ("COMPONENTS", "Profile", "ProfileSpectrum", "TRIM_MAX_FRACTION", "fit_line",
                "perpendicular_axes", "profile_dataset", "profile_spectrum", "resample_uniform",
                "spatial_profile", "spectrum_peaks"),
    "study": ("analyse_run", "analyse_tracker_run", "gather_gears", "gather_peaks",
              "gather_profiles"),
    "figures": ("MECHANISM_MARKERS", "THESIS_FIGURES", "deviation_figure", "figure_numbers",
                "mechanism_figure", "psd_figure", "runs_of"),
    "findings": ("THESIS_DIRECTIONS", "figure_directions", "quiet_band", "straightness_findings"),
    "tables": ("ATTRIBUTION_COLUMNS", "attribution_table", "band_floor_table", "band_peak_ratio",
               "direction_text", "mesh_table", "read_peaks", "run_summary_table",
               "run_values_table", "surface_cross_check", "surface_tolerance_per_mm", "truth_table",
               "with_labels"),
    "deflection": ("DEFLECTION_COLUMNS", "deflection_table", "pass_deflection_um"),
    "truth": ("TRUTH_CHECK_COLUMNS", "attribution_counts", "evaluate_attribution",
              "planted_gear_elements", "truth_check"),
}

__getattr__, __dir__, __all__ = lazy_exports(__name__, _EXPORTS)
