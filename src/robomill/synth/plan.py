"""The synthetic study: which raw files the instrument simulators write, and the manifest."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from robomill.experiment import Cut, plan_cuts
from robomill.synth import ctrack, dynamometer, impact, loadtests, profilometer, tracker

INSTRUMENTS = {
    "profile": profilometer,
    "force": dynamometer,
    "tracker": tracker,
    "impact": impact,
    "ctrack": ctrack,
    "stiffness": loadtests,
}
"""Instrument module per raw-data kind; each has ``plan(config) -> list[dict]``."""


def synthetic_cuts(config: Mapping[str, Any]) -> list[Cut]:
    """The cuts of the virtual study (``experiment.sets`` cycled to ``synth.sets`` sets)."""
    exp = config["experiment"]
    return plan_cuts(exp["sets"], int(config["synth"]["sets"]), exp["directions"])


def experiment_header(config: Mapping[str, Any]) -> dict[str, Any]:
    """The manifest's ``experiment`` mapping from the configuration."""
    exp = config["experiment"]
    return {k: exp[k] for k in ("spindle_rpm", "flutes", "tool_diameter_mm", "cut_length_mm")}


def planned_files(config: Mapping[str, Any]) -> list[dict[str, Any]]:
    """Every synthetic raw file (path relative to the raw folder, kind, metadata): the cell
    file ``cell.yaml`` (written from ``config.yaml: cell``), then each instrument's files."""
    files: list[dict[str, Any]] = [{"path": "cell.yaml", "kind": "cell"}]
    for module in INSTRUMENTS.values():
        files.extend(module.plan(config))
    return files
