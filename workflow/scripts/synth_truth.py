"""Write the virtual cell's planted truth (results/synthetic/truth.nc)."""

from robomill.io import write_artefact
from robomill.pipeline.runlog import setup
from robomill.synth.truth import cell_truth

log = setup(snakemake.log[0], "synth_truth")
cfg = dict(snakemake.params.cfg)  # cell (facts) + synth (planted truth) + experiment
ds = cell_truth(cfg)
write_artefact(ds, snakemake.output[0], rule="synth_truth", config_section=cfg)
log.info("wrote %s with %d variables", snakemake.output[0], len(ds.data_vars))
