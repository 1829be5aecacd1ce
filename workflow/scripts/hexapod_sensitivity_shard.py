"""One shard of the sensitivity study: one actuator in error, every error size."""

from robomill.hexapod import sensitivity_shard
from robomill.io import write_artefact
from robomill.runlog import setup

log = setup(snakemake.log[0], "hexapod")
section = snakemake.params.hexapod
ds = sensitivity_shard(section, int(snakemake.params.actuator))
write_artefact(ds, snakemake.output[0], rule=snakemake.rule, config_section=section)
log.info("actuator %s: drift %s mm", snakemake.params.actuator, ds["drift_mm"].values.round(4))
