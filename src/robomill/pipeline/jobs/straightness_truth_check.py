"""Synthetic runs: every planted gear element vs the attributions (results/straightness/;
see robomill.straightness.truth_check).

The job of the rule script ``workflow/scripts/straightness_truth_check.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.io import open_artefact, write_table
from robomill.straightness.truth import attribution_counts, truth_check


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    if not inputs.truth:  # real data: no planted truth
        table = truth_check(None, None, None, params.settings)
        log.info("no truth (real data): empty table")
    else:
        table = truth_check(
            pd.read_csv(inputs.peaks, keep_default_na=False, na_values=[""]),
            open_artefact(inputs.truth[0]), open_artefact(inputs.profiles),
            params.settings)
        log.info("attribution vs truth: %s", attribution_counts(table))
    write_table(table, outputs[0])
