"""Closing the loop: each prediction beside the outcome of the cut it was made for.

An outcome is whatever the run measured (or simulated) under the cut's id: the mean cutting
force of ``results/forces/mean_forces.csv`` (magnitude of Fx, Fy, Fz) and the waviness of the
tracker run along the cut (the in-phase sum of its gear-attributed lateral lines,
``results/straightness/peaks.csv``, the quantity :func:`robomill.plan.measured.waviness_um`
predicts). Cuts without an outcome are left out; a prediction is judged within its interval
and within a relative tolerance (the issue's 25 %).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

CHECK_COLUMNS = ["cut", "quantity", "unit", "predicted", "low", "high", "outcome",
                 "within_interval", "within_tolerance", "source"]


def force_outcomes(mean_forces: pd.DataFrame) -> pd.Series:
    """Mean-force magnitude per cut [N]."""
    F = mean_forces[["Fx_N", "Fy_N", "Fz_N"]].to_numpy(float)
    return pd.Series(np.linalg.norm(F, axis=1), index=mean_forces["cut"].astype(str))


def waviness_outcomes(peaks: pd.DataFrame) -> pd.Series:
    """In-phase sum of the gear-attributed lateral line amplitudes per cut [µm]."""
    g = peaks[(peaks["mechanism"] == "gear") & (peaks["component"] == "lateral")]
    return g.groupby(g["cut"].astype(str))["amplitude_um"].sum()


def check_table(predicted: pd.DataFrame, *, mean_forces: pd.DataFrame | None = None,
                peaks: pd.DataFrame | None = None, tolerance: float = 0.25) -> pd.DataFrame:
    """Rows ``cut, quantity, unit, predicted, low, high, outcome, within_interval,
    within_tolerance, source`` for every predicted cut with an outcome.

    Parameters
    ----------
    predicted
        Rows with ``cut`` and the prediction columns (``force_N``, ``force_low_N``,
        ``force_high_N``, ``waviness_um``, …): ``plan.csv`` and ``study_cuts.csv``.
    """
    outcomes = []
    if mean_forces is not None and len(mean_forces):
        outcomes.append(("force", "N", force_outcomes(mean_forces),
                         "results/forces/mean_forces.csv"))
    if peaks is not None and len(peaks):
        outcomes.append(("waviness", "um", waviness_outcomes(peaks),
                         "results/straightness/peaks.csv"))
    rows = []
    for _, r in predicted.iterrows():
        cut = str(r["cut"])
        for name, unit, series, source in outcomes:
            if cut not in series.index or f"{name}_{unit}" not in r:
                continue
            p = float(r[f"{name}_{unit}"])
            lo, hi = float(r[f"{name}_low_{unit}"]), float(r[f"{name}_high_{unit}"])
            o = float(series[cut])
            rows.append({"cut": cut, "quantity": name, "unit": unit, "predicted": p,
                         "low": lo, "high": hi, "outcome": o,
                         "within_interval": bool(lo <= o <= hi),
                         "within_tolerance": bool(abs(o - p) <= tolerance * abs(o)),
                         "source": source})
    return pd.DataFrame(rows, columns=CHECK_COLUMNS)
