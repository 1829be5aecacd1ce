"""Execute a chapter notebook with papermill and render it to HTML
(see robomill.pipeline.chapters)."""

from robomill.pipeline.chapters import render_chapter
from robomill.pipeline.runlog import setup

log = setup(snakemake.log[0], "chapter")
# every named input is a notebook parameter, except the notebook itself and `code`
# (library modules declared as inputs only so that editing them reruns the chapter)
inputs = {k: v for k, v in snakemake.input.items() if k not in ("notebook", "code")}
params = dict(snakemake.params.parameters) if "parameters" in snakemake.params.keys() else {}
opts = snakemake.params.options
render_chapter(
    snakemake.input.notebook,
    snakemake.output.ipynb,
    snakemake.output.html,
    snakemake.output.figures,
    {**inputs, **params},
    kernel=opts["kernel"],
    start_timeout_s=opts["start_timeout_s"],
    execution_timeout_s=opts["execution_timeout_s"],
    failed_copy=snakemake.params.failed_copy,
    shown=snakemake.params.shown,
)
log.info("rendered %s", snakemake.output.html)
