"""All tracker runs: profiles.nc, gears.csv and peaks.csv (temporal vs spatial classification;
see robomill.straightness.gather_profiles, gather_gears, gather_peaks)."""

import pandas as pd

from robomill.io import open_artefact, write_artefact, write_table
from robomill.pipeline.runlog import setup
from robomill.straightness.study import gather_gears, gather_peaks, gather_profiles

log = setup(snakemake.log[0], "straightness_gather")
p = snakemake.params
prof = gather_profiles([open_artefact(f) for f in snakemake.input.runs],
                       [r["run"] for r in p.runs])
write_artefact(prof, snakemake.output.profiles, rule="straightness_gather",
               inputs=snakemake.input.runs, config_section=p.settings)
write_table(gather_gears([pd.read_csv(f) for f in snakemake.input.gears]),
            snakemake.output.gears)
peaks = gather_peaks([pd.read_csv(f, keep_default_na=False, na_values=[""])
                      for f in snakemake.input.peaks], prof,
                     tol_bins=p.settings["class_tol_bins"])
write_table(peaks, snakemake.output.peaks)
log.info("%d runs, %d peaks: %s", len(p.runs), len(peaks),
         peaks["mechanism"].value_counts().to_dict())
