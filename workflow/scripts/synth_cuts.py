"""Integrate every planned cut of the virtual cell once (robomill.synth.cutstate) and store
its simulated state, one file per cut, one cut after the other in this process (the set-up of
the first cut, imports and compiled kernels, is paid once)."""

from robomill.pipeline.runlog import setup

log = setup(snakemake.log[0], "synth_cuts")

import time  # noqa: E402

from robomill.experiment import Cut  # noqa: E402
from robomill.synth.cell import cell_from_config  # noqa: E402
from robomill.synth.cutstate import write_cut_state  # noqa: E402

cfg = dict(snakemake.params.cfg)
cell = cell_from_config(cfg)
for spec, path in zip(snakemake.params.cuts, snakemake.output, strict=True):
    cut = Cut(**spec["cut"])
    t0 = time.perf_counter()
    write_cut_state(cell, cut, cfg, path, length_mm=spec["length_mm"], air=spec["air"])
    log.info("simulated %s (%s%s) in %.2f s -> %s", cut.id,
             "whole cut" if spec["length_mm"] is None else f"first {spec['length_mm']:g} mm",
             ", with its air pass" if spec["air"] else "", time.perf_counter() - t0, path)
