"""The force accuracy each position tolerance needs: results/hexapod/force_accuracy.csv
(see robomill.hexapod.sensitivity.force_accuracy_requirement).

The job of the rule script ``workflow/scripts/hexapod_force_accuracy.py``."""

from __future__ import annotations

import logging

from robomill.hexapod.sensitivity import force_accuracy_requirement
from robomill.io import open_artefact


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    sens = open_artefact(inputs.sensitivity)
    force_N = float(open_artefact(inputs.forces)["vertical_force_N"][0, 0])
    table = force_accuracy_requirement(sens, force_N)
    table.to_csv(outputs[0], index=False)
    log.info("force accuracy for %d tolerances (worst actuator %d)", len(table),
             table["worst_actuator"].iloc[0])
