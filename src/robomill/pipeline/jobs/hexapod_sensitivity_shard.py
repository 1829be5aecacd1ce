"""One shard of the sensitivity study: one actuator in error, every error size.

The job of the rule script ``workflow/scripts/hexapod_sensitivity_shard.py``."""

from __future__ import annotations

import logging

from robomill.hexapod.study import sensitivity_shard
from robomill.io import write_artefact
from robomill.pipeline.runlog import Progress


def run(inputs, outputs, params, *, log: logging.Logger, rule) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    section = params.hexapod
    progress = Progress(log, 1.0, f"sensitivity of actuator {params.actuator}")
    ds = sensitivity_shard(section, int(params.actuator), progress=progress.update)
    write_artefact(ds, outputs[0], rule=rule, config_section=section)
    progress.finish(f"actuator {params.actuator}: {ds.sizes['force_error_pct']} force "
                    f"errors, drift {ds['drift_mm'].values.round(4).tolist()} mm")
