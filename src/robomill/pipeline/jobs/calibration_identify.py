"""Identify the calibrated model from the C-Track tables (thesis ch. 1).

The job of the rule script ``workflow/scripts/calibration_identify.py``."""

from __future__ import annotations

import logging

import numpy as np

from robomill.calibration.dataset import circle_table, joint_error_table, model_to_dataset
from robomill.calibration.gravity import mass_model_from_cell
from robomill.calibration.identification import GRAVITY_NONE, identify
from robomill.io import write_artefact, write_table
from robomill.io.cell import read_cell
from robomill.io.ctrack import READERS
from robomill.study import load_study


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    manifest = load_study(inputs.study)
    tables = {}
    for name, relpath in params.relpaths.items():
        manifest.verify_file(relpath)
        tables[name] = READERS[name](inputs[name])
    if params.cell_relpath:
        manifest.verify_file(params.cell_relpath)
    c = dict(params.calibration)
    # Fourier orders of the joint errors: the cell's gear trains (r and r·z of every element),
    # unless the configuration lists them explicitly
    em = dict(c["error_model"])
    cell = read_cell(inputs.cell)
    if em.get("orders") is None:
        em["orders"] = cell.fourier_orders()
    c["error_model"] = em
    # the gravity model: the cell's mass model (manufacturer data / CAD), if it states one
    masses = mass_model_from_cell(cell)
    if masses is None:
        log.warning("%s states no mass_model: gravity model %s", inputs.cell, GRAVITY_NONE)
    ident = identify(
        tables["circles"], tables["home"], tables["steps"], tables["loads"], tables["base"],
        masses=masses,
        fixture_offset_mm=np.asarray(c["fixture_offset_mm"], float),
        orders={i + 1: o for i, o in enumerate(em["orders"])},
        max_degree=int(em["max_degree"]), holdout_every=int(em["holdout_every"]),
        iterations=int(c["iterations"]),
    )
    read = [inputs[k] for k in params.relpaths] + [inputs.cell]
    write_artefact(model_to_dataset(ident), outputs.model, rule="calibration_identify",
                   inputs=read, config_section=c)
    write_table(joint_error_table(ident, int(em["holdout_every"])), outputs.joint_errors)
    write_table(ident.base, outputs.base)
    write_table(circle_table(tables["circles"], ident), outputs.circles)
    log.info("compliance %s rad/Nm; base %.3g rad/Nm (R2 %.3f)", ident.model.compliance,
             ident.base_compliance, ident.base_r2)
