"""One areal scan: form removal, ISO 25178-2 height parameters, areal PSD (radial, along and
across the feed) and the profile along the feed (robomill.surface.areal.analyse_scan).
The job: robomill.pipeline.jobs.surface_areal."""

from robomill.pipeline.jobs import surface_areal
from robomill.pipeline.runlog import setup

surface_areal.run(snakemake.input, snakemake.output, snakemake.params,
                  log=setup(snakemake.log[0], "surface_areal"))
