"""Each prediction of the plan (and of the study's own cuts) beside the outcome measured or
simulated under the same cut id (issue 28: closing the loop)."""

import pandas as pd

from robomill.io import write_table
from robomill.pipeline.runlog import setup
from robomill.plan.check import check_summary, check_table, summary_table

log = setup(snakemake.log[0], "plan")
inp = snakemake.input
predicted = pd.concat([pd.read_csv(inp.plan), pd.read_csv(inp.study)], ignore_index=True)
table = check_table(
    predicted,
    mean_forces=pd.read_csv(inp.mean_forces) if "mean_forces" in inp.keys() else None,
    peaks=pd.read_csv(inp.peaks) if "peaks" in inp.keys() else None,
    tolerance=float(snakemake.params.tolerance),
    simulated=pd.read_csv(inp.simulated) if "simulated" in inp.keys() else None,
    force_peaks=pd.read_csv(inp.force_peaks) if "force_peaks" in inp.keys() else None,
    chatter_fraction_of_mean=float(snakemake.params.chatter_fraction_of_mean))
write_table(table, snakemake.output.check)
summary = check_summary(table, float(snakemake.params.tolerance))
write_table(summary_table(summary), snakemake.output.summary)
log.info("%s", table.groupby("quantity")[["within_interval", "within_tolerance"]].mean()
         .to_string() if len(table) else "no outcomes")
