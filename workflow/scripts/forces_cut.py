"""Analyse force records in chunks: mean forces, Welch PSD, low-band thesis power, peaks
(robomill.forces). One cut, or every cut of the virtual cell in one job: ``params.cut`` and
the outputs in the same order.
The job: robomill.pipeline.jobs.forces_cut."""

from robomill.pipeline.jobs import forces_cut
from robomill.pipeline.runlog import setup

forces_cut.run(snakemake.input, snakemake.output, snakemake.params,
               log=setup(snakemake.log[0], "forces_cut"))
