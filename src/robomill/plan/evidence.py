"""The kinds of evidence behind ``results/plan/check.csv``: the outcomes read from a run's
chatter verdicts and tracker passes, whether a row is in-sample, and how often the stated
intervals held against their nominal level.

* **Stability** from the run's chatter verdicts (``results/chatter/verdicts.csv``: one row per
  cut and recording, columns ``cut, verdict, chatter_hz, source, evidence``, verdict
  ``stable`` | ``chatter`` | ``forced`` | ``undetermined``): a cut chatters when any of its
  recordings is called chatter, is stable when none is and at least one is called stable or
  forced (a forced line is vibration the cut did not make: no chatter), and is undetermined
  otherwise (NaN: no outcome to judge).
* **Deflection** from the run's tracker passes (``results/straightness/deflection.csv``: the
  loaded pass minus the air pass along the same path,
  :func:`robomill.straightness.deflection.pass_deflection_um`), as the magnitudes the planner
  predicts, |δ·n| and |δ·ẑ|.
* **In-sample**: an outcome whose data were used to identify a model the prediction rests on
  (the study's own cuts: their mean forces fitted the cutting coefficients, their tracker
  runs the gear amplitudes, both enter every prediction of the cut; and the cuts whose
  chatter verdicts conditioned the stability limit, :mod:`robomill.plan.conditioning`). A
  planned cut's outcome from its own run is out-of-sample.
* **Coverage**: the share of judged out-of-sample rows whose outcome held (inside the stated
  interval; for stability, the interval's verdict matching), beside the nominal level p of the
  intervals: consistent when the count held lies within the central 95 % range of a
  binomial(n, p) count (the rows taken as independent; rows of one cut are not, so the
  range is a guide), below or above otherwise.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

import numpy as np
import pandas as pd

from robomill.errors import RawDataError

VERDICT_COLUMNS = ("cut", "verdict", "chatter_hz", "source", "evidence")
"""Columns of ``results/chatter/verdicts.csv``."""

VERDICTS = ("stable", "chatter", "forced", "undetermined")
"""The verdicts of a cut's recording (``forced``: a line its air pass shows, not chatter)."""


def read_verdicts(path: str | Path) -> pd.DataFrame:
    """``results/chatter/verdicts.csv`` checked against its contract.

    Raises
    ------
    RawDataError
        A column is missing, or a row's verdict is not one of :data:`VERDICTS` (the message
        names the file, the row and what was expected).
    """
    table = pd.read_csv(path, dtype={"cut": str, "verdict": str}, keep_default_na=False,
                        na_values={"chatter_hz": [""]})
    missing = [c for c in VERDICT_COLUMNS if c not in table.columns]
    if missing:
        raise RawDataError(path, f"column(s) {', '.join(missing)} missing", where="header",
                           expected="columns " + ", ".join(VERDICT_COLUMNS))
    for i, v in enumerate(table["verdict"]):
        if v not in VERDICTS:
            raise RawDataError(path, f"verdict is {v!r}", where=f"row {i + 2}, column verdict",
                               expected=" | ".join(VERDICTS))
    return table


def verdict_stability(verdicts: pd.DataFrame) -> pd.Series:
    """Per cut, 1 (stable), 0 (chatter) or NaN (undetermined) from its recordings' verdicts
    (module docstring)."""
    out = {}
    for cut, g in verdicts.groupby(verdicts["cut"].astype(str), sort=False):
        v = set(g["verdict"])
        out[cut] = 0.0 if "chatter" in v else 1.0 if v & {"stable", "forced"} else np.nan
    return pd.Series(out, dtype=float)


def deflection_outcomes(deflection: pd.DataFrame) -> dict[str, pd.Series]:
    """``deflection_normal`` and ``deflection_axial`` magnitudes per cut [µm] from
    ``results/straightness/deflection.csv`` (cuts without a loaded pass left out; a cut with
    several air passes: their median)."""
    out = {}
    for name in ("normal", "axial"):
        col = f"deflection_{name}_um"
        d = deflection[["cut", col]].dropna()
        out[f"deflection_{name}"] = (d[col].abs().groupby(d["cut"].astype(str)).median()
                                     .astype(float))
    return out


def air_runs(deflection: pd.DataFrame | None) -> set[str]:
    """The air passes listed in ``results/straightness/deflection.csv`` (not read for
    waviness: the wall a cut leaves is that of its loaded pass)."""
    if deflection is None or deflection.empty:
        return set()
    return set(deflection["air_run"].astype(str))


def stated_verdict_held(low: float, high: float, stable: bool) -> bool:
    """Whether the stability interval's verdict matches the outcome: stable where the whole
    margin interval is positive, chatter where it is negative, either where it straddles 0."""
    return bool(high > 0 if stable else low < 0)


def in_sample(cuts: Iterable[str], identified: Iterable[str]) -> np.ndarray:
    """True for each cut whose data identified a model the predictions rest on (``identified``:
    the study's own cuts)."""
    ident = {str(c) for c in identified}
    return np.array([str(c) in ident for c in cuts], bool)


def identified_cuts(study_cuts: Iterable[str], evidence_used: pd.DataFrame | None
                    ) -> set[str]:
    """The cuts whose rows are in-sample: the study's own and those whose chatter verdicts
    conditioned the stability limit (``used`` in ``results/plan/evidence_used.csv``,
    :mod:`robomill.plan.conditioning`)."""
    out = {str(c) for c in study_cuts}
    if evidence_used is not None and len(evidence_used):
        used = evidence_used["used"].astype(str).str.lower().isin(["true", "1"])
        out |= set(evidence_used.loc[used, "cut"].astype(str))
    return out


def judged(check: pd.DataFrame) -> pd.Series:
    """``held`` as True/False with the rows of no determined outcome (empty ``held``) False,
    whatever the table's read-back dtype."""
    return check["held"].astype("boolean").fillna(False).astype(bool)


def has_verdict(check: pd.DataFrame) -> pd.Series:
    """The rows with a determined outcome (``held`` not empty)."""
    return check["held"].astype("boolean").notna()


def binomial_range(n: int, nominal: float) -> tuple[float, float]:
    """The central 95 % range of the count held among ``n`` rows if each holds with
    probability ``nominal`` (binomial quantiles 2.5 % and 97.5 %); NaN for no row."""
    if n <= 0:
        return np.nan, np.nan
    from scipy.stats import binom

    lo, hi = binom.ppf([0.025, 0.975], n, nominal)
    return float(lo), float(hi)


def coverage_summary(check: pd.DataFrame, nominal: float) -> dict[str, float]:
    """Chapter 7's coverage numbers: over the out-of-sample (``_oos``) and the in-sample
    (``_in``) rows, per quantity q ``n_<q>_oos`` (rows), ``n_<q>_judged_oos`` (with a determined
    outcome) and ``n_<q>_held_oos``; in all ``n_oos``, ``n_judged_oos``, ``n_held_oos``,
    ``coverage_oos_percent`` (NaN where none judged) and the same with ``_in``;
    ``nominal_coverage_percent``; ``held_range_low_oos``, ``held_range_high_oos``: the
    count held expected at the nominal level (:func:`binomial_range`)."""
    out: dict[str, float] = {"nominal_coverage_percent": 100.0 * float(nominal)}
    flag = check["in_sample"].astype("boolean").fillna(False).astype(bool)
    ok, held = has_verdict(check), judged(check)
    for suffix, rows in (("_oos", ~flag), ("_in", flag)):
        for q, idx in check[rows].groupby("quantity").groups.items():
            out[f"n_{q}{suffix}"] = float(len(idx))
            out[f"n_{q}_judged{suffix}"] = float(ok[idx].sum())
            out[f"n_{q}_held{suffix}"] = float(held[idx].sum())
        n, k = int((rows & ok).sum()), int((rows & held).sum())
        out[f"n{suffix}"] = float(rows.sum())
        out[f"n_judged{suffix}"] = float(n)
        out[f"n_held{suffix}"] = float(k)
        out[f"coverage{suffix}_percent"] = 100.0 * k / n if n else np.nan
    lo, hi = binomial_range(int(out["n_judged_oos"]), float(nominal))
    out["held_range_low_oos"], out["held_range_high_oos"] = lo, hi
    return out


def coverage_case(summary: dict) -> str:
    """Which of chapter 7's coverage sentences holds, from ``check_summary.csv``: ``none`` (no
    judged out-of-sample row), ``consistent`` (the count held within
    ``held_range_low_oos``–``held_range_high_oos``), ``below`` or ``above`` that range."""
    n = summary.get("n_judged_oos")
    if n is None or not n == n or n <= 0:
        return "none"
    k = float(summary["n_held_oos"])
    if k < float(summary["held_range_low_oos"]):
        return "below"
    return "above" if k > float(summary["held_range_high_oos"]) else "consistent"
