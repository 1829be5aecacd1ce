"""Instrument simulators drawing from one virtual cell (:mod:`robomill.synth.cell`).

Each instrument module exposes ``plan(config) -> list[dict]`` (the raw files it writes, with
their manifest metadata, paths relative to the synthetic raw folder) and a ``simulate_*``
function that writes one file in the contract format. :func:`robomill.synth.plan.planned_files`
gathers every instrument's plan.
"""
