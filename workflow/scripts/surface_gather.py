"""Gather the per-cut analyses: Tables 2.1/2.2, thesis comparison, peaks with mechanism,
metrics, spectra and profiles of every cut."""

import numpy as np
import pandas as pd
import xarray as xr

from robomill.io import open_artefact, write_artefact, write_table
from robomill.runlog import setup
from robomill.surface import (
    attribute_mechanisms,
    compare_with_thesis,
    load_thesis_tables,
    rms_table,
    settings,
    spectra_dataset,
)

log = setup(snakemake.log[0], "surface_gather")
opts = settings(snakemake.params.settings)
cuts = pd.DataFrame(snakemake.params.cuts).rename(columns={"id": "cut"})
by_id = {c: i for i, c in enumerate(cuts["cut"])}
per_cut = [open_artefact(f) for f in snakemake.input.cuts]
ids = [d.attrs["cut"] for d in per_cut]
order = np.argsort([by_id[c] for c in ids])
per_cut = [per_cut[i] for i in order]
ids = [ids[i] for i in order]

scalars = ["Wt_um", "Wq_um", "Rq_um", "Ra_um", "Rz_um", "waviness_rms_um", "roughness_rms_um",
           "parseval_rms_um", "tilt_um_per_mm"]
metrics = pd.DataFrame([{"cut": c, **{k: float(d[k]) for k in scalars}}
                        for c, d in zip(ids, per_cut, strict=True)])
metrics = metrics.merge(cuts[["cut", "set", "segment", "direction", "feed_mm_s", "depth_mm"]],
                        on="cut")
write_table(metrics, snakemake.output.metrics)

thesis = load_thesis_tables()
comparisons = []
for key, value, out in [("table_2_1_waviness_rms_um", "waviness_rms_um",
                         snakemake.output.waviness),
                        ("table_2_2_roughness_rms_um", "roughness_rms_um",
                         snakemake.output.roughness)]:
    table = rms_table(metrics, value)
    write_table(table, out, index=True)
    comparisons.append(compare_with_thesis(table, thesis[key], key))
comparison = pd.concat(comparisons, ignore_index=True)
write_table(comparison, snakemake.output.comparison)

peaks = pd.concat([pd.read_csv(f) for f in snakemake.input.peaks], ignore_index=True)
peaks = attribute_mechanisms(peaks, cuts, tolerance=float(opts["match_tolerance"]),
                             min_feed_ratio=float(opts["min_feed_ratio"]))
cols = ["cut", "f_spatial_per_mm", "f_temporal_hz", "amplitude_um", "mechanism", "band",
        "feed_mm_s", "power_um2", "n_witnesses", "n_kinematic_support", "n_dynamic_support",
        "resolution_per_mm", "below_resolution"]
write_table(peaks[cols], snakemake.output.peaks)

spectra = spectra_dataset(per_cut, ids)
write_artefact(spectra, snakemake.output.spectra, rule="surface_gather",
               inputs=snakemake.input.cuts, config_section=opts)
keep = ["z_measured", "z", "waviness", "roughness"]
profiles = xr.concat([d[keep].astype("float32") for d in per_cut], dim="cut",
                     join="override", compat="override", coords="minimal")
for k in keep:
    profiles[k].attrs = per_cut[0][k].attrs
profiles = profiles.assign_coords(cut=("cut", ids, {"units": "1", "long_name": "cut"}))
for col, units in [("feed_mm_s", "mm/s"), ("set", "1"), ("segment", "1"), ("direction", "1")]:
    profiles[col] = ("cut", cuts.set_index("cut").loc[ids, col].to_numpy(),
                     {"units": units, "long_name": col})
write_artefact(profiles, snakemake.output.profiles, rule="surface_gather",
               inputs=snakemake.input.cuts, config_section=opts)
n_in = int(comparison["within_1.5x"].sum())
log.info("%d cuts; %d of %d table cells within a factor 1.5 of the thesis; %d peaks (%s)",
         len(ids), n_in, len(comparison), len(peaks),
         peaks["mechanism"].value_counts().to_dict())
