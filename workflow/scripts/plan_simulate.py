"""The virtual cell cuts the planned cuts and the study's own (issue 28, closing the loop):
stability in the seed-002 time-domain model and static deflection from the planted truth at
each cut's pose (robomill.synth.plancuts) -> results/plan/simulated.csv."""

import numpy as np
import yaml

from robomill.io import write_table
from robomill.pipeline.runlog import setup
from robomill.study import load_study
from robomill.synth.cell import cell_from_config
from robomill.synth.plancuts import (
    PosedCut,
    planned_cuts,
    planted_compliance,
    settings,
    simulate_cuts,
)

log = setup(snakemake.log[0], "plan")
inp, p = snakemake.input, snakemake.params
cfg = dict(p.cfg)
s = settings(p.settings)
cell = cell_from_config(cfg)
planned = planned_cuts(yaml.safe_load(open(inp.manifest)))
experiment = dict(p.experiment)
own = [PosedCut(c, experiment) for c in load_study(inp.study).cuts]
if s["modes_reference_mm"] is not None:
    reference = np.asarray(s["modes_reference_mm"], float)
elif own:  # where the impact test is made: the middle of the study's cuts (as the planner)
    reference = np.array([c.middle_mm for c in own]).mean(0)
else:
    reference = np.array([c.middle_mm for c in planned]).mean(0)
table = simulate_cuts(planned + own, cell, planted_compliance(cfg), reference, s)
write_table(table, snakemake.output.simulated)
log.info("modes' reference point %s mm; %d cuts simulated, %d stable",
         np.round(reference, 3).tolist(), len(table), int(table["stable"].fillna(False).sum()))
