"""Chapter 2's findings (robomill.surface.findings), with the scorecard rows of the stage for
its "Against the thesis" section.

The job of the rule script ``workflow/scripts/surface_findings.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.findings import write_findings
from robomill.io import open_artefact
from robomill.pipeline.design_tables import describe_design
from robomill.pipeline.scorecard import stage_comparisons
from robomill.surface.findings import surface_findings
from robomill.surface.options import settings


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    metrics = pd.read_csv(inputs.metrics)
    cuts = pd.read_csv(inputs.cuts)
    optional = {k: pd.read_csv(inputs[k]) for k in ("comparison", "recovery", "reference", "areal",
                                                "profile_vs_areal") if k in inputs.keys()}
    found = surface_findings(
        metrics, pd.read_csv(inputs.peaks), open_artefact(inputs.profiles),
        settings=settings(params.settings), thesis_layout=bool(params.thesis_layout),
        synthetic=bool(params.synthetic),
        design=describe_design(cuts[cuts["cut"].isin(metrics["cut"])], params.experiment),
        **optional)
    found.comparisons = stage_comparisons("surface", thesis_study=bool(params.thesis_study))
    write_findings(found, outputs.findings)
    log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
