"""Chapter 3.2's findings (robomill.straightness.findings), with the scorecard rows of the
stage for its "Against the thesis" section.

The job of the rule script ``workflow/scripts/straightness_findings.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.findings import write_findings
from robomill.io import open_artefact
from robomill.pipeline.scorecard import stage_comparisons
from robomill.straightness.findings import straightness_findings


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    peaks = pd.read_csv(inputs.peaks, keep_default_na=False, na_values=[""])
    surface = pd.read_csv(inputs.surface_peaks) if "surface_peaks" in inputs.keys() else None
    found = straightness_findings(open_artefact(inputs.profiles), peaks,
                                  surface_band_per_mm=params.surface_band_per_mm,
                                  fmax_store_per_mm=params.fmax_store_per_mm,
                                  threshold=params.threshold,
                                  surface_peaks=surface,
                                  truth_check=pd.read_csv(inputs.truth_check),
                                  tol_bins=params.tol_bins, fmin_cycles=params.fmin_cycles,
                                  truth_margin=params.truth_margin,
                                  thesis_design=params.thesis_design)
    found.comparisons = stage_comparisons("straightness", thesis_study=bool(params.thesis_study))
    write_findings(found, outputs.findings)
    log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
