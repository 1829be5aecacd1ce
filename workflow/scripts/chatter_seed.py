"""Shagniev 2019 lobes, time-domain runs, detection and adaptive depth -> simulation.nc."""

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

from robomill.chatter.seed import run_seed  # noqa: E402
from robomill.io import write_artefact  # noqa: E402
from robomill.pipeline.runlog import setup  # noqa: E402

log = setup(snakemake.log[0], "chatter")
cfg = dict(snakemake.params.seed)
ds = run_seed(cfg, accuracy=snakemake.params.accuracy)
write_artefact(ds, snakemake.output.nc, rule="chatter_seed",
               config_section={**cfg, "accuracy": snakemake.params.accuracy})
log.info("a* %.4f mm, boundary at n %.4f mm, detections %s, lowered %.3f",
         ds.attrs["a_star_mm"], ds.attrs["a_boundary_at_n_mm"],
         ds.attrs["detections_adaptive_s"], ds.attrs["adaptation_lowered_fraction"])
