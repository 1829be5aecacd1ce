"""Gather the per-cut analyses: Tables 2.1/2.2, thesis comparison, peaks with mechanism,
metrics, spectra and profiles of every cut (see robomill.surface.gather_surface)."""

import pandas as pd

from robomill.experiment import cut_process, is_thesis_design
from robomill.io import open_artefact, write_artefact, write_table
from robomill.pipeline.runlog import setup
from robomill.study import load_study
from robomill.surface.options import settings
from robomill.surface.study import gather_surface

log = setup(snakemake.log[0], "surface_gather")
opts = settings(snakemake.params.settings)
cuts = pd.DataFrame(snakemake.params.cuts).rename(columns={"id": "cut"})
manifest = load_study(snakemake.input.study)
plan = [manifest.cut(c) for c in cuts["cut"]]
# a design other than the thesis': each cut's own speed, flutes, feed per tooth, direction
processes = (None if is_thesis_design(plan)
             else {c.id: cut_process(c, manifest.experiment) for c in plan})
out = gather_surface([open_artefact(f) for f in snakemake.input.cuts], cuts,
                     [pd.read_csv(f) for f in snakemake.input.peaks], opts,
                     processes=processes)
write_table(out["metrics"], snakemake.output.metrics)
if processes is None:
    write_table(out["waviness"], snakemake.output.waviness, index=True)
    write_table(out["roughness"], snakemake.output.roughness, index=True)
    write_table(out["comparison"], snakemake.output.comparison)
else:
    write_table(out["by_design"], snakemake.output.by_design)
write_table(out["peaks"], snakemake.output.peaks)
for name in ("spectra", "profiles"):
    write_artefact(out[name], snakemake.output[name], rule="surface_gather",
                   inputs=snakemake.input.cuts, config_section=opts)
peaks = out["peaks"]
if processes is None:
    comparison = out["comparison"]
    log.info("%d cuts; %d of %d table cells within a factor 1.5 of the thesis; %d peaks (%s)",
             len(out["metrics"]), int(comparison["within_1.5x"].sum()), len(comparison),
             len(peaks), peaks["mechanism"].value_counts().to_dict())
else:
    log.info("%d cuts of a free design (metrics_by_design.csv); %d peaks (%s)",
             len(out["metrics"]), len(peaks), peaks["mechanism"].value_counts().to_dict())
