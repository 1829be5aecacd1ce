"""The study's robot: lobes for each slot of the study's cuts, mode coupling, recommendations."""

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import pandas as pd  # noqa: E402

from robomill.chatter.slot_lobes import study_lobes  # noqa: E402
from robomill.io import write_artefact, write_table  # noqa: E402
from robomill.pipeline.runlog import setup  # noqa: E402
from robomill.study import read_study  # noqa: E402

log = setup(snakemake.log[0], "chatter")
inp, p = snakemake.input, snakemake.params
modes = pd.read_csv(inp.modes)
coeffs = pd.read_csv(inp.coefficients)
peaks = pd.read_csv(inp.peaks)
missing = [c for c in ("f_n_hz", "zeta", "k_modal_N_m", "shape_x", "shape_y")
           if c not in modes.columns]
if missing:
    raise ValueError(f"{inp.modes}: missing columns {missing} (contract: CONTRACTS.md)")
lobes, rec = study_lobes(modes, coeffs, peaks, dict(p.thesis), study=read_study(inp.study),
                        accuracy=p.accuracy)
write_artefact(lobes, snakemake.output.lobes, rule="chatter_thesis",
               inputs=[inp.modes, inp.coefficients, inp.peaks, inp.study],
               config_section={**dict(p.thesis), "accuracy": p.accuracy})
write_table(rec, snakemake.output.recommendations)
log.info("recommendations:\n%s", rec.to_string())
