"""Synthetic runs: every planted gear element vs the attributions (results/straightness/)."""

import pandas as pd

from robomill.io import open_artefact, write_table
from robomill.runlog import setup
from robomill.straightness import attribution_counts, evaluate_attribution

log = setup(snakemake.log[0], "straightness_truth_check")
opt = snakemake.params.settings
columns = ["direction", "feed_mm_s", "joint", "stage", "order", "f_spatial_per_mm",
           "amplitude_um", "snr_expected", "class", "found", "merged", "found_amplitude_um",
           "false_attribution"]
if not snakemake.input.truth:  # real data: no planted truth
    write_table(pd.DataFrame(columns=columns), snakemake.output[0])
    log.info("no truth (real data): empty table")
else:
    truth = open_artefact(snakemake.input.truth[0])
    prof = open_artefact(snakemake.input.profiles)
    peaks = pd.read_csv(snakemake.input.peaks, keep_default_na=False, na_values=[""])
    peaks[["stage", "order"]] = peaks[["stage", "order"]].fillna("")
    rows = []
    for k, run in enumerate(truth["tracker_run"].values):
        for g in truth["gear"].values:
            for o in truth["order"].values:
                rows.append({
                    "run": str(run), "direction": str(truth["tracker_direction"].values[k]),
                    "feed_mm_s": float(truth["tracker_feed_mm_s"].values[k]),
                    "joint": int(truth["gear_joint"].sel(gear=g)),
                    "stage": str(truth["gear_stage"].sel(gear=g).values), "order": str(o),
                    "f_spatial_per_mm": float(truth["tracker_gear_f_spatial_per_mm"].sel(
                        tracker_run=run, gear=g, order=o)),
                    "amplitude_um": float(truth["tracker_gear_amplitude_um"].sel(
                        tracker_run=run, gear=g, order=o))})
    planted = pd.DataFrame(rows)
    runs = pd.DataFrame({k: prof[k].values for k in ("direction", "feed_mm_s",
                                                      "resolution_per_mm", "fmin_per_mm",
                                                      "floor_um2")})
    ev = evaluate_attribution(peaks, planted, runs, threshold=opt["threshold"],
                              tol_bins=opt["tol_bins"], fmax_per_mm=opt["fmax_per_mm"])
    write_table(ev[columns], snakemake.output[0])
    log.info("attribution vs truth: %s", attribution_counts(ev))
