"""What the planner and ``robomill predict`` read of a study: the identified quantities
(:class:`robomill.plan.measured.Measured`), the planner's view of the cell, the study's reach
and its chatter verdicts, from the study's artefacts, by one routine (:func:`load_inputs`).

The plan rule records the artefacts and parameters it read in ``results/plan/model.yaml``
(:func:`model_record`), so that ``robomill predict`` predicts any list of cuts from the same
inputs with the same code as the plan (:func:`load_recorded`).
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr
import yaml

from robomill.catalogue import artefact
from robomill.errors import RawDataError

MODEL_RECORD = artefact("plan.model")
"""Where the plan rule records its inputs (relative to the project folder)."""

INPUT_KEYS = ("modes", "modal_fit", "coefficients", "means", "joints", "peaks", "profiles",
              "verdicts", "request", "cell", "study")
"""The artefacts the planner may read (each optional but ``request``, ``cell``, ``study``)."""


@dataclass
class PlanInputs:
    """The planner's inputs: the request, the identified quantities, the cell, the study's
    cuts and experiment, their midpoints [mm] (None when not placed), the reach, the
    chatter verdicts per cut (1 stable, 0 chatter, NaN undetermined; None without) and the
    study's slots."""

    req: Any
    measured: Any
    cell: Any
    cell_file: Any
    cuts: list
    experiment: dict
    mids: np.ndarray | None
    reach: Any
    stability: pd.Series | None
    slots: list | None
    notes: list[str] = field(default_factory=list)
    study_cuts: list = field(default_factory=list)
    """The study's cuts with the process the ingestion rule resolved
    (:class:`robomill.study.StudyCut`): the candidates of the study's own cuts."""
    impact_tcp_mm: np.ndarray | None = None
    """Where the impact test was made [mm, base frame], as its files state it (None where
    they do not)."""


def load_inputs(paths: Mapping[str, str], params: Mapping[str, Any], *,
                log: logging.Logger | None = None) -> PlanInputs:
    """The planner's inputs from the artefacts ``paths`` (keys of :data:`INPUT_KEYS`) and the
    parameters ``params`` (``waviness_noise``, ``fmin_cycles``, ``level``); the study's cuts
    and experiment come from its ``study`` artefact."""
    from robomill.experiment import cut_endpoints_mm
    from robomill.forces.prediction import regression_from_means
    from robomill.io.cell import read_cell
    from robomill.plan.check import waviness_min_cycles
    from robomill.plan.evidence import read_verdicts, verdict_stability
    from robomill.plan.extrapolation import axes_not_measured, reach_from_means
    from robomill.plan.measured import Measured, cut_mid_poses, gear_joint_amplitudes
    from robomill.plan.outputs import cell_of
    from robomill.plan.request import read_request
    from robomill.study import load_study, read_study

    log = log or logging.getLogger("robomill.plan")
    req = read_request(paths["request"])
    cell_file = read_cell(paths["cell"])
    study = load_study(paths["study"])
    cuts = list(study.cuts)
    experiment = dict(study.experiment)  # the study's, its block layout resolved at ingestion
    placed = bool(cuts) and experiment.get("cut_length_mm") is not None
    notes = []
    if cuts and not placed:
        notes.append("the study gives no cut_length_mm: its cuts are not placed (no gear "
                     "lines carried)")
    mids = (np.array([np.mean(cut_endpoints_mm(c, experiment), 0) for c in cuts]) if placed
            else None)
    band, tcp = modal_fit_band_and_pose(paths.get("modal_fit"))
    if tcp is not None and req.reference_point_mm is not None and not np.allclose(
            tcp, req.reference_point_mm, rtol=0.0, atol=1e-6):
        log.info("reference pose: the impact test's TCP %s from its files, not the request's "
                 "reference_point_mm %s", np.round(tcp, 3).tolist(),
                 np.round(req.reference_point_mm, 3).tolist())
    cell = cell_of(cell_file, req, tcp)

    def table(name):
        return pd.read_csv(paths[name]) if paths.get(name) else None

    gears = None
    noise = params["waviness_noise"]
    level = float(params["level"])
    if paths.get("peaks") and placed:
        poses = cut_mid_poses(cell.robot, cuts, experiment, tool_rotation=cell.R0,
                              q0_rad=cell.q_seed_rad)
        profiles = xr.load_dataset(paths["profiles"]) if paths.get("profiles") else None
        gears = gear_joint_amplitudes(
            pd.read_csv(paths["peaks"]), cell.robot, poses, profiles=profiles,
            noise_band_bins=float(noise["band_bins"]),
            noise_exclude_bins=float(noise["exclude_bins"]), level=level)
        log.info("gear elements (joint amplitudes, tracker noise):\n%s", gears.to_string())
    regression = regression_from_means(table("means"), int(experiment.get("flutes", req.flutes)))
    measured = Measured(modes=table("modes"), coefficients=table("coefficients"),
                        joints=table("joints"), gears=gears, force_regression=regression,
                        level=level, waviness_coverage=float(noise["coverage"]),
                        waviness_min_cycles=waviness_min_cycles(
                            params["fmin_cycles"], float(noise["exclude_bins"])))
    require_reference_pose(tcp, req, measured, paths.get("modal_fit") or paths["modes"])
    # the axes the impact test did not measure: empty shape columns of modes.csv
    reach = reach_from_means(table("means"), experiment, mids, band,
                             axes_not_measured(measured.modes))
    slots = ([np.asarray(cut_endpoints_mm(c, experiment), float) for c in cuts] if placed
             else None)
    stability = None
    if paths.get("verdicts"):
        try:
            stability = verdict_stability(read_verdicts(paths["verdicts"]))
        except RawDataError as err:
            notes.append(f"{err} (the stability model is not weighted by verdicts)")
    return PlanInputs(req, measured, cell, cell_file, cuts, experiment, mids, reach,
                      stability, slots, notes, study_cuts=list(read_study(paths["study"]).cuts),
                      impact_tcp_mm=tcp)


def require_reference_pose(tcp_mm: np.ndarray | None, req: Any, measured: Any,
                           where: str | None) -> None:
    """Stop with one line where the planner must move the impact test's robot modes to the
    cuts' poses (modes and joint stiffness measured) but knows no pose of the test: neither
    the impact files' ``tcp_mm`` nor the request's ``reference_point_mm``."""
    if (tcp_mm is None and req.reference_point_mm is None and measured.has("modes")
            and measured.has("joints")):
        raise RawDataError(where or "results/modal", "the impact test states no pose, so its "
                           "modes cannot be moved to the cuts' poses",
                           expected="the TCP point of the test as manifest key tcp_mm of its "
                           f"impact entries, or reference_point_mm in {req.path}")


def modal_fit_band_and_pose(path: str | None) -> tuple[list[float] | None, np.ndarray | None]:
    """The impact test's band [Hz] and the TCP point [mm, base frame] where it was made (the
    modal stage's ``frf_synth.nc`` attributes ``band_hz`` and ``impact_tcp_mm``, from the
    impact entries' manifest key ``tcp_mm``); None for what the file (or its absence) does
    not give."""
    if not path:
        return None, None
    with xr.open_dataset(path) as fit:
        band = [float(b) for b in np.atleast_1d(fit.attrs.get("band_hz", []))] or None
        tcp = (np.asarray(fit.attrs["impact_tcp_mm"], float).reshape(3)
               if "impact_tcp_mm" in fit.attrs else None)
    return band, tcp


def model_record(paths: Mapping[str, str], params: Mapping[str, Any]) -> dict[str, Any]:
    """``results/plan/model.yaml``: the artefacts (project-relative paths) and parameters the
    plan read."""
    def plain(v):
        if isinstance(v, Mapping):
            return {str(k): plain(x) for k, x in v.items()}
        if isinstance(v, list | tuple):
            return [plain(x) for x in v]
        if isinstance(v, np.generic):
            return v.item()
        return v

    return {"kind": "plan_model",
            "inputs": {k: str(paths[k]) for k in INPUT_KEYS if paths.get(k)},
            "params": plain({k: params[k] for k in ("waviness_noise", "fmin_cycles",
                                                    "level")})}


def load_recorded(study: str | Path, *, request: str | Path | None = None) -> PlanInputs:
    """The inputs the plan of the project folder ``study`` read (its
    ``results/plan/model.yaml``; ``study`` may also be that results folder), with another
    ``request`` if given.

    Raises
    ------
    RawDataError
        No record (the plan was not made there), or a recorded artefact is missing.
    """
    root = Path(study)
    if (root / "plan" / "model.yaml").exists() and not (root / MODEL_RECORD).exists():
        root = root.parent
    rec_path = root / MODEL_RECORD
    if not rec_path.exists():
        raise RawDataError(rec_path, "no record of the plan's inputs",
                           expected="a study whose plan was made (snakemake -j2 plan)")
    rec = yaml.safe_load(rec_path.read_text())
    if not isinstance(rec, dict) or rec.get("kind") != "plan_model":
        raise RawDataError(rec_path, "not a record of the plan's inputs",
                           expected="kind: plan_model, as the plan rule writes it")
    paths = {k: str(root / v) for k, v in rec["inputs"].items()}
    if request is not None:
        paths["request"] = str(request)
    for k, p in paths.items():
        if not Path(p).exists():
            raise RawDataError(p, f"the plan's input {k} is missing", where=str(rec_path),
                               expected="the study's artefacts as the plan read them")
    return load_inputs(paths, rec["params"])
