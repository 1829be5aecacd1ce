"""Gather the sensitivity shards into results/hexapod/sensitivity.nc."""

from robomill.hexapod.sensitivity import gather_sensitivity
from robomill.io import open_artefact, write_artefact
from robomill.pipeline.runlog import setup

log = setup(snakemake.log[0], "hexapod")
ds = gather_sensitivity([open_artefact(p) for p in snakemake.input.shards])
write_artefact(ds, snakemake.output[0], rule=snakemake.rule, inputs=snakemake.input.shards,
               config_section=snakemake.params.hexapod)
log.info("sensitivity map %s", dict(ds["drift_mm"].sizes))
