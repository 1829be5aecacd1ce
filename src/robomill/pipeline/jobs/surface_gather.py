"""Gather the per-cut analyses: Tables 2.1/2.2, thesis comparison, peaks with mechanism,
metrics, spectra and profiles of every cut (see robomill.surface.gather_surface).

The job of the rule script ``workflow/scripts/surface_gather.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.experiment import cut_process, is_thesis_design
from robomill.io import open_artefact, write_artefact, write_table
from robomill.study import load_study
from robomill.surface.options import settings
from robomill.surface.study import gather_surface


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    opts = settings(params.settings)
    cuts = pd.DataFrame(params.cuts).rename(columns={"id": "cut"})
    manifest = load_study(inputs.study)
    plan = [manifest.cut(c) for c in cuts["cut"]]
    # a design other than the thesis': each cut's own speed, flutes, feed per tooth, direction
    processes = (None if is_thesis_design(plan)
                 else {c.id: cut_process(c, manifest.experiment) for c in plan})
    out = gather_surface([open_artefact(f) for f in inputs.cuts], cuts,
                         [pd.read_csv(f) for f in inputs.peaks], opts,
                         processes=processes)
    write_table(out["metrics"], outputs.metrics)
    if processes is None:
        write_table(out["waviness"], outputs.waviness, index=True)
        write_table(out["roughness"], outputs.roughness, index=True)
        write_table(out["comparison"], outputs.comparison)
    else:
        write_table(out["by_design"], outputs.by_design)
    write_table(out["peaks"], outputs.peaks)
    for name in ("spectra", "profiles"):
        write_artefact(out[name], outputs[name], rule="surface_gather",
                       inputs=inputs.cuts, config_section=opts)
    peaks = out["peaks"]
    if processes is None:
        comparison = out["comparison"]
        log.info("%d cuts; %d of %d table cells within a factor 1.5 of the thesis; %d peaks (%s)",
                 len(out["metrics"]), int(comparison["within_1.5x"].sum()), len(comparison),
                 len(peaks), peaks["mechanism"].value_counts().to_dict())
    else:
        log.info("%d cuts of a free design (metrics_by_design.csv); %d peaks (%s)",
                 len(out["metrics"]), len(peaks), peaks["mechanism"].value_counts().to_dict())
