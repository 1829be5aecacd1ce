"""Chapter 2 tables: the thesis layout of Tables 2.1/2.2 and the comparison with the thesis'
values, the per-design table of any other design, the chapter's summaries (direction
means, feed correlation, comparison summary, peak counts) and which cuts its figures show
(directions, the example cut, the cuts of a figure per direction).
"""

from __future__ import annotations

from collections.abc import Sequence
from importlib import resources

import numpy as np
import pandas as pd
import yaml

from robomill.experiment import DIRECTION_LABELS

DIRECTION_ORDER = ("px", "py", "my")
"""Column order of the thesis tables within a set: +X, +Y, −Y."""

def table_column(set_: int, direction: str) -> str:
    """Column name of the thesis tables: ``s{set}_{dir}``."""
    return f"s{int(set_)}_{direction}"


def rms_table(metrics: pd.DataFrame, value: str) -> pd.DataFrame:
    """A thesis-layout table (Table 2.1 / 2.2): rows ``segment`` 1–5, columns
    ``s1_px, s1_py, s1_my, s2_px, …`` (set-major, +X, +Y, −Y), values of column ``value``."""
    df = metrics.copy()
    df["column"] = [table_column(s, d) for s, d in zip(df["set"], df["direction"], strict=True)]
    tab = df.pivot_table(index="segment", columns="column", values=value, aggfunc="first")
    sets = sorted(df["set"].unique())
    cols = [table_column(s, d) for s in sets for d in DIRECTION_ORDER
            if table_column(s, d) in tab.columns]
    tab = tab[cols]
    tab.index = tab.index.astype(int)
    tab.index.name = "segment"
    tab.columns.name = None
    return tab


def load_thesis_tables() -> dict[str, pd.DataFrame]:
    """Thesis Tables 2.1 (waviness) and 2.2 (roughness) from the package data file
    ``robomill/data/thesis_tables_ch2.yaml``, in the layout of :func:`rms_table`."""
    text = resources.files("robomill.data").joinpath("thesis_tables_ch2.yaml").read_text()
    data = yaml.safe_load(text)
    out = {}
    for key in ("table_2_1_waviness_rms_um", "table_2_2_roughness_rms_um"):
        t = data[key]
        df = pd.DataFrame(t["values"], columns=t["columns"],
                          index=pd.Index(t["segments"], name="segment"))
        out[key] = df
    return out


def compare_with_thesis(ours: pd.DataFrame, thesis: pd.DataFrame, table: str,
                        factor: float = 1.5) -> pd.DataFrame:
    """Long comparison table: every cell present in both, ``pipeline_um, thesis_um, ratio``
    and whether the ratio lies within ``[1/factor, factor]``."""
    rows = []
    for seg in ours.index:
        for col in ours.columns:
            if seg in thesis.index and col in thesis.columns:
                a, b = float(ours.loc[seg, col]), float(thesis.loc[seg, col])
                rows.append({"table": table, "segment": int(seg), "column": col,
                             "pipeline_um": a, "thesis_um": b, "ratio": a / b,
                             f"within_{factor:g}x": bool(1 / factor <= a / b <= factor)})
    return pd.DataFrame(rows)

#: design keys of a cut, in the order the per-design table groups by them
DESIGN_KEYS = ("path_direction", "spindle_rpm", "flutes", "tool_diameter_mm",
               "radial_immersion", "milling", "depth_mm", "feed_mm_s")


def path_direction(direction: str | None, direction_deg: float | None) -> str:
    """One label per feed direction: the name (``px``, ``mx``, ``py``, ``my``) or
    ``"<deg> deg"`` for a ``direction_deg`` cut."""
    if direction_deg is not None and not pd.isna(direction_deg):
        return f"{float(direction_deg):g} deg"
    return str(direction)


def design_table(metrics: pd.DataFrame,
                 values: Sequence[str] = ("waviness_rms_um", "roughness_rms_um", "Wq_um",
                                          "Rq_um")) -> pd.DataFrame:
    """The per-cut table of a design other than the thesis' (``metrics_by_design.csv``).

    The design keys that vary across the cuts (of :data:`DESIGN_KEYS`) come first, in that
    order, and the rows are sorted by them (so the cuts of a spindle-speed series at one
    direction sit together, in increasing speed), then ``cut``, ``feed_per_tooth_mm``,
    ``tooth_passing_hz`` and ``values``. A key that every cut shares is left out (it is one
    value of the experiment).
    """
    varying = [k for k in DESIGN_KEYS if k in metrics and metrics[k].nunique(dropna=False) > 1]
    cols = varying + ["cut", "feed_per_tooth_mm", "tooth_passing_hz", *values]
    tab = metrics[[c for c in cols if c in metrics]]
    return tab.sort_values(varying + ["cut"] if varying else ["cut"], kind="stable"
                           ).reset_index(drop=True)

def direction_means(metrics: pd.DataFrame) -> pd.DataFrame:
    """Mean waviness and roughness RMS per cut direction (thesis §2.3: X smallest, +Y
    largest).

    Parameters
    ----------
    metrics
        ``results/surface/metrics.csv`` (``direction, waviness_rms_um, roughness_rms_um``).

    Returns
    -------
    pandas.DataFrame
        Index ``direction``; ``waviness_rms_um, roughness_rms_um`` (means over the cuts of
        that direction, µm) and ``n_cuts``.
    """
    g = metrics.groupby("direction")
    out = g[["waviness_rms_um", "roughness_rms_um"]].mean()
    out["n_cuts"] = g.size()
    return out


def feed_correlation(metrics: pd.DataFrame) -> pd.Series:
    """Pearson correlation of the waviness and roughness RMS with the feed over every cut
    (thesis §2.3: a higher feed raises the amplitude).

    Returns
    -------
    pandas.Series
        ``waviness`` and ``roughness``: ``r = cov(v, RMS)/(σ_v σ_RMS)``; NaN with fewer than
        two cuts or no spread in the feed.
    """
    def r(col: str) -> float:
        if len(metrics) < 2 or metrics["feed_mm_s"].nunique() < 2:
            return float("nan")
        return float(np.corrcoef(metrics["feed_mm_s"], metrics[col])[0, 1])

    return pd.Series({"waviness": r("waviness_rms_um"), "roughness": r("roughness_rms_um")})


def comparison_summary(comparison: pd.DataFrame) -> pd.DataFrame:
    """How many cells of each thesis table the pipeline reproduces within a factor 1.5.

    Parameters
    ----------
    comparison
        ``results/surface/thesis_comparison.csv`` (``table, ratio, within_1.5x``).

    Returns
    -------
    pandas.DataFrame
        Index ``table``; ``within`` (cells within 1.5×), ``cells`` and ``median_ratio``
        (median of pipeline/thesis).
    """
    g = comparison.groupby("table")
    return pd.DataFrame({"within": g["within_1.5x"].sum().astype(int),
                         "cells": g.size(), "median_ratio": g["ratio"].median()})


def path_label(direction: str) -> str:
    """``+X``, ``−Y`` … for a named direction, ``45°`` for an artefact's path direction
    ``"45 deg"``."""
    d = str(direction)
    return DIRECTION_LABELS.get(d) or f"{float(d.split()[0]):g}°"


def with_directions(metrics: pd.DataFrame) -> pd.DataFrame:
    """``metrics`` with ``direction`` (a free design's ``path_direction`` where it has none)
    and its printed ``label``."""
    out = metrics.copy()
    if "direction" not in out:
        out["direction"] = out["path_direction"]
    out["direction"] = out["direction"].astype(str)
    out["label"] = [path_label(d) for d in out["direction"]]
    return out


def figure_directions(metrics: pd.DataFrame, thesis_layout: bool) -> list[str]:
    """The directions of the profile figures: the thesis' +X, +Y, −Y present in its first set,
    or every path direction of any other design (sorted by name)."""
    m = with_directions(metrics)
    if thesis_layout:
        first = m[m["set"] == m["set"].min()]
        return [d for d in DIRECTION_ORDER if (first["direction"] == d).any()]
    return sorted(m["direction"].unique(), key=str)


def example_cut(metrics: pd.DataFrame, thesis_layout: bool) -> str:
    """The cut of the single-profile figures: the first by set and segment in the thesis
    layout, the first of the plan otherwise."""
    m = metrics.sort_values(["set", "segment"], kind="stable") if thesis_layout else metrics
    return str(m.iloc[0]["cut"])


def plot_groups(metrics: pd.DataFrame, directions: Sequence[str], thesis_layout: bool,
                set_: int | None = None) -> dict[str, pd.DataFrame]:
    """The cuts of one figure, per direction, in plot order: one set by segment (thesis
    layout) or every cut by feed (any other design)."""
    m = with_directions(metrics)
    if thesis_layout:
        sel = m[m["set"] == set_] if set_ is not None else m
        return {d: sel[sel["direction"] == d].sort_values("segment") for d in directions}
    return {d: m[m["direction"] == d].sort_values(["feed_mm_s", "cut"]) for d in directions}


def peak_counts(peaks: pd.DataFrame) -> pd.DataFrame:
    """Peaks of ``results/surface/peaks.csv`` counted by ``band`` (rows) and ``mechanism``
    (columns)."""
    return peaks.groupby(["band", "mechanism"]).size().unstack(fill_value=0)
