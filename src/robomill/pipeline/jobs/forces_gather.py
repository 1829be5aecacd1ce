"""Gather the per-cut force analyses: spectra.nc, peaks.csv, mean forces, harmonics and the
identified cutting coefficients (robomill.forces.study.gather_force_study).

The job of the rule script ``workflow/scripts/forces_gather.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.experiment import cut_process, is_thesis_design
from robomill.forces.coefficients import (
    identification_status,
    not_identified_sentence,
)
from robomill.forces.study import force_record_chatter, gather_force_study
from robomill.io import open_artefact, write_artefact, write_table
from robomill.study import load_study


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    s = params.settings
    manifest = load_study(inputs.study)
    exp = manifest.experiment
    datasets = [open_artefact(p) for p in inputs.cuts]
    # a design other than the thesis': each cut's own speed, flutes, immersion and milling mode
    processes = (None if is_thesis_design(manifest.cuts)
                 else {c.id: cut_process(c, exp) for c in manifest.cuts})
    chattered = force_record_chatter(pd.read_csv(inputs.verdicts))
    if chattered:
        log.info("left out of the coefficients (judged to chatter, %s): %s",
                 inputs.verdicts, ", ".join(chattered))
    spectra, peaks, means, harmonics, coeffs = gather_force_study(
        datasets, flutes=int(exp["flutes"]), confidence=float(s["confidence"]),
        processes=processes, chattered=chattered)
    kept = sorted(set(chattered) & set(means.loc[means["in_fit"], "cut"].astype(str)))
    if kept:
        log.warning("cuts judged to chatter kept in the coefficients' identification (without "
                    "them the other cuts identify nothing): %s", ", ".join(kept))
    write_artefact(spectra, outputs.spectra, rule="forces_gather", inputs=inputs.cuts,
                   config_section=s)
    write_table(peaks, outputs.peaks)
    write_table(coeffs, outputs.coefficients)
    write_table(means, outputs.means)
    write_table(harmonics, outputs.harmonics)
    why = identification_status(coeffs)
    if why is not None:  # a legitimate design: everything else is written as always
        log.warning("cutting coefficients %s: written as NaN (%s)",
                    not_identified_sentence(why), outputs.coefficients)
    else:
        log.info("coefficients:\n%s", coeffs.to_string(index=False))
    suspect = coeffs.loc[~coeffs["physical"], "name"].tolist()
    if suspect and why is None:
        log.warning("coefficients that cannot be physical (negative, or a fit residual larger "
                    "than the signal): %s", ", ".join(suspect))
