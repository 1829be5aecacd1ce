"""Analyse one stylus profile: detrend, Gaussian split, spectra, segment RMS, peaks."""

from robomill.io import write_artefact, write_table
from robomill.io.profiles import read_profile
from robomill.pipeline.runlog import setup
from robomill.study import load_study
from robomill.surface.options import settings
from robomill.surface.peaks import profile_peaks
from robomill.surface.psd import analyse_profile

log = setup(snakemake.log[0], "surface_profile")
p = snakemake.params
opts = settings(p.settings)
path = load_study(snakemake.input.study).verify_file(p.relpath)
x, z, fs = read_profile(path)
ds = analyse_profile(x, z, opts)
ds.attrs.update({"cut": p.cut["id"], "feed_mm_s": float(p.cut["feed_mm_s"])})
peaks = profile_peaks(ds, opts)
peaks.insert(0, "cut", p.cut["id"])
write_artefact(ds, snakemake.output.nc, rule="surface_profile", inputs=[str(path)],
               config_section=opts)
write_table(peaks, snakemake.output.peaks)
log.info("%s: %d samples at %g /mm; waviness RMS %.3f um, roughness RMS %.3f um, %d peaks",
         p.cut["id"], x.size, fs, float(ds.waviness_rms_um), float(ds.roughness_rms_um),
         len(peaks))
