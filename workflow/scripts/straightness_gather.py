"""All tracker runs: profiles.nc, gears.csv and peaks.csv (temporal vs spatial classification)."""

import pandas as pd
import xarray as xr

from robomill.io import open_artefact, write_artefact, write_table
from robomill.runlog import setup
from robomill.straightness import PEAK_COLUMNS, classify_peaks

log = setup(snakemake.log[0], "straightness_gather")
p = snakemake.params
runs = p.runs
parts = []
for r, path in zip(runs, snakemake.input.runs, strict=True):
    ds = open_artefact(path)
    parts.append(ds.expand_dims(run=[r["run"]]))
keys = ("direction", "feed_mm_s", "cut", "resolution_per_mm", "length_mm", "speed_mm_s",
        "fmin_per_mm", "floor_um2")
units = {"feed_mm_s": "mm/s", "resolution_per_mm": "1/mm", "length_mm": "mm",
         "speed_mm_s": "mm/s", "fmin_per_mm": "1/mm", "floor_um2": "um^2"}
names = {"direction": "cut direction", "feed_mm_s": "commanded feed",
         "cut": "cut whose path the run follows", "resolution_per_mm": "frequency resolution 1/L",
         "length_mm": "analysed path length L", "speed_mm_s": "measured speed",
         "fmin_per_mm": "lowest analysed frequency", "floor_um2": "median power in the band"}
coords = {k: ("run", [ds.attrs[k] for ds in parts], {"units": units.get(k, "1"),
                                                     "long_name": names[k]}) for k in keys}
for ds in parts:
    ds.attrs = {}
prof = xr.concat(parts, dim="run", join="outer").assign_coords(coords)
prof["run"].attrs = {"units": "1", "long_name": "tracker run <dir>_f<feed>"}
write_artefact(prof, snakemake.output.profiles, rule="straightness_gather",
               inputs=snakemake.input.runs, config_section=p.settings)

gears = pd.concat([pd.read_csv(f) for f in snakemake.input.gears], ignore_index=True)
gears["f_temporal_hz"] = gears["f_spatial_per_mm"] * gears["feed_mm_s"]
write_table(gears, snakemake.output.gears)

peaks = pd.concat([pd.read_csv(f, keep_default_na=False, na_values=[""])
                   for f in snakemake.input.peaks], ignore_index=True)
peaks["joint"] = peaks["joint"].astype("Int64")
peaks[["stage", "order"]] = peaks[["stage", "order"]].fillna("")
res = {(d, float(v)): float(x) for d, v, x in zip(prof["direction"].values,
                                                  prof["feed_mm_s"].values,
                                                  prof["resolution_per_mm"].values, strict=True)}
peaks = classify_peaks(peaks, res, tol_bins=p.settings["class_tol_bins"])
extra = [c for c in ("n_candidates",) if c in peaks]
write_table(peaks[PEAK_COLUMNS + extra], snakemake.output.peaks)
log.info("%d runs, %d peaks: %s", len(runs), len(peaks),
         peaks["mechanism"].value_counts().to_dict())
