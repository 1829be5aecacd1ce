"""One areal scan: form removal, ISO 25178-2 height parameters, areal PSD (radial, along and
across the feed) and the profile along the feed (robomill.surface.areal.analyse_scan).

The job of the rule script ``workflow/scripts/surface_areal.py``."""

from __future__ import annotations

import logging

import numpy as np
import pandas as pd

from robomill.io import write_artefact, write_table
from robomill.io.areal import read_areal
from robomill.study import load_study
from robomill.surface.areal import analyse_scan
from robomill.surface.options import settings


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    opts = settings(params.settings)
    study = load_study(inputs.study)
    path = study.verify_file(params.relpath)
    z, dx, dy, attrs = read_areal(path)
    ds, (x, zp) = analyse_scan(z, dx, dy, float(params.entry["feed_angle_deg"]), opts)
    # the instrument's statements (file and manifest entry) carried into the artefact
    keep = ("instrument", "probe", "lateral_spacing_um", "lateral_resolution_um", "source_file",
            "source_format")
    ds.attrs.update({k: (str(v) if isinstance(v, list) else v) for k, v in
                     {**attrs, **{k: params.entry[k] for k in keep if k in params.entry}}.items()})
    ds.attrs["cut"] = params.entry["cut"]
    write_artefact(ds, outputs.nc, rule="surface_areal", inputs=[str(path)],
                   config_section=opts)
    write_table(pd.DataFrame({"x_mm": np.round(x, 9), "z_um": zp}), outputs.profile)
    log.info("%s: %d x %d points, valid %.1f %%; Sq %.4g um (form degree %d); profile along the "
             "feed: line %d, %d points", params.entry["cut"], z.shape[1], z.shape[0],
             100 * float(ds["valid_share"]), float(ds["Sq_um"]), int(opts["areal_form_degree"]),
             int(ds["profile_line"]), x.size)
