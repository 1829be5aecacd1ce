"""One configured lobe case -> results/chatter/cases/<name>.nc (ZOA and converged SEM).

The job of the rule script ``workflow/scripts/chatter_case.py``."""

from __future__ import annotations

import logging

from robomill.chatter.cases import run_case
from robomill.io import write_artefact
from robomill.pipeline.runlog import Progress


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    case = dict(params.case)
    progress = Progress(log, 1.0, f"lobe map {case['name']}")
    ds = run_case(case, accuracy=params.accuracy, depth_max_m=params.depth_max_mm * 1e-3,
                  progress=progress.update)
    write_artefact(ds, outputs.nc, rule="chatter_case",
                   config_section={"case": case, "accuracy": params.accuracy})
    progress.finish(f"case {case['name']}: {ds.sizes['spindle_rpm']} speeds, min a_crit zoa "
                    f"{float(ds.a_crit_mm.sel(solver='zoa').min()):.3f} mm, sem "
                    f"{float(ds.a_crit_mm.sel(solver='sem').min()):.3f} mm, worst error "
                    f"{100 * ds.attrs['worst_relative_error']:.3f} %")
