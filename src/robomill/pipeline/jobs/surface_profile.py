"""Analyse stylus profiles: detrend, Gaussian split, spectra, segment RMS, peaks (one cut, or
every cut of the virtual cell in one job: ``params.cut`` and the outputs in the same order).
A cut with an areal scan and no stylus profile is analysed from the scan's profile along the
feed.

The job of the rule script ``workflow/scripts/surface_profile.py``."""

from __future__ import annotations

import logging

from robomill.io import write_artefact, write_table
from robomill.io.profiles import read_profile
from robomill.pipeline.jobs import path_list
from robomill.study import load_study
from robomill.surface.options import settings
from robomill.surface.peaks import profile_peaks
from robomill.surface.psd import analyse_profile


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""

    opts = settings(params.settings)
    study = load_study(inputs.study)
    for relpath, raw, cut, nc, peaks_csv in zip(params.relpath, path_list(inputs.raw), params.cut,
                                                path_list(outputs.nc),
                                                path_list(outputs.peaks), strict=True):
        # a stylus profile of the raw folder (sha256 checked), or an areal scan's profile along
        # the feed (relpath None: written by rule surface_areal)
        path = study.verify_file(relpath) if relpath is not None else raw
        x, z, fs = read_profile(path)
        ds = analyse_profile(x, z, opts)
        ds.attrs.update({"cut": cut["id"], "feed_mm_s": float(cut["feed_mm_s"])})
        peaks = profile_peaks(ds, opts)
        peaks.insert(0, "cut", cut["id"])
        write_artefact(ds, nc, rule="surface_profile", inputs=[str(path)], config_section=opts)
        write_table(peaks, peaks_csv)
        log.info("%s: %d samples at %g /mm; waviness RMS %.3f um, roughness RMS %.3f um, %d peaks",
                 cut["id"], x.size, fs, float(ds.waviness_rms_um), float(ds.roughness_rms_um),
                 len(peaks))
