"""Gather the per-cut analyses: Tables 2.1/2.2, thesis comparison, peaks with mechanism,
metrics, spectra and profiles of every cut (see robomill.surface.gather_surface)."""

import pandas as pd

from robomill.io import open_artefact, write_artefact, write_table
from robomill.pipeline.runlog import setup
from robomill.surface import gather_surface, settings

log = setup(snakemake.log[0], "surface_gather")
opts = settings(snakemake.params.settings)
cuts = pd.DataFrame(snakemake.params.cuts).rename(columns={"id": "cut"})
out = gather_surface([open_artefact(f) for f in snakemake.input.cuts], cuts,
                     [pd.read_csv(f) for f in snakemake.input.peaks], opts)
write_table(out["metrics"], snakemake.output.metrics)
write_table(out["waviness"], snakemake.output.waviness, index=True)
write_table(out["roughness"], snakemake.output.roughness, index=True)
write_table(out["comparison"], snakemake.output.comparison)
write_table(out["peaks"], snakemake.output.peaks)
for name in ("spectra", "profiles"):
    write_artefact(out[name], snakemake.output[name], rule="surface_gather",
                   inputs=snakemake.input.cuts, config_section=opts)
comparison, peaks = out["comparison"], out["peaks"]
log.info("%d cuts; %d of %d table cells within a factor 1.5 of the thesis; %d peaks (%s)",
         len(out["metrics"]), int(comparison["within_1.5x"].sum()), len(comparison),
         len(peaks), peaks["mechanism"].value_counts().to_dict())
