"""Analyse stylus profiles: detrend, Gaussian split, spectra, segment RMS, peaks (one cut, or
every cut of the virtual cell in one job: ``params.cut`` and the outputs in the same order).
A cut with an areal scan and no stylus profile is analysed from the scan's profile along the
feed.
The job: robomill.pipeline.jobs.surface_profile."""

from robomill.pipeline.jobs import surface_profile
from robomill.pipeline.runlog import setup

surface_profile.run(snakemake.input, snakemake.output, snakemake.params,
                    log=setup(snakemake.log[0], "surface_profile"))
