"""Rybak n.d.: the programme's inverse dynamics and replay, and the vertical move with a force
error → trajectory.nc and forces.nc.

The job of the rule script ``workflow/scripts/hexapod_dynamics.py``."""

from __future__ import annotations

import logging

from robomill.hexapod.study import dynamics_datasets
from robomill.io import write_artefact


def run(inputs, outputs, params, *, log: logging.Logger, rule) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    section = params.hexapod
    traj, forces = dynamics_datasets(section)
    write_artefact(traj, outputs.trajectory, rule=rule, config_section=section)
    write_artefact(forces, outputs.forces, rule=rule, config_section=section)
    log.info("vertical move final drift %s mm, replay holds %.3f s",
             traj["vertical_final_drift_mm"].values.round(4), float(traj["replay_hold_s"]))
