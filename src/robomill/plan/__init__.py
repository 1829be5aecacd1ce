"""The plan of the next cuts (chapter 7): request, predictions, choice, outputs and
the check against the outcomes. Light on purpose: the workflow imports :data:`NEXT_RUN_DIR`
while it is parsed, on every run."""

NEXT_RUN_DIR = "results/plan/next/run"
"""Where the next experiment's run writes (its ``results/``, the virtual cell's raw folder,
logs), relative to the study's folder: ``results/plan/next/config.yaml`` names it (config
``workdir``), so that running the planned cuts leaves the study's results as they are; the
study's ``plan_check`` reads the outcomes of the planned cuts from there."""
