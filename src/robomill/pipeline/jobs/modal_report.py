"""Modes -> the chapter-3.3 tables: thesis peak groups, the planted-truth check (synthetic
runs) and the ±15 % mode-coupling test against the forces chapter's vibration frequency.

The job of the rule script ``workflow/scripts/modal_report.py``."""

from __future__ import annotations

import logging

import numpy as np
import pandas as pd

from robomill.io import open_artefact, write_table
from robomill.io.impact import read_frf
from robomill.modal.checks import mode_coupling, truth_check
from robomill.modal.layout import TOOLTIP, points
from robomill.modal.peaks import THESIS_NATURAL_HZ, group_peaks


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    ds = read_frf(inputs.frf)
    modes = pd.read_csv(inputs.modes)
    peaks = pd.read_csv(inputs.peaks)
    f = ds["frequency"].values
    tooltip = (points(ds, "output") == list(TOOLTIP)
               and points(ds, "input") == list(TOOLTIP))
    groups = group_peaks(peaks, float(f[1] - f[0]),
                         reference_hz=THESIS_NATURAL_HZ if tooltip else None)
    write_table(groups, outputs.peak_groups)

    truth = inputs.get("truth")
    if truth and tooltip:
        tt = open_artefact(truth)
        check = truth_check(modes, tt["mode_f_hz"].values, tt["mode_zeta"].values,
                            tt["mode_k_N_m"].values, tt["mode_shape"].values)
    else:
        check = truth_check(modes.iloc[:0], [], [], [], np.zeros((0, 3)))
    write_table(check, outputs.truth_check)

    forces_peaks = inputs.get("forces_peaks")
    fp = pd.read_csv(forces_peaks) if forces_peaks else pd.DataFrame()
    if (tooltip and len(fp) and "dominant_hz" in fp and fp["dominant_hz"].notna().any()
            and len(modes)):
        f_vib = float(fp["dominant_hz"].median())  # of the cuts that have a dominant peak
        per_mode, pairs = mode_coupling(modes, f_vib,
                                        tolerance=params.coupling_tolerance)
        log.info("vibration %.2f Hz (median of %d cuts): %d modes within +-%g %%", f_vib, len(fp),
                 int(per_mode["close"].sum()), 100 * params.coupling_tolerance)
    else:
        per_mode, pairs = (df.iloc[:0] for df in mode_coupling(modes.iloc[:0], 1.0))
        log.info("no mode-coupling test: %s", "not the tool-tip layout" if not tooltip
                 else "no dominant force frequency")
    write_table(per_mode, outputs.coupling)
    write_table(pairs, outputs.coupling_pairs)
    log.info("%d peak groups, %d truth rows", len(groups), len(check))
