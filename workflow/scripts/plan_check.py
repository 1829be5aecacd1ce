"""Each prediction of the plan (and of the study's own cuts) beside the outcome its run's files
recorded under the same cut id: the planned cuts' from their own run (results/plan/next/run),
the study's from the study (in-sample)."""

import pandas as pd
import xarray as xr

from robomill.errors import RawDataError
from robomill.io import write_table
from robomill.pipeline.runlog import setup
from robomill.plan.check import (
    RunOutcomes,
    check_summary,
    check_table,
    summary_table,
    waviness_min_cycles,
)
from robomill.plan.evidence import identified_cuts, read_verdicts
from robomill.plan.misses import explain_misses

log = setup(snakemake.log[0], "plan")
inp, p = snakemake.input, snakemake.params


def table(name):
    return pd.read_csv(inp[name]) if name in inp.keys() else None


def dataset(name):
    return xr.load_dataset(inp[name]) if name in inp.keys() else None


def verdicts(name):
    """A run's chatter verdicts; one line in the log and none where the file breaks its
    contract (the other outcomes are still checked)."""
    if name not in inp.keys():
        return None
    try:
        return read_verdicts(inp[name])
    except RawDataError as err:
        log.warning("%s (stability from its force spectrum instead)", err)
        return None


# the planned cuts' own run (results/plan/next/run), once it has run
planned_run = RunOutcomes(p.next_run, mean_forces=table("next_mean_forces"),
                          force_peaks=table("next_force_peaks"),
                          verdicts=verdicts("next_verdicts"),
                          run_gears=table("next_gears"), profiles=dataset("next_profiles"),
                          deflection=table("next_deflection"))
study_run = RunOutcomes("", mean_forces=table("mean_forces"), force_peaks=table("force_peaks"),
                        verdicts=verdicts("verdicts"), run_gears=table("gears"),
                        profiles=dataset("profiles"), deflection=table("deflection"))
study = pd.read_csv(inp.study)
predicted = pd.concat([pd.read_csv(inp.plan), study], ignore_index=True)
tolerance = float(p.tolerance)
# in-sample: the study's cuts (they identified the models) and the cuts whose verdicts
# conditioned the stability limit (results/plan/evidence_used.csv)
identified = identified_cuts(study["cut"], pd.read_csv(inp.evidence))
table = check_table(
    predicted, study=study_run, planned_run=planned_run, peaks=table("peaks"),
    identified_cuts=identified, tolerance=tolerance,
    chatter_fraction_of_mean=float(p.chatter_fraction_of_mean),
    waviness_min_cycles=waviness_min_cycles(
        p.fmin_cycles, float(p.waviness_noise["exclude_bins"])))
write_table(table, snakemake.output.check)
summary = check_summary(table, tolerance, float(p.nominal_coverage))
write_table(summary_table(summary), snakemake.output.summary)
with xr.open_dataset(inp.candidates) as cand:
    band = cand.attrs.get("modal_band_hz")
band = tuple(float(b) for b in band) if band is not None and len(band) == 2 else None
write_table(explain_misses(table, pd.read_csv(inp.plan), planned_run.verdicts, band),
            snakemake.output.misses)
log.info("%s", table.groupby(["in_sample", "quantity"])["held"].agg(["size", "sum"])
         .to_string() if len(table) else "no outcomes")
