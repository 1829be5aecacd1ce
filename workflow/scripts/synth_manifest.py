"""Write the synthetic study's manifest.yaml (sha256 of every simulated raw file)."""

from robomill.experiment import Cut
from robomill.io.manifest import build_manifest, write_manifest
from robomill.runlog import setup

log = setup(snakemake.log[0], "synth_manifest")
p = snakemake.params
cuts = [Cut(**c) for c in p.cuts]
manifest = build_manifest(p.experiment, cuts, p.files, p.raw_dir)
manifest["source"] = "synthetic (robomill virtual cell, see results/synthetic/truth.nc)"
write_manifest(manifest, snakemake.output[0])
log.info("manifest: %d cuts, %d files", len(cuts), len(p.files))
