"""The plan's check as one job: each prediction of the plan (and of the study's own cuts)
beside the outcome its run's files recorded under the same cut id (:mod:`robomill.plan.check`):
the planned cuts' from their own run (``results/plan/next/run``), the study's from the study
(in-sample); the check table, its summary and the misses explained
(:func:`robomill.plan.misses.explain_misses`)."""

from __future__ import annotations

import logging
from collections.abc import Mapping
from typing import Any

import pandas as pd
import xarray as xr

from robomill.errors import RawDataError
from robomill.io import write_table
from robomill.plan.check import (
    RunOutcomes,
    check_summary,
    check_table,
    summary_table,
    waviness_min_cycles,
)
from robomill.plan.evidence import identified_cuts, read_verdicts
from robomill.plan.misses import explain_misses


def check_plan_files(inputs: Mapping[str, str], outputs: Mapping[str, str], *,
                     next_run: str, tolerance: float, chatter_fraction_of_mean: float,
                     nominal_coverage: float, fmin_cycles: float,
                     waviness_noise: Mapping[str, Any], log: logging.Logger) -> None:
    """Check the plan from the files ``inputs`` names (``plan``, ``study``, ``candidates``,
    ``evidence``, and each outcome present: ``mean_forces``, ``force_peaks``, ``verdicts``,
    ``gears``, ``profiles``, ``deflection``, ``peaks``, and the next run's ``next_*``) into
    ``outputs`` ``check``, ``summary`` and ``misses``; ``next_run``: the planned cuts' run
    folder; the other arguments are the ``plan`` configuration's."""
    inputs = dict(inputs.items())  # a mapping, or Snakemake's named inputs: by name

    def table(name):
        return pd.read_csv(inputs[name]) if name in inputs else None

    def dataset(name):
        return xr.load_dataset(inputs[name]) if name in inputs else None

    def verdicts(name):
        """A run's chatter verdicts; one line in the log and none where the file breaks its
        contract (the other outcomes are still checked)."""
        if name not in inputs:
            return None
        try:
            return read_verdicts(inputs[name])
        except RawDataError as err:
            log.warning("%s (stability from its force spectrum instead)", err)
            return None

    # the planned cuts' own run (results/plan/next/run), once it has run
    planned_run = RunOutcomes(next_run, mean_forces=table("next_mean_forces"),
                              force_peaks=table("next_force_peaks"),
                              verdicts=verdicts("next_verdicts"),
                              run_gears=table("next_gears"), profiles=dataset("next_profiles"),
                              deflection=table("next_deflection"))
    study_run = RunOutcomes("", mean_forces=table("mean_forces"),
                            force_peaks=table("force_peaks"), verdicts=verdicts("verdicts"),
                            run_gears=table("gears"), profiles=dataset("profiles"),
                            deflection=table("deflection"))
    study = pd.read_csv(inputs["study"])
    predicted = pd.concat([pd.read_csv(inputs["plan"]), study], ignore_index=True)
    # in-sample: the study's cuts (they identified the models) and the cuts whose verdicts
    # conditioned the stability limit (results/plan/evidence_used.csv)
    identified = identified_cuts(study["cut"], pd.read_csv(inputs["evidence"]))
    checked = check_table(
        predicted, study=study_run, planned_run=planned_run, peaks=table("peaks"),
        identified_cuts=identified, tolerance=float(tolerance),
        chatter_fraction_of_mean=float(chatter_fraction_of_mean),
        waviness_min_cycles=waviness_min_cycles(
            fmin_cycles, float(waviness_noise["exclude_bins"])))
    write_table(checked, outputs["check"])
    summary = check_summary(checked, float(tolerance), float(nominal_coverage))
    write_table(summary_table(summary), outputs["summary"])
    with xr.open_dataset(inputs["candidates"]) as cand:
        band = cand.attrs.get("modal_band_hz")
    band = tuple(float(b) for b in band) if band is not None and len(band) == 2 else None
    write_table(explain_misses(checked, pd.read_csv(inputs["plan"]), planned_run.verdicts,
                               band), outputs["misses"])
    log.info("%s", checked.groupby(["in_sample", "quantity"])["held"].agg(["size", "sum"])
             .to_string() if len(checked) else "no outcomes")
