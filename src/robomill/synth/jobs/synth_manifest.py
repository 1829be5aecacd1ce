"""Write the synthetic study's manifest.yaml (sha256 of every simulated raw file).

The job of the rule script ``workflow/scripts/synth_manifest.py``."""

from __future__ import annotations

import logging
from pathlib import Path

from robomill.experiment import Cut
from robomill.io.manifest import build_manifest, write_manifest


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    cuts = [Cut(**c) for c in params.cuts]
    # The synthetic raw folder is the pipeline's own output: files left by an earlier
    # configuration (no longer planned) are removed so that the folder matches its manifest.
    raw = Path(params.raw_dir)
    planned = {f["path"] for f in params.files}
    for stale in sorted(q for q in raw.rglob("*") if q.is_file()):
        rel = stale.relative_to(raw).as_posix()
        if rel not in planned and rel != "manifest.yaml" and not stale.name.startswith("."):
            log.info("removing %s (not planned by the current configuration)", stale)
            stale.unlink()
    manifest = build_manifest(params.experiment, cuts, params.files, params.raw_dir)
    manifest["source"] = "synthetic (robomill virtual cell, see results/synthetic/truth.nc)"
    write_manifest(manifest, outputs[0])
    log.info("manifest: %d cuts, %d files", len(cuts), len(params.files))
