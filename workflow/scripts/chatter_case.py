"""One configured lobe case -> results/chatter/cases/<name>.nc (ZOA and converged SEM)."""

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"  # many small eigenproblems: threads only add overhead

from robomill.pipeline.runlog import Progress, setup  # noqa: E402

log = setup(snakemake.log[0], "chatter")

from robomill.chatter.cases import run_case  # noqa: E402
from robomill.io import write_artefact  # noqa: E402

p = snakemake.params
case = dict(p.case)
progress = Progress(log, 1.0, f"lobe map {case['name']}")
ds = run_case(case, accuracy=p.accuracy, depth_max_m=p.depth_max_mm * 1e-3,
              progress=progress.update)
write_artefact(ds, snakemake.output.nc, rule="chatter_case",
               config_section={"case": case, "accuracy": p.accuracy})
progress.finish(f"case {case['name']}: {ds.sizes['spindle_rpm']} speeds, min a_crit zoa "
                f"{float(ds.a_crit_mm.sel(solver='zoa').min()):.3f} mm, sem "
                f"{float(ds.a_crit_mm.sel(solver='sem').min()):.3f} mm, worst error "
                f"{100 * ds.attrs['worst_relative_error']:.3f} %")
