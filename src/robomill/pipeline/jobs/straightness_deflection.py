"""The static deflection of each cut with an air tracker pass: the loaded pass along its path
minus the air pass along the same path (robomill.straightness.deflection) ->
results/straightness/deflection.csv.

The job of the rule script ``workflow/scripts/straightness_deflection.py``."""

from __future__ import annotations

import logging

import numpy as np

from robomill.io import write_table
from robomill.io.tracker import read_tracker
from robomill.straightness.deflection import deflection_table, pass_deflection_um
from robomill.study import load_study


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    opt = params.settings
    manifest = load_study(inputs.study)
    raw = dict(zip([s["run"] for s in params.specs], inputs.raw, strict=True))
    specs = {s["run"]: s for s in params.specs}

    def read(run):
        """One pass' times (None without a time base) and positions, its file verified."""
        spec = specs[run]
        manifest.verify_file(spec["relpath"])
        untimed = spec["time_base"] == "none"
        t, points = read_tracker(raw[run], fs_hz=None if untimed else float(spec["fs_hz"]),
                                 spatial_only=untimed)
        return (None if untimed else t), points

    rows = []
    for pair in params.pairs:
        row = {**pair, "deflection_normal_um": np.nan, "deflection_axial_um": np.nan,
               "stderr_normal_um": np.nan, "stderr_axial_um": np.nan, "length_mm": np.nan}
        if not pair["loaded_run"]:
            log.warning("air pass %s of cut %s: the cut has no loaded tracker pass (no deflection)",
                        pair["air_run"], pair["cut"])
            rows.append(row)
            continue
        _, loaded = read(pair["loaded_run"])
        t_air, air = read(pair["air_run"])
        try:
            row.update(pass_deflection_um(loaded, air, ds_mm=opt["ds_mm"], trim_mm=opt["trim_mm"],
                                          t_air_s=t_air))
        except ValueError as err:
            log.warning("cut %s (%s - %s): %s", pair["cut"], pair["loaded_run"], pair["air_run"],
                        err)
        rows.append(row)
        log.info("cut %s: loaded %s - air %s: %.3g um normal, %.3g um axial over %.3g mm",
                 pair["cut"], pair["loaded_run"], pair["air_run"], row["deflection_normal_um"],
                 row["deflection_axial_um"], row["length_mm"])
    write_table(deflection_table(rows), outputs.deflection)
