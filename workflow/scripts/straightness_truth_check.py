"""Synthetic runs: every planted gear element vs the attributions (results/straightness/;
see robomill.straightness.truth_check)."""

import pandas as pd

from robomill.io import open_artefact, write_table
from robomill.pipeline.runlog import setup
from robomill.straightness.truth import attribution_counts, truth_check

log = setup(snakemake.log[0], "straightness_truth_check")
if not snakemake.input.truth:  # real data: no planted truth
    table = truth_check(None, None, None, snakemake.params.settings)
    log.info("no truth (real data): empty table")
else:
    table = truth_check(
        pd.read_csv(snakemake.input.peaks, keep_default_na=False, na_values=[""]),
        open_artefact(snakemake.input.truth[0]), open_artefact(snakemake.input.profiles),
        snakemake.params.settings)
    log.info("attribution vs truth: %s", attribution_counts(table))
write_table(table, snakemake.output[0])
