"""The tracker runs of a study as one job: each run's stream read, checked against the study,
analysed (:func:`robomill.straightness.study.analyse_tracker_run`: re-ordered in space, its
spectrum, the gear frequencies and the gear-matched peaks) and written: the run's profile
dataset and its peaks and gears tables. A stream without a time base (manifest
``time_base: none``) is analysed in space only."""

from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

from robomill.experiment import cut_redundancy_deg
from robomill.io import write_artefact, write_table
from robomill.io.cell import read_cell
from robomill.io.tracker import read_tracker
from robomill.pipeline.jobs import path_list
from robomill.straightness.profile import TRIM_MAX_FRACTION, profile_dataset
from robomill.straightness.study import analyse_tracker_run
from robomill.study import load_study


def analyse_tracker_files(study: str, cell: str, runs: Sequence[Mapping[str, Any]],
                          raws: str | Sequence[str], out_nc: str | Sequence[str],
                          out_peaks: str | Sequence[str], out_gears: str | Sequence[str], *,
                          settings: Mapping[str, Any], cell_relpath: str,
                          log: logging.Logger, rule: str = "straightness_run") -> None:
    """Analyse each tracker run of ``runs`` (the workflow's run specs: ``run``, ``relpath``,
    ``direction``, ``feed_mm_s``, ``fs_hz``, ``time_base``, ``cut``), read from ``raws``, into
    ``out_nc``, ``out_peaks``, ``out_gears`` (same order; one path may be a string);
    ``study``: ``study.yaml``; ``cell``: the cell file (``cell_relpath``: its path in the raw
    folder, verified against its sha256; empty for the configuration's cell); ``settings``:
    the ``straightness`` section."""
    manifest = load_study(study)
    if cell_relpath:  # the raw folder's cell.yaml (else the configuration's cell, ingest_cell)
        manifest.verify_file(cell_relpath)
    the_cell = read_cell(cell)
    theta = {c.id: cut_redundancy_deg(c) for c in manifest.cuts}
    for run, raw, nc, peaks, gears in zip(runs, path_list(raws), path_list(out_nc),
                                          path_list(out_peaks), path_list(out_gears),
                                          strict=True):
        manifest.verify_file(run["relpath"])
        _analyse_run(run, raw, nc, peaks, gears, the_cell, theta.get(run["cut"], 0.0),
                     settings, log, rule)


def _analyse_run(run: Mapping[str, Any], raw: str, out_nc: str, out_peaks: str,
                 out_gears: str, cell: Any, theta_deg: float, opt: Mapping[str, Any],
                 log: logging.Logger, rule: str) -> None:
    """One run into its three outputs; ``theta_deg``: the tool's rotation about its axis
    while cutting the run's cut."""
    untimed = run["time_base"] == "none"
    t, points = read_tracker(raw, fs_hz=None if untimed else float(run["fs_hz"]),
                             spatial_only=untimed)
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
    meta: dict[str, Any] = {"direction": run["direction"], "feed_mm_s": float(run["feed_mm_s"]),
                            "cut": run["cut"]}
    if untimed:
        meta["time_base"] = "none"
    fmin = opt["fmin_cycles"] * spec.resolution_per_mm
    band = (spec.f_per_mm >= fmin) & (spec.f_per_mm <= opt["fmax_per_mm"])
    ds = profile_dataset(prof, spec, fmax_store_per_mm=opt["fmax_store_per_mm"],
                         attrs={**meta, "fmin_per_mm": fmin,
                                "floor_um2": float(np.median(spec.power_um2[band])),
                                "run": run["run"]})
    write_artefact(ds, out_nc, rule=rule, inputs=[raw], config_section=opt)
    # the run id, the one key joining the run's rows downstream, last (after the contract's
    # columns)
    write_table(pd.concat([pd.DataFrame([meta] * len(peaks)), peaks], axis=1)
                .assign(run=run["run"]), out_peaks)
    write_table(pd.concat([pd.DataFrame([meta] * len(gears)), gears], axis=1)
                .assign(run=run["run"]), out_gears)
    log.info("%s: %d samples, L = %.2f mm, v = %.3f mm/s, %d peaks (%d gear-matched)",
             run["run"], t.size, prof.length_mm, prof.speed_mm_s, len(peaks),
             int(peaks["joint"].notna().sum()))
