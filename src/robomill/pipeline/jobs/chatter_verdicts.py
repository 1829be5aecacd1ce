"""Chatter verdicts of every cut's force record and every sound/vibration recording
(robomill.chatter.recordings), their chatter lines tested on the cuts' air passes:
results/chatter/verdicts.csv and the pooled spectrograms.

The job of the rule script ``workflow/scripts/chatter_verdicts.py``."""

from __future__ import annotations

import logging

from robomill.chatter.recordings import (
    JUDGED_KINDS,
    is_air_pass,
    judge_study,
    verdict_findings,
)
from robomill.chatter.verdicts import VerdictSettings
from robomill.findings import write_findings
from robomill.io import write_artefact
from robomill.io.artefacts import write_table
from robomill.study import load_study


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    manifest = load_study(inputs.study)
    settings = VerdictSettings.from_mapping(params.settings)
    entries = [f for f in manifest.files if f["kind"] in JUDGED_KINDS]
    table, spectrograms = judge_study(manifest, entries, settings, log=log)
    write_table(table, outputs.verdicts)
    spectrograms.attrs["energy_ratio_threshold"] = settings.energy_ratio_threshold
    write_artefact(spectrograms, outputs.spectrograms, rule="chatter_verdicts",
                   inputs=list(inputs.raw), config_section=params.settings)
    counts = table["verdict"].value_counts().to_dict() if len(table) else {}
    log.info("%d records judged: %s", len(table), counts)
    n_air = sum(is_air_pass(e) for e in entries)
    write_findings(verdict_findings(table, settings, n_air), outputs.findings)
