"""Impact-test modal identification of the tool tip (thesis §3.3, and beyond it): the
package, one subject per submodule.

The chain, each step a pure function on arrays:

1. :mod:`~robomill.modal.hits` — automatic rejection of a hit (double hit, overload), the
   force and exponential windows, the accepted hits grouped by reference point.
2. :mod:`~robomill.modal.layout` — measurement points ``(node, ±direction)`` of any test
   layout, their labels and the FRF dataset's coordinates.
3. :mod:`~robomill.modal.frf` — FRFs H(response point, reference point) by pyFRF: H1, H2 and
   the coherence averaged over the accepted hits (the thesis: the 3×3 receptance matrix).
4. :mod:`~robomill.modal.peaks` — the thesis' peak picking on every FRF (an extremum of the
   imaginary part, real-part extrema of opposite signs on either side, coherence > 0.75)
   and the peaks of all FRFs grouped into natural frequencies.
5. :mod:`~robomill.modal.band` — the analysis band (configuration, manifest or data).
6. :mod:`~robomill.modal.lscf` — poles by the LSCF stabilization chart (sdypy-EMA), the
   physical poles selected, the exponential window's damping removed.
7. :mod:`~robomill.modal.synthesis` — residues by LSFD, the FRF synthesized from poles and
   residues; :mod:`~robomill.modal.shapes` — mode shapes, modal masses, MAC;
   :mod:`~robomill.modal.tables` — the mode table with its sanity flags;
   :mod:`~robomill.modal.identification` — the whole chain on an FRF dataset.
8. :mod:`~robomill.modal.checks` — planted-truth check, synthesis misfit, mode coupling;
   :mod:`~robomill.modal.ncio` — complex variables in netCDF; :mod:`~robomill.modal.uff` —
   FRFs and modes written as UFF 58/55.
9. :mod:`~robomill.modal.findings` — chapter 3.3's findings from the stage's artefacts;
   :mod:`~robomill.modal.shown` — the tables it shows; :mod:`~robomill.modal.figures` — its
   figures (matplotlib).

Importing this package imports none of them: every public name is loaded from its
submodule on first use (PEP 562 ``__getattr__``), so ``from robomill.modal import identify``
keeps working while the workflow's scripts import the submodules they use
(``from robomill.modal.lscf import stabilization``) and a rule depends only on those
(:mod:`robomill.pipeline.codedeps`).

FRF convention (as in sdypy-EMA): ``H(ω) = Σ_r A_r/(jω − p_r) + A_r*/(jω − p_r*)``.
"""

from __future__ import annotations

from robomill.lazy import lazy_exports

_NAMES = {
    "band": ("BAND_COVERAGE_MIN", "BandChoice", "band_coverage", "band_from_data",
             "choose_band"),
    "checks": ("COUPLING_TOLERANCE", "mode_coupling", "synthesis_misfit", "truth_check"),
    "findings": ("modal_findings",),
    "figures": ("STABILITY_STYLE", "frf_grid_figure", "frf_pair_figure", "impact_test_figure",
                "mac_shapes_figure", "measured_pairs", "stabilization_figure"),
    "frf": ("combine_frfs", "force_spectrum", "frf_from_groups", "frf_matrix",
            "to_receptance"),
    "hits": ("CHANNELS", "HIT_COLUMNS", "HitCheck", "HitGroup", "check_and_group", "check_hit",
             "empty_traces", "exponential_window_rate", "hit_table_empty", "hit_traces",
             "impact_windows"),
    "identification": ("Identification", "coherence_at", "identify"),
    "layout": ("AXES", "AXIS_CODE", "TOOLTIP", "driving_points", "frf_coords",
               "parse_direction", "point_label", "points"),
    "lscf": ("correct_window_damping", "pole_f_zeta", "select_poles", "stabilization"),
    "ncio": ("COMPLEX_VARS", "join_complex", "split_complex"),
    "peaks": ("PEAK_COLUMNS", "THESIS_NATURAL_HZ", "group_peaks", "interpolated_peak_hz",
              "peak_picking"),
    "shapes": ("ModeShapes", "mac_matrix", "mode_shapes"),
    "shown": ("MODE_ROUNDING", "misfit_table", "shown_hits", "shown_modes",
              "shown_peak_groups"),
    "synthesis": ("modal_constants", "modal_residues", "synthesize_frf"),
    "tables": ("MODE_COLUMNS", "modes_table", "shapes_table"),
    "uff": ("write_frf_uff", "write_modes_uff"),
}
"""Submodule → the public names it defines (the lazy import table)."""

__getattr__, __dir__, __all__ = lazy_exports(__name__, _NAMES)
