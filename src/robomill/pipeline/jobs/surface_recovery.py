"""Synthetic runs: planted (truth.nc) vs recovered waviness and roughness RMS of every cut.

The job of the rule script ``workflow/scripts/surface_recovery.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.io import open_artefact, write_table
from robomill.surface.recovery import recovery_table


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    df = recovery_table(pd.read_csv(inputs.metrics), open_artefact(inputs.truth))
    write_table(df, outputs[0])
    worst = max((df["waviness_ratio"] - 1).abs().max(), (df["roughness_ratio"] - 1).abs().max())
    log.info("%d cuts; worst relative error of recovered RMS %.1f %%", len(df), 100 * worst)
