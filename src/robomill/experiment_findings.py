"""Chapter 0's findings: what the experiment is, computed from the study's cut table and
rendered by the chapter (:mod:`robomill.pipeline.prose`).

- the cuts: how many, in how many sets of how many segments and along which directions where
  they follow the thesis' layout (ids ``s{set}_g{segment}_{dir}``, §2.1);
- the process of every cut (its own keys, else the experiment's): spindle speed n [rpm] and
  its frequency n / 60 [Hz], tooth-passing frequency N n / 60 and feed per tooth
  c = v / (N n) ([Pulatbek 2024, §2.1]; :func:`robomill.experiment.feed_per_tooth_mm`), one
  value or a range;
- the design (what varies, what is constant, as :mod:`robomill.pipeline.design_tables`
  describes it) and, for a design other than the thesis', the feed per tooth and tooth
  passing of each level of its first grouping factor;
- the thesis' cell (§2.1) its "Against the thesis" section names, from
  ``robomill/data/references.yaml``.

The comparison rows (the thesis' feed per tooth at 1 and 10 mm/s beside ours) are the
scorecard's checks of ``results/ingest/cuts.csv``, added by the rule script.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd

from robomill import catalogue, references
from robomill.experiment import (
    CUT_ID,
    CUT_PROCESS_KEYS,
    DIRECTION_LABELS,
    DIRECTIONS,
    feed_per_tooth_mm,
    spindle_hz,
    tooth_passing_hz,
)
from robomill.findings import Findings

_CUTS = catalogue.artefact("ingest.cuts")
_STUDY = catalogue.artefact("ingest.study")
_REFERENCES = "src/robomill/data/references.yaml"
_CELL = ("robot", "workpiece", "dynamometer", "tool", "spindle_rpm")


def _span(values) -> list[float]:
    v = np.asarray(values, float)
    return [float(np.min(v)), float(np.max(v))]


def _one(values) -> float | None:
    """The value every cut shares (rounded to 1e-9 relative), else ``None``."""
    v = np.unique(np.round(np.asarray(values, float), 9))
    return float(v[0]) if v.size == 1 else None


def _process_column(cuts: pd.DataFrame, key: str, experiment: Mapping[str, Any]
                    ) -> pd.Series | None:
    """A process key per cut: the cut's own value, else the experiment's; ``None`` where
    neither gives one for every cut."""
    default = experiment.get(key)
    col = (pd.to_numeric(cuts[key], errors="coerce") if key in cuts
           else pd.Series(np.nan, index=cuts.index))
    if default is not None:
        col = col.fillna(float(default))
    return None if col.isna().any() else col.astype(float)


def thesis_layout_of(cuts: pd.DataFrame) -> bool:
    """Whether the cut table follows the thesis' layout: every id ``s{set}_g{segment}_{dir}``
    and no cut with a process key of its own (the table's view of
    :func:`robomill.experiment.is_thesis_design`, which also checks ``start_mm``)."""
    own = [k for k in CUT_PROCESS_KEYS if k in cuts and cuts[k].notna().any()]
    return bool(len(cuts)) and not own and all(CUT_ID.match(str(c)) for c in cuts["cut"])


def experiment_findings(cuts: pd.DataFrame, experiment: Mapping[str, Any] | None = None, *,
                        design: Mapping[str, Any] | None = None,
                        thesis_design: bool | None = None,
                        thesis_study: bool = False) -> Findings:
    """The findings of the experiment (chapter 0).

    Parameters
    ----------
    cuts
        ``results/ingest/cuts.csv``: ``cut``, ``feed_mm_s``, ``depth_mm``, optionally ``set``,
        ``segment``, ``direction`` and the cuts' own process keys (``spindle_rpm``,
        ``flutes`` …; empty = the experiment's).
    experiment
        The study's experiment defaults (``results/ingest/study.yaml``: ``spindle_rpm``,
        ``flutes``) for the cuts that do not set them.
    design
        The design as the rule describes it (:func:`robomill.pipeline.design_tables.
        design_summary`, tooling this module does not import): ``design`` (one line),
        ``grouping`` and ``dependent`` (factors), ``groups`` (``[{label, cuts}]``: the cuts
        of each level of the first grouping factor). ``None`` leaves these findings out.
    thesis_design
        :func:`robomill.experiment.is_thesis_design` of the study's cuts; ``None``: judged
        from the table (:func:`thesis_layout_of`).
    thesis_study
        :func:`robomill.experiment.is_thesis_study`: the closing section names the thesis'
        cell.

    Returns
    -------
    Findings
        ``n_cuts``, ``has_cuts``, ``missing`` (process keys no cut or default gives);
        ``thesis_layout``, ``thesis_study``, with the layout ``n_sets``, ``n_segments``
        (most per set), ``directions`` (labels, machining order), ``n_directions``;
        ``feed_mm_s_range``, ``depth_mm_values``, ``flutes_values``; ``single_speed`` and
        ``spindle_rpm``, ``spindle_hz``, ``tooth_passing_hz`` (the one value, ``None`` if
        several),
        ``spindle_rpm_range``, ``spindle_hz_range``, ``tooth_passing_hz_range``,
        ``feed_per_tooth_um_range``; from ``design``: ``design``, ``grouping``,
        ``dependent``, ``group_by`` and ``groups`` (per level: ``label``,
        ``feed_per_tooth_um`` and ``tooth_passing_hz`` as ``[min, max]``); the thesis' cell
        ``ref_robot``, ``ref_workpiece``, ``ref_dynamometer``, ``ref_tool``,
        ``ref_spindle_rpm`` and ``ref_cell_where``.
    """
    experiment = dict(experiment or {})
    found = Findings("ingest")
    found.add("n_cuts", len(cuts), artefact=_CUTS, what="rows")
    found.add("has_cuts", bool(len(cuts)), artefact=_CUTS, what="rows")
    layout = thesis_layout_of(cuts) if thesis_design is None else bool(thesis_design)
    found.add("thesis_layout", layout, artefact=_STUDY,
              what="cut ids s{set}_g{segment}_{dir}, no per-cut process keys")
    found.add("thesis_study", bool(thesis_study), artefact=_STUDY,
              what="thesis layout, spindle speed and flutes")
    rpm = _process_column(cuts, "spindle_rpm", experiment)
    flutes = _process_column(cuts, "flutes", experiment)
    found.add("missing", [k for k, v in (("spindle_rpm", rpm), ("flutes", flutes))
                          if v is None and len(cuts)],
              artefact=_STUDY, what="experiment defaults and the cuts' own keys")
    if not len(cuts):
        _sources(found)
        return found
    if layout:
        _layout(found, cuts)
    found.add("feed_mm_s_range", _span(cuts["feed_mm_s"]), "mm/s", artefact=_CUTS,
              what="feed_mm_s")
    found.add("depth_mm_values", sorted(float(d) for d in cuts["depth_mm"].dropna().unique()),
              "mm", artefact=_CUTS, what="depth_mm")
    if rpm is not None and flutes is not None:
        _process(found, cuts, rpm, flutes, design)
    if design is not None:
        found.add("design", design.get("design"), artefact=_CUTS, what="design factors")
        found.add("grouping", list(design.get("grouping") or []), artefact=_CUTS,
                  what="factors the per-cut tables group by")
        found.add("dependent", list(design.get("dependent") or []), artefact=_CUTS,
                  what="factors fixed by the grouping factors")
    _sources(found)
    return found


def _layout(found: Findings, cuts: pd.DataFrame) -> None:
    """Sets, segments and directions of a study in the thesis' layout."""
    if "set" in cuts and cuts["set"].notna().any():
        found.add("n_sets", int(cuts["set"].nunique()), artefact=_CUTS, what="set")
        if "segment" in cuts:
            found.add("n_segments", int(cuts.groupby("set")["segment"].nunique().max()),
                      artefact=_CUTS, what="segments per set (most)")
    if "direction" in cuts:
        present = set(cuts["direction"].dropna())
        labels = [DIRECTION_LABELS[d] for d in DIRECTIONS if d in present]
        found.add("directions", labels, artefact=_CUTS,
                  what="direction, in machining order (+Y, +X, −Y)")
        found.add("n_directions", len(labels), artefact=_CUTS, what="direction")


def _process(found: Findings, cuts: pd.DataFrame, rpm: pd.Series, flutes: pd.Series,
             design: Mapping[str, Any] | None) -> None:
    """Spindle speed, tooth passing N n / 60 and feed per tooth c = v / (N n) of every cut
    [Pulatbek 2024, §2.1], overall and per level of the design's first grouping factor."""
    hz = spindle_hz(rpm)
    tooth = tooth_passing_hz(rpm, flutes)
    c_um = 1e3 * feed_per_tooth_mm(cuts["feed_mm_s"].astype(float), rpm, flutes)
    what = "cut's own value, else the experiment's"
    found.add("flutes_values", sorted(int(z) for z in flutes.unique()), artefact=_STUDY,
              what=f"flutes: {what}")
    found.add("single_speed", _one(rpm) is not None and _one(tooth) is not None,
              artefact=_STUDY, what="one spindle speed and one tooth-passing frequency")
    found.add("spindle_rpm", _one(rpm), "rpm", artefact=_STUDY, what=f"spindle_rpm: {what}")
    found.add("spindle_hz", _one(hz), "Hz", artefact=_STUDY, what="spindle_rpm / 60")
    found.add("tooth_passing_hz", _one(tooth), "Hz", artefact=_STUDY,
              what="flutes × spindle_rpm / 60")
    found.add("spindle_rpm_range", _span(rpm), "rpm", artefact=_STUDY, what="spindle_rpm")
    found.add("spindle_hz_range", _span(hz), "Hz", artefact=_STUDY, what="spindle_rpm / 60")
    found.add("tooth_passing_hz_range", _span(tooth), "Hz", artefact=_STUDY,
              what="flutes × spindle_rpm / 60")
    found.add("feed_per_tooth_um_range", _span(c_um), "um", artefact=_CUTS,
              what="1000 feed_mm_s / (flutes × spindle_rpm / 60)")
    grouping = list((design or {}).get("grouping") or [])
    found.add("group_by", grouping[0] if grouping else None, artefact=_CUTS,
              what="first grouping factor")
    groups = []
    for g in (design or {}).get("groups") or []:
        sel = cuts["cut"].isin(list(g["cuts"])).to_numpy()
        if sel.any():
            groups.append({"label": str(g["label"]), "feed_per_tooth_um": _span(c_um[sel]),
                           "tooth_passing_hz": _span(tooth[sel])})
    found.add("groups", groups, artefact=_CUTS,
              what="per level of the first grouping factor: [min, max] of c and N n / 60")


def _sources(found: Findings) -> None:
    """The thesis' cell (§2.1) that chapter 0's "Against the thesis" names
    (``robomill/data/references.yaml``)."""
    for part in _CELL:
        key = f"thesis.cell.{part}"
        found.add(f"ref_{part}", references.value(key), references.reference(key)["unit"],
                  artefact=_REFERENCES, what=key)
    found.add("ref_cell_where", references.reference("thesis.cell.robot")["where"],
              artefact=_REFERENCES, what="thesis.cell.robot: where")
