"""Ours beside the parameters a profile file states about itself (one row per parameter; see
robomill.surface.reference.reference_comparison).

The job of the rule script ``workflow/scripts/surface_reference.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.io import write_table
from robomill.io.profiles import read_profile
from robomill.study import load_study
from robomill.surface.options import settings
from robomill.surface.reference import REFERENCE_COLUMNS, reference_comparison


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    opts = settings(params.settings)
    study = load_study(inputs.study)
    tables = []
    for cut, relpath, reference in zip(params.cuts, params.relpath, params.reference, strict=True):
        x, z, _ = read_profile(study.verify_file(relpath))
        tables.append(reference_comparison(x, z, reference, lambda_c_mm=opts["lambda_c_mm"],
                                           rtol=opts["reference_rtol"], cut=cut))
    table = (pd.concat(tables, ignore_index=True) if tables
             else pd.DataFrame(columns=REFERENCE_COLUMNS))
    write_table(table, outputs[0])
    log.info("%d parameters of %d files; %d within %g of the file's own", len(table), len(tables),
             int(table["within_tolerance"].sum()), opts["reference_rtol"])
