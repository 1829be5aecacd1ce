"""Tracker runs: validate, re-order in space, spectrum, gear frequencies, gear-matched peaks
(a stream without a time base, manifest time_base: none, in space only). One run, or every run
of the virtual cell in one job: ``params.runs`` and the outputs in the same order."""

import numpy as np
import pandas as pd

from robomill.experiment import cut_redundancy_deg
from robomill.io import write_artefact, write_table
from robomill.io.cell import read_cell
from robomill.io.tracker import read_tracker
from robomill.pipeline.runlog import setup
from robomill.straightness.profile import TRIM_MAX_FRACTION, profile_dataset
from robomill.straightness.study import analyse_tracker_run
from robomill.study import load_study


def items(paths):
    """A rule's output or input as a list (one path is a string)."""
    return [paths] if isinstance(paths, str) else list(paths)


def analyse_run(run, raw, out_nc, out_peaks, out_gears):
    """Analyse one run (``run``: :func:`tracker_run_spec` of the rule file) into its outputs."""
    manifest.verify_file(run["relpath"])
    # a stream without a time base (time_base: none, --spatial-only): analysed in space only
    untimed = run["time_base"] == "none"
    t, points = read_tracker(raw, fs_hz=None if untimed else float(run["fs_hz"]),
                             spatial_only=untimed)
    # the tool's rotation about its axis while cutting the run's cut (the manifest's cut key)
    theta_deg = next((cut_redundancy_deg(c) for c in manifest.cuts if c.id == run["cut"]), 0.0)
    prof, spec, gears, peaks = analyse_tracker_run(
        None if untimed else t, points, cell, data_file=raw,
        redundancy_deg=theta_deg, ds_mm=opt["ds_mm"],
        trim_mm=opt["trim_mm"], nfft=opt["nfft"], fmin_cycles=opt["fmin_cycles"],
        fmax_per_mm=opt["fmax_per_mm"], threshold=opt["threshold"], n_peaks=opt["n_peaks"],
        tol_bins=opt["tol_bins"], detrend_order=opt["detrend_order"],
        merge_bins=opt["merge_bins"], local_prominence_ratio=opt["local_prominence_ratio"],
        local_floor_halfwidth_bins=opt["local_floor_halfwidth_bins"])
    if prof.trim_mm < opt["trim_mm"]:
        log.warning("%s: path of %.3g mm: trimmed %.3g mm at each end instead of "
                    "straightness.trim_mm %g mm (at most %g %% of the path)", run["run"],
                    prof.length_mm + 2 * prof.trim_mm, prof.trim_mm, opt["trim_mm"],
                    100 * TRIM_MAX_FRACTION)
    meta = {"direction": run["direction"], "feed_mm_s": float(run["feed_mm_s"]),
            "cut": run["cut"]}
    if untimed:
        meta["time_base"] = "none"
    fmin = opt["fmin_cycles"] * spec.resolution_per_mm
    band = (spec.f_per_mm >= fmin) & (spec.f_per_mm <= opt["fmax_per_mm"])
    ds = profile_dataset(prof, spec, fmax_store_per_mm=opt["fmax_store_per_mm"],
                         attrs={**meta, "fmin_per_mm": fmin,
                                "floor_um2": float(np.median(spec.power_um2[band])),
                                "run": run["run"]})
    write_artefact(ds, out_nc, rule="straightness_run", inputs=[raw], config_section=opt)
    # the run id, the one key joining the run's rows downstream, last (after the contract's
    # columns)
    write_table(pd.concat([pd.DataFrame([meta] * len(peaks)), peaks], axis=1)
                .assign(run=run["run"]), out_peaks)
    write_table(pd.concat([pd.DataFrame([meta] * len(gears)), gears], axis=1)
                .assign(run=run["run"]), out_gears)
    log.info("%s: %d samples, L = %.2f mm, v = %.3f mm/s, %d peaks (%d gear-matched)",
             run["run"], t.size, prof.length_mm, prof.speed_mm_s, len(peaks),
             int(peaks["joint"].notna().sum()))


log = setup(snakemake.log[0], "straightness_run")
p = snakemake.params
opt = p.settings
manifest = load_study(snakemake.input.study)
if p.cell_relpath:  # the raw folder's cell.yaml (else the configuration's cell, ingest_cell)
    manifest.verify_file(p.cell_relpath)
cell = read_cell(snakemake.input.cell)
out = snakemake.output
for args in zip(p.runs, items(snakemake.input.raw), items(out.nc), items(out.peaks),
                items(out.gears), strict=True):
    analyse_run(*args)
