"""Each prediction of the plan (and of the study's own cuts) beside the outcome measured or
simulated under the same cut id (issue 28: closing the loop)."""

import pandas as pd
import xarray as xr

from robomill.io import write_table
from robomill.pipeline.runlog import setup
from robomill.plan.check import (
    RunOutcomes,
    check_summary,
    check_table,
    summary_table,
    waviness_min_cycles,
)

log = setup(snakemake.log[0], "plan")
inp = snakemake.input


def table(name):
    return pd.read_csv(inp[name]) if name in inp.keys() else None


def dataset(name):
    return xr.load_dataset(inp[name]) if name in inp.keys() else None


# the planned cuts' own run (results/plan/next/run), once it has run
planned_run = RunOutcomes(snakemake.params.next_run, mean_forces=table("next_mean_forces"),
                          force_peaks=table("next_force_peaks"),
                          run_gears=table("next_gears"), profiles=dataset("next_profiles"))
predicted = pd.concat([pd.read_csv(inp.plan), pd.read_csv(inp.study)], ignore_index=True)
table = check_table(
    predicted,
    mean_forces=table("mean_forces"),
    peaks=table("peaks"),
    tolerance=float(snakemake.params.tolerance),
    simulated=table("simulated"),
    force_peaks=table("force_peaks"),
    chatter_fraction_of_mean=float(snakemake.params.chatter_fraction_of_mean),
    planned_run=planned_run,
    run_gears=table("gears"),
    profiles=dataset("profiles"),
    waviness_min_cycles=waviness_min_cycles(
        snakemake.params.fmin_cycles,
        float(snakemake.params.waviness_noise["exclude_bins"])))
write_table(table, snakemake.output.check)
summary = check_summary(table, float(snakemake.params.tolerance))
write_table(summary_table(summary), snakemake.output.summary)
log.info("%s", table.groupby("quantity")[["within_interval", "within_tolerance"]].mean()
         .to_string() if len(table) else "no outcomes")
