"""Execute a chapter notebook with papermill and render it to HTML
(see robomill.pipeline.chapters).
The job: robomill.pipeline.jobs.render_chapter."""

from robomill.pipeline.jobs import render_chapter
from robomill.pipeline.runlog import setup

render_chapter.run(snakemake.input, snakemake.output, snakemake.params,
                   log=setup(snakemake.log[0], "chapter"))
