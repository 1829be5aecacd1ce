"""Per-cut tables for any experiment design, and the gate on the thesis' remarks.

The chapters were written around the thesis' design (thesis §2.1: three sets of five U
segments, each cut +Y, +X, −Y, one spindle speed and tool). For any other design
(``examples/other_cell``: a spindle-speed series, −X and 45° cuts, half-immersion down
milling) they show the same quantities per cut, grouped by the design factors that vary.

The *design factors* of a cut are, in grouping order, :data:`FACTORS`. A factor *varies* when
the cuts take more than one value of it; a varying factor is *dependent* when its value is
fixed by the varying factors before it (in the thesis the depth is fixed by the set, the feed
by the set and segment), so it is shown as a column, not used for grouping. The rest are the
*grouping* factors: the index of the per-cut tables (sets × segments × directions in the
thesis; spindle speed × direction × feed in ``examples/other_cell``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from robomill.experiment import DIRECTION_DEG, DIRECTION_LABELS

FACTORS = ("set", "segment", "spindle_rpm", "flutes", "tool_diameter_mm", "radial_immersion",
           "milling", "direction", "depth_mm", "feed_mm_s")
"""Design factors of a cut, in the order the per-cut tables group by them."""

FACTOR_NAMES = {"set": ("set", "sets"), "segment": ("segment", "segments"),
                "spindle_rpm": ("spindle speed", "spindle speeds"),
                "flutes": ("tool", "flute counts"),
                "tool_diameter_mm": ("tool diameter", "tool diameters"),
                "radial_immersion": ("radial immersion", "radial immersions"),
                "milling": ("milling mode", "milling modes"),
                "direction": ("direction", "directions"), "depth_mm": ("depth", "depths"),
                "feed_mm_s": ("feed", "feeds")}
"""Singular and plural names of each factor (for :func:`describe_design`)."""


def direction_label(direction: Any, direction_deg: Any = None) -> str:
    """The feed direction of a cut as printed: ``+X``, ``−Y`` … for a named direction (thesis
    §2.1), ``45°`` for one given as ``direction_deg`` (0 = +X, counter-clockwise) or as the
    artefacts' path direction ``"45 deg"``."""
    if isinstance(direction, str) and direction in DIRECTION_LABELS:
        return DIRECTION_LABELS[direction]
    if isinstance(direction, str) and (direction in DIRECTION_LABELS.values()
                                       or direction.endswith("°")):
        return direction  # already a label
    if isinstance(direction, str) and direction.endswith(" deg"):  # an artefact's path
        return f"{float(direction[:-4]):g}°"  # direction (robomill.surface.path_direction)
    if direction_deg is not None and not pd.isna(direction_deg):
        return f"{float(direction_deg):g}°"
    raise ValueError(f"direction_label: a cut has neither a direction name ({direction!r}) "
                     f"nor direction_deg ({direction_deg!r})")


def with_design(cuts: pd.DataFrame, experiment: Mapping[str, Any] | None = None
                ) -> pd.DataFrame:
    """The cut table with every design factor filled in.

    Parameters
    ----------
    cuts
        One row per cut (``results/ingest/cuts.csv`` or any per-cut artefact): ``direction``
        and/or ``direction_deg``, ``feed_mm_s``, optionally ``depth_mm``, ``set``,
        ``segment`` and the per-cut process keys (``spindle_rpm``, ``flutes``,
        ``tool_diameter_mm``, ``radial_immersion``, ``milling``).
    experiment
        The experiment defaults (manifest ``experiment``: ``spindle_rpm``, ``flutes``,
        ``tool_diameter_mm``) for the keys a cut does not set; radial immersion defaults to 1
        (slot) and the milling mode to ``slot`` (``down`` below full immersion), as in
        :func:`robomill.experiment.cut_process`.

    Returns
    -------
    pandas.DataFrame
        A copy with the process columns filled and ``direction`` replaced by its label
        (:func:`direction_label`); ``direction_deg`` filled from the names (+X = 0°). Columns
        that neither the table nor the experiment give stay absent.
    """
    experiment = dict(experiment or {})
    out = cuts.copy()
    for key in ("spindle_rpm", "flutes", "tool_diameter_mm"):
        default = experiment.get(key)
        if default is None:
            continue
        out[key] = out[key].fillna(default) if key in out else default
    if "radial_immersion" in out or "milling" in out or "spindle_rpm" in out:
        ae = out["radial_immersion"].fillna(1.0) if "radial_immersion" in out else \
            pd.Series(1.0, index=out.index)
        out["radial_immersion"] = ae.astype(float)
        mode = np.where(ae >= 1.0, "slot", "down")
        out["milling"] = (out["milling"].fillna(pd.Series(mode, index=out.index))
                          if "milling" in out else mode)
    if "flutes" in out:
        out["flutes"] = out["flutes"].astype(int)
    if "direction" in out or "direction_deg" in out:
        names = out["direction"] if "direction" in out else pd.Series(None, index=out.index)
        degs = out["direction_deg"] if "direction_deg" in out else \
            pd.Series(np.nan, index=out.index)
        by_label = {lab: DIRECTION_DEG[n] for n, lab in DIRECTION_LABELS.items()}
        out["direction"] = [direction_label(n, g) for n, g in zip(names, degs, strict=True)]
        out["direction_deg"] = [float(g) if not pd.isna(g) else
                                DIRECTION_DEG.get(n, by_label.get(lab, np.nan))
                                if lab[-1] != "°" else float(lab[:-1])
                                for n, g, lab in zip(names, degs, out["direction"],
                                                     strict=True)]
    return out


@dataclass(frozen=True)
class Design:
    """What the cuts of a study have in common and what varies (:func:`design_factors`)."""

    n_cuts: int
    grouping: list[str] = field(default_factory=list)
    """Varying factors that the per-cut tables group by (their index), in :data:`FACTORS`
    order."""
    dependent: list[str] = field(default_factory=list)
    """Varying factors fixed by the grouping factors before them (shown as columns)."""
    constant: dict[str, Any] = field(default_factory=dict)
    """Factors that every cut shares, with their value."""
    levels: dict[str, list] = field(default_factory=dict)
    """The values each varying factor takes, sorted."""


def _determined(table: pd.DataFrame, key: str, by: Sequence[str]) -> bool:
    """Whether ``key`` takes one value for each combination of the factors ``by``."""
    if not by:
        return False
    return bool((table.groupby(list(by), dropna=False)[key].nunique(dropna=False) <= 1).all())


def design_factors(cuts: pd.DataFrame, experiment: Mapping[str, Any] | None = None
                   ) -> Design:
    """The design factors that vary across the cuts, those that depend on them, and the ones
    every cut shares.

    Parameters
    ----------
    cuts
        One row per cut (see :func:`with_design`); columns that are absent are no factor.
    experiment
        The experiment defaults (:func:`with_design`).

    Returns
    -------
    Design
        For the thesis plan (3 sets × 5 segments × +Y, +X, −Y; depth by set, feed by
        segment): grouping ``[set, segment, direction]``, dependent ``[depth_mm, feed_mm_s]``.
        For one cut, or cuts that differ in nothing: no grouping factor, every factor
        constant.
    """
    table = with_design(cuts, experiment)
    present = [k for k in FACTORS if k in table and table[k].notna().any()]
    grouping: list[str] = []
    dependent: list[str] = []
    constant: dict[str, Any] = {}
    levels: dict[str, list] = {}
    for key in present:
        values = table[key].dropna().unique().tolist()
        if table[key].nunique(dropna=False) <= 1:
            v = values[0]
            constant[key] = v.item() if isinstance(v, np.generic) else v
            continue
        levels[key] = sorted(values, key=_sort_key)
        (dependent if _determined(table, key, grouping) else grouping).append(key)
    return Design(len(table), grouping, dependent, constant, levels)


def _sort_key(value: Any) -> tuple:
    """Numbers by value, labels by their text (a mixed column sorts numbers first)."""
    if isinstance(value, (int, float, np.integer, np.floating)):
        return (0, float(value), "")
    return (1, 0.0, str(value))


def format_factor(key: str, value: Any) -> str:
    """One factor value as text with its unit: ``18000 rpm``, ``3 flutes``, ``a_e/D 0.5``."""
    if key == "spindle_rpm":
        return f"{float(value):g} rpm"
    if key == "flutes":
        return f"{int(value)} flutes"
    if key == "tool_diameter_mm":
        return f"tool Ø {float(value):g} mm"
    if key == "radial_immersion":
        return f"a_e/D {float(value):g}"
    if key == "milling":
        return f"{value} milling" if value != "slot" else "slotting"
    if key == "depth_mm":
        return f"depth {float(value):g} mm"
    if key == "feed_mm_s":
        return f"feed {float(value):g} mm/s"
    if key in ("set", "segment"):
        return f"{key} {value}"
    return str(value)


def describe_design(cuts: pd.DataFrame, experiment: Mapping[str, Any] | None = None) -> str:
    """One line describing the design of the cuts.

    ``"45 cuts: 3 sets × 5 segments × 3 directions (depth by set, feed by set and segment);
    constant: 28000 rpm, 2 flutes, slotting"`` for the thesis plan; ``"6 cuts: 3 spindle
    speeds × 2 directions × 2 feeds (6 of the 12 combinations); constant: 3 flutes, …"`` for
    a fractional one; ``"1 cut; constant: …"`` for a single cut.
    """
    d = design_factors(cuts, experiment)
    head = f"{d.n_cuts} cut{'s' if d.n_cuts != 1 else ''}"
    if d.grouping:
        head += ": " + " × ".join(
            f"{len(d.levels[k])} {FACTOR_NAMES[k][1 if len(d.levels[k]) != 1 else 0]}"
            for k in d.grouping)
        full = int(np.prod([len(d.levels[k]) for k in d.grouping]))
        n_combos = len(with_design(cuts, experiment).drop_duplicates(d.grouping))
        if n_combos < full:
            head += f" ({n_combos} of the {full} combinations)"
        if d.dependent:
            head += " (" + ", ".join(
                f"{FACTOR_NAMES[k][0]} by " + " and ".join(
                    FACTOR_NAMES[g][0] for g in _determining(cuts, experiment, k, d.grouping))
                for k in d.dependent) + ")"
    if d.constant:
        head += "; constant: " + ", ".join(format_factor(k, v) for k, v in d.constant.items())
    return head


def design_summary(cuts: pd.DataFrame, experiment: Mapping[str, Any] | None = None
                   ) -> dict[str, Any]:
    """The design as chapter 0's findings state it (:func:`robomill.experiment_findings.
    experiment_findings`): ``design`` (:func:`describe_design`), ``grouping`` and
    ``dependent`` (:func:`design_factors`), and ``groups``: per level of the first grouping
    factor (sorted), its ``label`` (:func:`format_factor`) and the ids of its ``cuts``."""
    if not len(cuts):
        return {"design": None, "grouping": [], "dependent": [], "groups": []}
    d = design_factors(cuts, experiment)
    groups = []
    if d.grouping:
        first = d.grouping[0]
        filled = with_design(cuts, experiment)
        groups = [{"label": format_factor(first, level),
                   "cuts": filled.loc[filled[first] == level, "cut"].astype(str).tolist()}
                  for level in d.levels[first]]
    return {"design": describe_design(cuts, experiment), "grouping": list(d.grouping),
            "dependent": list(d.dependent), "groups": groups}


def _determining(cuts: pd.DataFrame, experiment: Mapping[str, Any] | None, key: str,
                 grouping: Sequence[str]) -> list[str]:
    """The shortest prefix of ``grouping`` that fixes ``key``."""
    table = with_design(cuts, experiment)
    for n in range(1, len(grouping) + 1):
        if _determined(table, key, grouping[:n]):
            return list(grouping[:n])
    return list(grouping)


def per_cut_table(results: pd.DataFrame, values: Sequence[str],
                  cuts: pd.DataFrame | None = None,
                  experiment: Mapping[str, Any] | None = None, *, key: str = "cut"
                  ) -> pd.DataFrame:
    """Per-cut results grouped by the design factors that vary.

    Parameters
    ----------
    results
        One row per cut (or per tracker run) with a ``key`` column and the ``values``.
    values
        The result columns to show (RMS, force levels, stiffness …), in that order.
    cuts
        The cut table (``results/ingest/cuts.csv``) joined on ``key`` for the design factors;
        None when ``results`` carries them itself.
    experiment
        The experiment defaults (:func:`with_design`).
    key
        The identifying column (``cut``, or ``run`` for tracker runs).

    Returns
    -------
    pandas.DataFrame
        Indexed by the grouping factors of the rows present (:func:`design_factors`; by
        ``key`` when nothing varies), sorted by them; columns ``key``, the dependent factors,
        then ``values``. A value column missing from ``results`` raises ``KeyError`` naming
        it.
    """
    missing = [v for v in values if v not in results]
    if missing:
        raise KeyError(f"per_cut_table: results have no column(s) {missing}")
    table = results
    if cuts is not None:
        extra = [c for c in cuts.columns if c == key or c not in results.columns]
        table = results.merge(cuts[extra], on=key, how="left")
    table = with_design(table, experiment)
    d = design_factors(table.drop(columns=list(values), errors="ignore"), experiment)
    index = d.grouping or [key]
    cols = ([key] if d.grouping else []) + d.dependent + list(values)
    out = table[index + [c for c in cols if c not in index]]
    out = out.sort_values(index, key=lambda s: s.map(_sort_key), kind="stable")
    return out.set_index(index)


def thesis_gate(thesis_study: bool | None) -> Callable[[str], str]:
    """The gate on the chapters' comparisons with the thesis' numbers.

    Returns a function ``vs_thesis(text)`` that returns ``text`` for a study of the thesis'
    design (:func:`robomill.experiment.is_thesis_study`; ``None``, a notebook run without the
    parameter, counts as the thesis study) and ``""`` otherwise, so that a remark such as
    ``" (thesis: 13 Hz)"`` appears only where it means something.
    """
    show = thesis_study is not False

    def vs_thesis(text: str) -> str:
        return text if show else ""

    vs_thesis.shown = show  # type: ignore[attr-defined]
    return vs_thesis


def dominant_wavelengths(peaks: pd.DataFrame, *, by: str = "band",
                         f_col: str = "f_spatial_per_mm", amp_col: str = "amplitude_um",
                         key: str = "cut") -> pd.DataFrame:
    """The wavelength of each cut's largest peak per group (band, component …).

    Parameters
    ----------
    peaks
        One row per peak: ``key``, ``by``, the spatial frequency ``f_col`` [mm⁻¹] and the
        amplitude ``amp_col``.

    Returns
    -------
    pandas.DataFrame
        Index ``key``; one column ``<group>_wavelength_mm`` = 1 / f of the largest-amplitude
        peak of that group per cut (NaN where the cut has none).
    """
    if not len(peaks):
        return pd.DataFrame(index=pd.Index([], name=key))
    top = peaks.loc[peaks.groupby([key, by])[amp_col].idxmax()]
    out = (1.0 / top.set_index([key, by])[f_col]).unstack(by)
    out.columns = [f"{c}_wavelength_mm" for c in out.columns]
    out.columns.name = None
    return out


def span(values: Sequence[float] | pd.Series, fmt: str = ".2f") -> str:
    """``"1.67–6.67"`` for a range of values (``"-0.88 to -0.66"`` below zero), ``"3.33"``
    when they are all one value."""
    v = pd.Series(values, dtype=float).dropna()
    if not len(v):
        return "none"
    lo, hi = v.min(), v.max()
    if f"{lo:{fmt}}" == f"{hi:{fmt}}":
        return f"{lo:{fmt}}"
    return f"{lo:{fmt}}{' to ' if lo < 0 else '–'}{hi:{fmt}}"
