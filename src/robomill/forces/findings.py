"""Chapter 3.1's findings: every number, range and verdict the chapter states, computed from
the forces stage's artefacts and rendered by the chapter (:mod:`robomill.pipeline.prose`).

- the dominant low-frequency force peak: where it lies, in how many cuts none stands out, and
  whether it sits at the identified modes of the impact test (chapter 3.3) within
  ``forces.mode_match_hz`` (:func:`forces_findings`);
- the records (:func:`_records`): samples, tooth-passing frequencies, the cuts of the spectra
  figures, the model cut's shape and the largest full-band peak of the figures' first cut
  above ``forces.full_band_min_hz``;
- the kinematic peak and its sanity flag against ``forces.min_peak_cycles``
  (:func:`_kinematic`);
- the design and the mean force levels (:func:`_levels`);
- the identified cutting coefficients, their sanity flags and, in a synthetic run, their
  error against the planted values (:func:`_coefficients`), and whether the feed directions
  share them (:func:`_directions`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill import catalogue, references
from robomill.findings import Findings
from robomill.forces.coefficients import (
    FLAG_COLUMNS,
    direction_heterogeneity,
    identification_status,
    not_identified_sentence,
    not_physical_reasons,
)
from robomill.forces.peaks import nearest_modes
from robomill.forces.tables import figure_cuts, process_table
from robomill.settings import schema_default, section_settings

_PEAKS = catalogue.artefact("forces.peaks")
_MODES = catalogue.artefact("modal.modes")
_SPECTRA = catalogue.artefact("forces.spectra")
_MEANS = catalogue.artefact("forces.mean_forces")
_COEFFICIENTS = catalogue.artefact("forces.cutting_coefficients")
_CUTS = catalogue.artefact("ingest.cuts")
_REFERENCES = "src/robomill/data/references.yaml"


def forces_findings(peaks: pd.DataFrame, modes: pd.DataFrame | None, *,
                    mode_match_hz: float, band_hz: Sequence[float],
                    prominence_db: float, spectra: xr.Dataset | None = None,
                    means: pd.DataFrame | None = None,
                    coefficients: pd.DataFrame | None = None,
                    design: Mapping[str, Any] | None = None,
                    planted: Mapping[str, float] | None = None,
                    experiment: Mapping[str, Any] | None = None,
                    settings: Mapping[str, Any] | None = None,
                    thesis_design: bool | None = None) -> Findings:
    """The findings of the forces stage (chapter 3.1).

    Parameters
    ----------
    peaks
        ``results/forces/peaks.csv`` (columns ``cut``, ``dominant_hz``; NaN where no peak
        stands out of its local floor).
    modes
        ``results/modal/modes.csv`` (``mode``, ``f_n_hz``), or ``None`` where the study has
        no impact test.
    mode_match_hz
        ``forces.mode_match_hz``: a dominant peak within this distance of an identified mode
        is "at the mode"; the verdict ``dominant_at_modes`` is ``pass`` when every dominant
        peak is (the thesis' reading: the tool-tip vibration modulates the chip load).
    band_hz, prominence_db
        ``forces.dominant_band_hz`` and ``forces.dominant_prominence_db`` (stated with the
        peaks).
    spectra, means, coefficients
        ``results/forces/spectra.nc``, ``mean_forces.csv`` and ``cutting_coefficients.csv``;
        each ``None`` leaves out the findings that need it (:func:`_records`,
        :func:`_levels`, :func:`_coefficients`).
    design
        The design of the cuts as the rule describes it from ``results/ingest/cuts.csv``
        (``design``: one line; ``grouping``: the factors that vary;
        :mod:`robomill.pipeline.design_tables`, tooling this package does not import).
    planted
        The planted cutting coefficients of a synthetic run by name
        (:func:`robomill.forces.tables.planted_coefficients`); ``None`` or empty otherwise.
    experiment
        The manifest's experiment defaults (flutes, spindle speed …) for the cuts' process.
    settings
        The ``forces`` config section: ``figure_set``, ``full_band_min_hz``,
        ``kinematic_band_per_mm``, ``kinematic_prominence_db``, ``min_peak_cycles``,
        ``lowband_hz``.
    thesis_design
        Whether the study is the thesis' design (its figures show one set).

    Returns
    -------
    Findings
        ``n_cuts``, ``n_dominant``, ``n_dominant_none``, ``dominant_hz_range`` (``[min, max]``
        or ``None``), ``dominant_band_hz``, ``dominant_prominence_db``, ``has_modes``,
        ``modes_hz``; with modes and peaks ``mode_offset_max_hz``, ``mode_offset_median_hz``
        (absolute peak − nearest mode), ``modes_hit_hz``/``modes_hit_cuts`` (the modes
        nearest to a peak, most often first) and the verdict ``dominant_at_modes``; then the
        findings of :func:`_records`, :func:`_kinematic`, :func:`_levels`,
        :func:`_coefficients` and :func:`_sources` whose inputs are given.
    """
    found = Findings("forces")
    settings = dict(settings or {})
    _dominant(found, peaks, modes, mode_match_hz=mode_match_hz, band_hz=band_hz,
              prominence_db=prominence_db)
    _kinematic(found, peaks, spectra, settings)
    if spectra is not None:
        _records(found, spectra, means, experiment, settings, thesis_design)
    if means is not None:
        _levels(found, means, design, experiment)
    if coefficients is not None:
        _coefficients(found, coefficients, planted, settings.get("confidence"))
        if means is not None and identification_status(coefficients) is None:
            _directions(found, means, experiment, settings.get("confidence"))
    _sources(found)
    return found


def _dominant(found: Findings, peaks: pd.DataFrame, modes: pd.DataFrame | None, *,
              mode_match_hz: float, band_hz: Sequence[float], prominence_db: float) -> None:
    """The dominant peak and its verdict against the modes (:func:`forces_findings`)."""
    dom = pd.to_numeric(peaks["dominant_hz"], errors="coerce").to_numpy(float)
    have = np.isfinite(dom)
    found.add("n_cuts", int(dom.size), artefact=_PEAKS, what="rows")
    found.add("n_dominant", int(have.sum()), artefact=_PEAKS, what="dominant_hz not empty")
    found.add("n_dominant_none", int((~have).sum()), artefact=_PEAKS,
              what="dominant_hz empty: no local maximum rises above its floor")
    found.add("dominant_hz_range", [float(dom[have].min()), float(dom[have].max())]
              if have.any() else None, "Hz", artefact=_PEAKS, what="dominant_hz")
    found.add("dominant_band_hz", [float(b) for b in band_hz], "Hz")
    found.add("dominant_prominence_db", float(prominence_db), "dB")
    has_modes = modes is not None and len(modes) > 0
    found.add("has_modes", bool(has_modes), artefact=_MODES)
    found.add("modes_hz", [float(f) for f in modes["f_n_hz"]] if has_modes else None, "Hz",
              artefact=_MODES, what="f_n_hz")
    if not (has_modes and have.any()):
        return
    near = nearest_modes(dom[have], modes)
    off = near["offset_hz"].abs().to_numpy(float)
    found.add("mode_offset_max_hz", float(off.max()), "Hz", artefact=_PEAKS,
              what="|dominant_hz - nearest f_n_hz|, largest")
    found.add("mode_offset_median_hz", float(np.median(off)), "Hz", artefact=_PEAKS,
              what="|dominant_hz - nearest f_n_hz|, median")
    hits = near.groupby("nearest_mode_hz").size().sort_values(ascending=False, kind="stable")
    found.add("modes_hit_hz", [float(f) for f in hits.index], "Hz", artefact=_MODES)
    found.add("modes_hit_cuts", [int(n) for n in hits.to_numpy()], artefact=_PEAKS)
    found.add("dominant_at_modes", bool(off.max() <= mode_match_hz),
              verdict="pass" if off.max() <= mode_match_hz else "fail",
              threshold=float(mode_match_hz), config_key="forces.mode_match_hz",
              artefact=_PEAKS, what="every dominant peak within the threshold of a mode")


def _records(found: Findings, spectra: xr.Dataset, means: pd.DataFrame | None,
             experiment: Mapping[str, Any] | None, settings: Mapping[str, Any],
             thesis_design: bool | None) -> None:
    """What was recorded and which cuts the figures show.

    ``n_samples_total`` and ``tooth_passing_hz_values`` over the cuts; ``thesis_layout``,
    ``figure_set`` (``None``: every cut), ``figure_cuts``, ``figure_directions``
    (:func:`robomill.forces.tables.figure_cuts`); ``lowband_hz`` (``forces.lowband_hz``, the
    time-frequency figures' band); the model cut's ``model_flutes``, ``model_milling``,
    ``model_radial_immersion`` (the first cut, with ``means``); and in the figures' first cut
    the largest peak of the full-band Welch PSD summed over the axes above
    ``forces.full_band_min_hz`` (``full_band_peak_cut``, ``full_band_peak_hz``) and its ratio
    to that cut's tooth-passing frequency (``full_band_peak_harmonic``).
    """
    filled = section_settings(settings, "forces")  # the schema's defaults where it lacks one
    found.add("n_samples_total", int(spectra["n_samples"].sum()), artefact=_SPECTRA,
              what="n_samples, summed over the cuts")
    tp = np.unique(spectra["tooth_passing_hz"].values.astype(float))
    found.add("tooth_passing_hz_values", tp, "Hz", artefact=_SPECTRA,
              what="tooth_passing_hz, each value once (sorted)")
    sel = figure_cuts(spectra, figure_set=int(filled["figure_set"]),
                      thesis_design=thesis_design)
    found.add("thesis_layout", sel.thesis_layout, artefact=_SPECTRA,
              what="the thesis' design and a set per cut: one set shown as the thesis")
    found.add("figure_set", sel.figure_set, artefact=_SPECTRA, what="set (forces.figure_set)")
    found.add("figure_cuts", sel.cuts, artefact=_SPECTRA, what="cut")
    found.add("figure_directions", sel.directions, artefact=_SPECTRA, what="direction")
    if "lowband_hz" in settings:
        found.add("lowband_hz", float(settings["lowband_hz"]), "Hz", artefact="config.yaml",
                  what="forces.lowband_hz", config_key="forces.lowband_hz")
    if means is not None and len(means):
        first = process_table(means, experiment).set_index("cut").loc[str(spectra.cut.values[0])]
        found.add("model_flutes", int(first["flutes"]), artefact=_MEANS, what="flutes")
        found.add("model_milling", str(first["milling"]), artefact=_MEANS, what="milling")
        found.add("model_radial_immersion", float(first["radial_immersion"]), artefact=_MEANS,
                  what="radial_immersion")
    min_hz = float(filled["full_band_min_hz"])
    cut = sel.cuts[0]
    f = spectra["frequency"].values
    psd = spectra["psd"].sel(cut=cut).sum("axis").values
    above = f > min_hz
    found.add("full_band_min_hz", min_hz, "Hz", artefact="config.yaml",
              what="forces.full_band_min_hz", config_key="forces.full_band_min_hz")
    if not above.any():
        return
    top = float(f[above][np.argmax(psd[above])])
    found.add("full_band_peak_cut", cut, artefact=_SPECTRA, what="cut")
    found.add("full_band_peak_hz", top, "Hz", artefact=_SPECTRA,
              what=f"argmax of psd summed over axis, frequency > {min_hz:g} Hz")
    found.add("full_band_peak_harmonic",
              top / float(spectra["tooth_passing_hz"].sel(cut=cut)), artefact=_SPECTRA,
              what="full_band_peak_hz / tooth_passing_hz")


def _kinematic(found: Findings, peaks: pd.DataFrame, spectra: xr.Dataset | None,
               settings: Mapping[str, Any]) -> None:
    """The kinematic peak (strongest local maximum of the spatial power in
    ``forces.kinematic_band_per_mm`` rising ``forces.kinematic_prominence_db`` above its
    floor) and its sanity flag.

    ``n_kinematic``, ``n_kinematic_none``, ``kinematic_per_mm_median`` and
    ``kinematic_per_mm_range`` over the cuts that have one; ``resolution_per_mm`` = 1/L of the
    first record and its ``resolution_feed_mm_s``; the flag ``n_kinematic_below_resolution``
    (verdict ``pass`` when no peak has fewer than ``forces.min_peak_cycles`` periods in its
    record), ``kinematic_below_resolution`` (each flagged cut), the frequency uncertainty of
    half a bin ``kinematic_uncertainty_pct`` = 50 / cycles and the record length that would
    hold the cycles of the lowest flagged peak, ``kinematic_record_needed_mm``.
    """
    kin = pd.to_numeric(peaks.get("kinematic_per_mm", pd.Series(dtype=float)),
                        errors="coerce")
    have = kin.notna()
    found.add("n_kinematic", int(have.sum()), artefact=_PEAKS, what="kinematic_per_mm not empty")
    found.add("n_kinematic_none", int((~have).sum()), artefact=_PEAKS,
              what="kinematic_per_mm empty: no local maximum rises above its floor")
    found.add("kinematic_per_mm_median", float(kin[have].median()) if have.any() else None,
              "1/mm", artefact=_PEAKS, what="kinematic_per_mm, median")
    found.add("kinematic_per_mm_range", [float(kin[have].min()), float(kin[have].max())]
              if have.any() else None, "1/mm", artefact=_PEAKS, what="kinematic_per_mm")
    for key, unit in (("kinematic_band_per_mm", "1/mm"), ("kinematic_prominence_db", "dB")):
        if key in settings:
            found.add(key, settings[key], unit, artefact="config.yaml", what=f"forces.{key}",
                      config_key=f"forces.{key}")
    if spectra is not None:
        found.add("resolution_per_mm", float(spectra["f_spatial_low"].isel(cut=0, lf_bin=1)),
                  "1/mm", artefact=_SPECTRA, what="f_spatial_low[lf_bin=1] of the first cut")
        found.add("resolution_feed_mm_s", float(spectra["feed_mm_s"].isel(cut=0)), "mm/s",
                  artefact=_SPECTRA, what="feed_mm_s of the first cut")
    if "kinematic_below_resolution" not in peaks or "min_peak_cycles" not in settings:
        return
    cycles = float(settings["min_peak_cycles"])
    flagged = peaks[peaks["kinematic_below_resolution"].astype(bool) & have]
    found.add("n_kinematic_below_resolution", len(flagged), artefact=_PEAKS,
              what="kinematic_below_resolution and kinematic_per_mm not empty",
              verdict="pass" if flagged.empty else "fail", threshold=cycles,
              config_key="forces.min_peak_cycles")
    found.add("kinematic_below_resolution",
              [f"{r.cut} ({r.kinematic_per_mm:.2f} mm⁻¹ at 1/L = "
               f"{r.kinematic_resolution_per_mm:.3f} mm⁻¹)" for r in flagged.itertuples()],
              artefact=_PEAKS, what="cut, kinematic_per_mm, kinematic_resolution_per_mm")
    found.add("kinematic_uncertainty_pct", 50.0 / cycles, "%", artefact="config.yaml",
              what="half a bin: 50 / forces.min_peak_cycles")
    found.add("kinematic_record_needed_mm",
              cycles / float(flagged["kinematic_per_mm"].min()) if len(flagged) else None,
              "mm", artefact=_PEAKS, what="min_peak_cycles / lowest flagged kinematic_per_mm")


def _levels(found: Findings, means: pd.DataFrame, design: Mapping[str, Any] | None,
            experiment: Mapping[str, Any] | None) -> None:
    """The design of the cuts (``design``: one line; ``grouping``: the factors that vary; as
    given), the mean force levels in the cut frame (``F_feed_N_range``,
    ``F_cross_feed_N_range``, ``F_axial_N_range``) and the engagement of the cuts
    (``all_slot``; ``millings``: each milling mode and radial immersion, for the mean-force
    equations)."""
    if design:
        found.add("design", str(design["design"]), artefact=_CUTS,
                  what="the cuts' design factors (robomill.pipeline.design_tables)")
        found.add("grouping", [str(g) for g in design["grouping"]], artefact=_CUTS,
                  what="design factors that vary")
    for col in ("F_feed_N", "F_cross_feed_N", "F_axial_N"):
        v = means[col].to_numpy(float)
        found.add(f"{col}_range", [float(v.min()), float(v.max())], "N", artefact=_MEANS,
                  what=col)
    proc = process_table(means, experiment)
    found.add("all_slot", bool((proc["milling"] == "slot").all()), artefact=_MEANS,
              what="milling == slot")
    found.add("millings", sorted({f"{r.milling} milling, a_e/D {float(r.radial_immersion):g}"
                                  for r in proc.itertuples()}), artefact=_MEANS,
              what="milling, radial_immersion")


def _coefficients(found: Findings, coefficients: pd.DataFrame,
                  planted: Mapping[str, float] | None, confidence: float | None) -> None:
    """The identified cutting coefficients: ``coefficient_<name>`` (value) and
    ``coefficient_<name>_ci`` (the ``forces.confidence`` interval, ``confidence_pct``) for
    each row; the sanity flags (``coefficient_flags_checked``: the table has them;
    ``n_coefficients``, ``n_not_physical``, ``not_physical``: each coefficient that is
    not and why: a negative value, or a fit residual rms above the signal rms, R² < 1/2,
    :func:`robomill.forces.coefficient_flags`); with ``planted`` values the largest relative
    error ``planted_error_pct_max`` (signed) and its coefficient ``planted_error_worst``.

    A table the design could not identify (one feed per tooth, fewer than three cuts:
    :func:`robomill.forces.coefficients.not_identified_table`) gives instead
    ``coefficients_not_identified_reason`` (the code of ``not_identified_reason``),
    ``coefficients_not_identified`` (its sentence: ``"not identified: the cuts have one feed
    per tooth (need ≥ 3 cuts at ≥ 2 feeds per tooth)"``), ``n_coefficients`` and
    ``coefficient_flags_checked`` False (an identified table gives neither of the first
    two)."""
    if confidence is not None:
        found.add("confidence_pct", 100 * float(confidence), "%", artefact="config.yaml",
                  what="forces.confidence", config_key="forces.confidence")
    why = identification_status(coefficients)
    if why is not None:
        found.add("coefficients_not_identified_reason", why, artefact=_COEFFICIENTS,
                  what="not_identified_reason (identified == False)")
        found.add("coefficients_not_identified",
                  not_identified_sentence(why),
                  artefact=_COEFFICIENTS, what="not_identified_reason, in words")
        found.add("n_coefficients", len(coefficients), artefact=_COEFFICIENTS, what="rows")
        found.add("coefficient_flags_checked", False, artefact=_COEFFICIENTS,
                  what="no flags: nothing identified")
        return
    for r in coefficients.itertuples():
        found.add(f"coefficient_{r.name}", float(r.value), str(r.unit),
                  artefact=_COEFFICIENTS, what=f"value[name={r.name}]")
        found.add(f"coefficient_{r.name}_ci", [float(r.ci_low), float(r.ci_high)],
                  str(r.unit), artefact=_COEFFICIENTS, what=f"ci_low, ci_high[name={r.name}]")
    found.add("n_coefficients", len(coefficients), artefact=_COEFFICIENTS, what="rows")
    checked = set(FLAG_COLUMNS) <= set(coefficients.columns)
    found.add("coefficient_flags_checked", checked, artefact=_COEFFICIENTS,
              what="the flag columns present")
    if checked:
        bad = coefficients[~coefficients["physical"].astype(bool)]
        found.add("n_not_physical", len(bad), artefact=_COEFFICIENTS, what="physical == False")
        found.add("not_physical", not_physical_reasons(coefficients),
                  artefact=_COEFFICIENTS, what="negative, residual_exceeds_signal")
    if planted:
        err = {r.name: 100 * (float(r.value) / float(planted[r.name]) - 1)
               for r in coefficients.itertuples() if r.name in planted}
        if err:
            worst = max(err, key=lambda k: abs(err[k]))
            found.add("planted_error_pct_max", err[worst], "%", artefact=_COEFFICIENTS,
                      what="100 (value / planted - 1), largest in magnitude (truth.nc)")
            found.add("planted_error_worst", worst, artefact=_COEFFICIENTS, what="name")


def _directions(found: Findings, means: pd.DataFrame, experiment: Mapping[str, Any] | None,
                confidence: float | None) -> None:
    """Whether the feed directions share the coefficients
    (:func:`robomill.forces.coefficients.direction_heterogeneity`, Cochran's test with Holm's
    correction over the six at the family-wise level ``1 − forces.confidence``):
    ``coefficient_direction_groups`` (the directions whose cuts identify the coefficients
    alone; nothing where fewer than two do), the verdict
    ``coefficient_directions_agree`` (``pass`` when no coefficient differs between them),
    ``coefficient_direction_level_pct`` and ``coefficient_directions_disagree``: per
    coefficient that differs, its value and interval in each direction and the test's Q and p
    (a sentence each)."""
    kw = {} if confidence is None else {"confidence": float(confidence)}
    if experiment and experiment.get("flutes") is not None:
        kw["flutes"] = int(experiment["flutes"])
    het = direction_heterogeneity(means, **kw)
    if het is None:
        return
    level = round(1 - (float(confidence) if confidence is not None
                       else schema_default("forces", "confidence")), 12)
    groups = het["directions"].iloc[0].split(", ")
    found.add("coefficient_direction_groups", groups, artefact=_MEANS,
              what="directions whose cuts identify the coefficients alone")
    found.add("coefficient_direction_level_pct", 100 * level, "%", artefact=_MEANS,
              what="1 - forces.confidence")
    bad = het[het["disagree"]]
    found.add("coefficient_directions_disagree",
              [f"{r['name']} " + ", ".join(
                  f"{r[f'value_{d}']:.1f} [{r[f'ci_low_{d}']:.1f}, {r[f'ci_high_{d}']:.1f}] "
                  f"({d})" for d in groups) + f" {r['unit']} (Q = {r['q']:.3g}, "
               f"p = {r['p_value']:.2g}, I² = {r['i2_pct']:.0f} %)"
               for _, r in bad.iterrows()],
              artefact=_MEANS, what="coefficients whose directions differ (Cochran's Q)")
    found.add("coefficient_directions_agree", bad.empty, artefact=_MEANS,
              what="no coefficient differs between the directions",
              verdict="pass" if bad.empty else "fail", threshold=level,
              config_key="forces.confidence")


def _sources(found: Findings) -> None:
    """The thesis' numbers the chapter's "Against the thesis" names
    (``robomill/data/references.yaml``)."""
    for key, ref in (("ref_full_band_peak_hz", "thesis.forces.full_band_peak_min_hz"),
                     ("ref_kinematic_per_mm", "thesis.forces.peaks.kinematic_per_mm.median")):
        found.add(key, references.value(ref), references.reference(ref)["unit"],
                  artefact=_REFERENCES, what=ref)
