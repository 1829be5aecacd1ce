"""Build the thesis book (results/thesis/) from the rendered chapters.
The job: robomill.pipeline.jobs.book."""

from robomill.pipeline.jobs import book
from robomill.pipeline.runlog import setup

book.run(snakemake.input, snakemake.output, snakemake.params,
         log=setup(snakemake.log[0], "book"), config=snakemake.config)
