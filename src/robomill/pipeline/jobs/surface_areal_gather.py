"""Gather the areal scans: ISO 25178-2 parameters per scan with its instrument's statements,
the spectra, and stylus against scan for cuts measured both ways
(robomill.surface.areal_study.gather_areal).

The job of the rule script ``workflow/scripts/surface_areal_gather.py``."""

from __future__ import annotations

import logging

from robomill.io import open_artefact, write_artefact, write_table
from robomill.io.profiles import read_profile
from robomill.surface.areal_study import gather_areal
from robomill.surface.options import settings


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    opts = settings(params.settings)
    scans = [open_artefact(f) for f in inputs.scans]
    profiles = {c: read_profile(f)[:2] for c, f in zip(params.cuts, inputs.profiles, strict=True)}
    stylus = {c: open_artefact(f) for c, f in zip(params.stylus_cuts, inputs.stylus, strict=True)}
    out = gather_areal(scans, profiles, stylus, opts)
    write_table(out["areal"], outputs.areal)
    write_table(out["profile_vs_areal"], outputs.profile_vs_areal)
    write_artefact(out["spectra"], outputs.areal_spectra, rule="surface_areal_gather",
                   inputs=list(inputs.scans), config_section=opts)
    log.info("%d scans (Sq %s um); %d cuts measured both ways", len(out["areal"]),
             out["areal"]["Sq_um"].round(3).tolist(), len(stylus))
