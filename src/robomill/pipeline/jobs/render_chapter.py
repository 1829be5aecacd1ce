"""Execute a chapter notebook with papermill and render it to HTML
(see robomill.pipeline.chapters).

The job of the rule script ``workflow/scripts/render_chapter.py``."""

from __future__ import annotations

import logging

from robomill.pipeline.chapters import render_chapter


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    # every named input is a notebook parameter, except the notebook itself and `code`
    # (library modules declared as inputs only so that editing them reruns the chapter)
    named = {k: v for k, v in inputs.items() if k not in ("notebook", "code")}
    parameters = dict(params.parameters) if "parameters" in params.keys() else {}
    opts = params.options
    render_chapter(
        inputs.notebook,
        outputs.ipynb,
        outputs.html,
        outputs.figures,
        {**named, **parameters},
        kernel=opts["kernel"],
        start_timeout_s=opts["start_timeout_s"],
        execution_timeout_s=opts["execution_timeout_s"],
        failed_copy=params.failed_copy,
        shown=params.shown,
    )
    log.info("rendered %s", outputs.html)
