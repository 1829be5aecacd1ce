"""Instrument simulators drawing from one virtual cell (:mod:`robomill.synth.cell`).

The raw files each instrument writes (with their manifest metadata, paths relative to the
synthetic raw folder) are laid out from the configuration alone by
:mod:`robomill.io.synthetic_layout` (``instrument_files(config, instrument)``, every instrument's in
``planned_files``), which imports no simulator; each instrument module has a ``simulate_*``
function that writes one file in the contract format.
"""
