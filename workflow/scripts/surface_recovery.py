"""Synthetic runs: planted (truth.nc) vs recovered waviness and roughness RMS of every cut."""

import pandas as pd

from robomill.io import open_artefact, write_table
from robomill.pipeline.runlog import setup
from robomill.surface.recovery import recovery_table

log = setup(snakemake.log[0], "surface_recovery")
df = recovery_table(pd.read_csv(snakemake.input.metrics), open_artefact(snakemake.input.truth))
write_table(df, snakemake.output[0])
worst = max((df["waviness_ratio"] - 1).abs().max(), (df["roughness_ratio"] - 1).abs().max())
log.info("%d cuts; worst relative error of recovered RMS %.1f %%", len(df), 100 * worst)
