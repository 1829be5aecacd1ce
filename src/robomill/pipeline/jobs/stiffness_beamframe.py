"""Cai 2015 beam-frame model: precessing pneumatic wheel, δ_sum(t) and σ(t).

The job of the rule script ``workflow/scripts/stiffness_beamframe.py``."""

from __future__ import annotations

import logging

from robomill.beamframe import precession_dataset, sections_from_config
from robomill.io import write_artefact
from robomill.kinematics import robot_from_mapping


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    bf = params.beamframe
    robot = robot_from_mapping(bf["robot"])
    sections = sections_from_config(bf["sections"], bf["E_Pa"], bf["G_Pa"])
    ds = precession_dataset(robot, sections, q_seed_deg=bf["q_seed_deg"], wheel=bf["wheel"],
                            duration_s=bf["duration_s"], dt_s=bf["dt_s"], sigma=bf["sigma"])
    log.info("%d elements, K %s, delta_sum %.3g..%.3g um", ds.sizes["element"], ds["K0"].shape,
             float(ds["delta_sum_um"].min()), float(ds["delta_sum_um"].max()))
    write_artefact(ds, outputs.beamframe, rule="stiffness_beamframe", config_section=bf)
