"""Chapter 3.1's tables and its choice of figure cuts, built from the forces stage's artefacts
(the notebook loads, plots and renders; it builds nothing itself).

- :func:`figure_cuts`: the cuts the spectra figures show (the thesis' set ``forces.figure_set``
  for a study of its design, every cut otherwise);
- :func:`peak_table`: Table 3.1, the per-cut peaks with the nearest identified mode (the
  chapter groups it by the design factors that vary for a design other than the thesis');
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
            else f"{float(direction.split()[0]):g}°")


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


def peak_table(peaks: pd.DataFrame, means: pd.DataFrame, modes: pd.DataFrame | None, *,
               levels: bool) -> pd.DataFrame:
    """Table 3.1: each cut's dominant and kinematic peak and the identified mode nearest to
    the dominant one (:func:`robomill.forces.peaks.nearest_modes`), ``"none"`` where a peak
    is empty (:data:`NONE`), rounded to 4 decimals.

    ``levels`` (any design but the thesis'): ``cut``, the two peaks, the mean force levels in
    the cut frame (:data:`FORCE_COLUMNS`) and the nearest mode's frequency and offset, for
    the chapter to group by the design factors that vary; otherwise every column of
    ``peaks.csv`` with the cut's feed, depth and direction, as the thesis.
    """
    tab = peaks.merge(means[["cut", "feed_mm_s", "depth_mm", "direction"]], on="cut")
    if modes is not None and len(modes):
        tab = tab.join(nearest_modes(tab["dominant_hz"], modes))
    if levels:
        values = ["dominant_hz", "kinematic_per_mm", *FORCE_COLUMNS] + [
            c for c in ("nearest_mode_hz", "offset_hz") if c in tab]
        tab = tab.drop(columns=["feed_mm_s", "depth_mm", "direction"]).merge(
            means[["cut", *FORCE_COLUMNS]], on="cut")[["cut", *values]]
    tab = tab.round(4)
    return tab.astype({k: object for k in NONE}).fillna(NONE)


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
    """The mean-force table with each cut's process filled in: ``flutes`` (the cut's, else the
    experiment's, else 2), ``radial_immersion`` (else 1: a slot) and ``milling`` (else
    ``slot`` at full immersion, ``down`` below; as :func:`robomill.experiment.cut_process`)."""
    out = means.copy()
    flutes = (experiment or {}).get("flutes") or 2
    out["flutes"] = (out["flutes"].fillna(flutes) if "flutes" in out else flutes)
    out["flutes"] = np.asarray(out["flutes"], int)
    ae = (out["radial_immersion"].fillna(1.0) if "radial_immersion" in out
          else pd.Series(1.0, index=out.index)).astype(float)
    out["radial_immersion"] = ae
    mode = pd.Series(np.where(ae >= 1.0, "slot", "down"), index=out.index)
    out["milling"] = out["milling"].fillna(mode) if "milling" in out else mode
    return out
