"""All tracker runs: profiles.nc, gears.csv and peaks.csv (temporal vs spatial classification;
see robomill.straightness.gather_profiles, gather_gears, gather_peaks).

The job of the rule script ``workflow/scripts/straightness_gather.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.io import open_artefact, write_artefact, write_table
from robomill.straightness.study import gather_gears, gather_peaks, gather_profiles


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    prof = gather_profiles([open_artefact(f) for f in inputs.runs],
                           [r["run"] for r in params.runs])
    write_artefact(prof, outputs.profiles, rule="straightness_gather",
                   inputs=inputs.runs, config_section=params.settings)
    write_table(gather_gears([pd.read_csv(f) for f in inputs.gears]),
                outputs.gears)
    peaks = gather_peaks([pd.read_csv(f, keep_default_na=False, na_values=[""])
                          for f in inputs.peaks], prof,
                         tol_bins=params.settings["class_tol_bins"])
    write_table(peaks, outputs.peaks)
    log.info("%d runs, %d peaks: %s", len(params.runs), len(peaks),
             peaks["mechanism"].value_counts().to_dict())
