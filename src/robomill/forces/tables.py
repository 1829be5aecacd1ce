"""Chapter 3.1's tables and its choice of figure cuts, built from the forces stage's artefacts
(the notebook loads, plots and renders; it builds nothing itself).

- :func:`figure_cuts`: the cuts the spectra figures show (the thesis' set ``forces.figure_set``
  for a study of its design, every cut otherwise);
- :func:`peak_table`: Table 3.1, the per-cut peaks with the nearest identified mode;
- :func:`harmonic_table`: Table 3.3, the tooth-passing harmonics' median power;
- :func:`planted_coefficients`, :func:`coefficient_table`: Table 3.4, the identified cutting
  coefficients with the planted values of a synthetic run.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill.experiment import DIRECTION_LABELS
from robomill.forces.peaks import nearest_modes
from robomill.pipeline.design_tables import direction_label, per_cut_table, with_design

THESIS_DIRECTIONS = ("py", "px", "my")
"""The thesis' order of the feed directions in its figures (+Y, +X, −Y)."""

NONE = {"dominant_hz": "none", "kinematic_per_mm": "none"}
"""What an empty peak shows as in Table 3.1: no peak stands out of its local floor."""

FORCE_COLUMNS = ["F_feed_N", "F_cross_feed_N", "F_axial_N"]


@dataclass(frozen=True)
class FigureCuts:
    """The cuts of the spectra figures: ``figure_set`` (``None``: every cut), the ``cuts``
    and their feed ``directions`` in figure order; ``thesis_layout`` when they follow the
    thesis' figures (one set, +Y, +X, −Y)."""

    thesis_layout: bool
    figure_set: int | None
    cuts: list[str]
    directions: list[str]


def direction_text(direction: str) -> str:
    """+X, −Y … for a named direction, ``45°`` for a path direction ``"45 deg"``."""
    return (DIRECTION_LABELS[direction] if direction in DIRECTION_LABELS
            else direction_label(None, float(direction.split()[0])))


def figure_cuts(spectra: xr.Dataset, *, figure_set: int,
                thesis_design: bool | None) -> FigureCuts:
    """The cuts chapter 3.1's spectra figures show.

    A study of the thesis' design (``thesis_design`` not ``False``) whose spectra carry the
    ``set`` of each cut shows the set ``figure_set`` (the largest set when it has none of that
    number) along +Y, +X, −Y as the thesis' Figs 3.5–3.10; any other study shows every cut,
    its directions in the order they first appear.
    """
    direction = {str(c): str(v) for c, v in zip(spectra.cut.values,
                                                 spectra["direction"].values, strict=True)}
    if thesis_design is not False and "set" in spectra:
        sets = [int(s) for s in spectra["set"].values]
        chosen = int(figure_set) if int(figure_set) in sets else max(sets)
        cuts = [str(c) for c, s in zip(spectra.cut.values, sets, strict=True) if s == chosen]
        dirs = [d for d in THESIS_DIRECTIONS if any(direction[c] == d for c in cuts)]
        return FigureCuts(True, chosen, cuts, dirs)
    cuts = [str(c) for c in spectra.cut.values]
    return FigureCuts(False, None, cuts, list(dict.fromkeys(direction[c] for c in cuts)))


def peak_table(peaks: pd.DataFrame, means: pd.DataFrame, modes: pd.DataFrame | None,
               cuts: pd.DataFrame, experiment: Mapping[str, Any] | None, *,
               grouped: bool) -> pd.DataFrame:
    """Table 3.1: each cut's dominant and kinematic peak and the identified mode nearest to
    the dominant one (:func:`robomill.forces.peaks.nearest_modes`), ``"none"`` where a peak
    is empty (:data:`NONE`).

    ``grouped`` (any design but the thesis'): grouped by the design factors that vary
    (:func:`robomill.pipeline.design_tables.per_cut_table`) with the mean force levels in the
    cut frame; otherwise one row per cut with its feed, depth and direction, as the thesis.
    """
    tab = peaks.merge(means[["cut", "feed_mm_s", "depth_mm", "direction"]], on="cut")
    if modes is not None and len(modes):
        tab = tab.join(nearest_modes(tab["dominant_hz"], modes))
    if grouped:
        values = ["dominant_hz", "kinematic_per_mm", *FORCE_COLUMNS] + [
            c for c in ("nearest_mode_hz", "offset_hz") if c in tab]
        per_cut = tab.drop(columns=["feed_mm_s", "depth_mm", "direction"]).merge(
            means[["cut", *FORCE_COLUMNS]], on="cut")
        tab = per_cut_table(per_cut[["cut", *values]], values, cuts, experiment)
    tab = tab.round(4)
    shown = {k: v for k, v in NONE.items() if k in tab}
    return tab.astype({k: object for k in shown}).fillna(shown)


def harmonic_table(harmonics: pd.DataFrame, cuts: pd.DataFrame) -> pd.DataFrame:
    """Table 3.3: the median frequency and power (summed over the axes) of each tooth-passing
    harmonic over the cuts of one tooth-passing frequency (one spindle speed and tool);
    indexed by ``harmonic``, or by ``tooth_hz`` and ``harmonic`` when the cuts have several."""
    total = harmonics.assign(power_N2=harmonics[["Fx_power_N2", "Fy_power_N2",
                                                 "Fz_power_N2"]].sum(axis=1))
    by_tp = total.merge(cuts[["cut", "tooth_passing_hz"]].rename(
        columns={"tooth_passing_hz": "tooth_hz"}), on="cut")
    index = ["harmonic"] if by_tp["tooth_hz"].nunique() == 1 else ["tooth_hz", "harmonic"]
    return by_tp.pivot_table(index=index, values=["f_hz", "power_N2"],
                             aggfunc="median").round(4)


def planted_coefficients(truth: xr.Dataset | None) -> dict[str, float]:
    """The cutting coefficients planted in the virtual cell (``results/synthetic/truth.nc``
    variables ``cutting_<name>_<unit>``) by name (``Ktc`` …); empty without a truth."""
    if truth is None:
        return {}
    return {k.split("_")[1]: float(truth[k]) for k in truth.data_vars
            if k.startswith("cutting_")}


def coefficient_table(coefficients: pd.DataFrame,
                      planted: Mapping[str, float] | None = None) -> pd.DataFrame:
    """Table 3.4: ``cutting_coefficients.csv`` indexed by ``name``; with ``planted`` values
    the columns ``planted`` and ``error_pct`` = 100 (identified / planted − 1)."""
    table = coefficients.copy()
    if planted:
        table["planted"] = table["name"].map(planted).astype(float)
        table["error_pct"] = 100 * (table["value"] / table["planted"] - 1)
    return table.set_index("name").round(3)


def process_table(means: pd.DataFrame, experiment: Mapping[str, Any] | None) -> pd.DataFrame:
    """The mean-force table with each cut's process filled in (flutes, radial immersion,
    milling mode: :func:`robomill.pipeline.design_tables.with_design`); a table without
    them (no experiment) counts as two-flute slots."""
    out = with_design(means, experiment)
    if "flutes" not in out:
        out["flutes"] = 2
    if "milling" not in out:
        out["milling"], out["radial_immersion"] = "slot", 1.0
    out["flutes"] = np.asarray(out["flutes"], int)
    return out
