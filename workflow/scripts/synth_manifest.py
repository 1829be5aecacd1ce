"""Write the synthetic study's manifest.yaml (sha256 of every simulated raw file).
The job: robomill.synth.jobs.synth_manifest."""

from robomill.pipeline.runlog import setup
from robomill.synth.jobs import synth_manifest

synth_manifest.run(snakemake.input, snakemake.output, snakemake.params,
                   log=setup(snakemake.log[0], "synth_manifest"))
