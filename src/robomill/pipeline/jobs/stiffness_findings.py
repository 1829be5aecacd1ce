"""Chapter 5's findings (robomill.stiffness.findings), with the scorecard rows of the stage
for its "Against the source" section.

The job of the rule script ``workflow/scripts/stiffness_findings.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.findings import write_findings
from robomill.io import open_artefact
from robomill.pipeline.scorecard import stage_comparisons
from robomill.stiffness.findings import stiffness_findings


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    has = set(inputs.keys())
    planted = None
    if "truth" in has:
        truth = open_artefact(inputs.truth)
        robots = [str(r) for r in truth["stiffness_robot"].values]
        if params.map_robot in robots:
            planted = truth["stiffness_k_Nm_rad"].sel(stiffness_robot=params.map_robot).values
    found = stiffness_findings(
        open_artefact(inputs.maps), pd.read_csv(inputs.optimal), open_artefact(inputs.beamframe),
        pd.read_csv(inputs.joints), pd.read_csv(inputs.validation), planted_k_Nm_rad=planted,
        cut_stiffness=pd.read_csv(inputs.cut_stiffness) if "cut_stiffness" in has else None,
        slots=pd.read_csv(inputs.slots) if "slots" in has else None,
        waviness=pd.read_csv(inputs.waviness, index_col=0) if "waviness" in has else None,
        thesis_joints=pd.read_csv(inputs.thesis_joints) if "thesis_joints" in has else None,
        slot_asymmetry_pct=params.slot_asymmetry_pct)
    found.add("thesis_study", bool(params.thesis_study), what="robomill.experiment.is_thesis_study")
    found.comparisons = stage_comparisons("stiffness", thesis_study=bool(params.thesis_study))
    write_findings(found, outputs.findings)
    log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
