"""Analyse force records in chunks: mean forces, Welch PSD, low-band thesis power, peaks
(robomill.forces). One cut, or every cut of the virtual cell in one job: ``params.cut`` and
the outputs in the same order.

The job of the rule script ``workflow/scripts/forces_cut.py``."""

from __future__ import annotations

import logging
from collections.abc import Mapping
from typing import Any

from robomill.experiment import cut_process
from robomill.forces.settings import ForceAnalysisSettings, ForcePeakSettings
from robomill.forces.stream import ForceSpectrumAccumulator
from robomill.forces.study import force_cut_dataset
from robomill.io import write_artefact
from robomill.io.forces import open_force_record
from robomill.io.manifest import Manifest
from robomill.pipeline.jobs import path_list
from robomill.study import load_study


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    s = params.settings
    manifest = load_study(inputs.study)
    for args in zip(params.cut, params.relpath, path_list(inputs.raw), path_list(outputs),
                    strict=True):
        analyse_cut(manifest, *args, s=s, log=log)


def analyse_cut(manifest: Manifest, cut_id: str, relpath: str, raw: str, out_nc: str, *,
                s: Mapping[str, Any], log: logging.Logger) -> None:
    """One cut's record ``raw`` (study path ``relpath``, verified) into ``out_nc``; ``s``: the
    ``forces`` section."""
    path = manifest.verify_file(relpath)
    entry = manifest.entry(relpath)
    cut = manifest.cut(cut_id)
    record = open_force_record(path, float(entry["fs_hz"]))
    acc = ForceSpectrumAccumulator(record.fs_hz, record.n_samples,
                                   ForceAnalysisSettings.from_mapping(s))
    for t, force in record.chunks(int(s["chunk_samples"])):
        acc.add(t, force)
    proc = cut_process(cut, manifest.experiment)  # the cut's own speed and flutes (else the
    ds = force_cut_dataset(acc.result(), cut=cut.as_dict(), fs_hz=record.fs_hz,  # experiment's)
                           n_samples=record.n_samples, spindle_rpm=proc["spindle_rpm"],
                           flutes=proc["flutes"], n_harmonics=s["n_harmonics"],
                           peaks=ForcePeakSettings.from_mapping(s))
    write_artefact(ds, out_nc, rule="forces_cut", inputs=[raw], config_section=s)
    log.info("%s: %d samples at %g Hz, decimation %d (%s), dominant %.2f Hz, kinematic %.3f "
             "1/mm (nan: no peak stands out of its floor)",
             cut_id, record.n_samples, record.fs_hz, acc.D,
             "from the rate" if s["decimation"] is None else "forces.decimation",
             float(ds["dominant_hz"]), float(ds["kinematic_per_mm"]))
    if bool(ds["kinematic_below_resolution"]):
        log.warning("%s: kinematic peak %.3f 1/mm is below the record's resolution (%.3f 1/mm,"
                    " fewer than %g periods in the record)", cut_id,
                    float(ds["kinematic_per_mm"]), float(ds["kinematic_resolution_per_mm"]),
                    float(s["min_peak_cycles"]))
