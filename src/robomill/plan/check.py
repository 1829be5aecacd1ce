"""Closing the loop: each prediction beside the outcome of the cut it was made for, read only
from the files of a run of the cuts.

An outcome is what a run's instruments recorded under the cut's id, read by the pipeline's own
analyses of that run: the mean cutting force of ``results/forces/mean_forces.csv`` (magnitude
of Fx, Fy, Fz); the waviness of the tracker run along the cut (:func:`waviness_outcomes`: its
measured spectrum read at the gear lines the prediction used; the loaded pass); the static
deflection along the wall normal and the tool axis (quantities ``deflection_normal``,
``deflection_axial`` [µm]) from the loaded tracker pass minus the air pass along the same
path (``results/straightness/deflection.csv``); and the stability from the run's chatter
verdicts (``results/chatter/verdicts.csv``, :mod:`robomill.plan.evidence`), else from its
force spectrum (``results/forces/peaks.csv``: chatter when the dominant modal-band line,
√(bin power), exceeds ``chatter_fraction_of_mean`` of the mean force).

The planned cuts' own run (``snakemake all --configfile results/plan/next/config.yaml``,
written under ``results/plan/next/run``: :data:`robomill.plan.NEXT_RUN_DIR`; on the virtual
cell or a lab's files of the planned cuts alike) gives the outcomes of the planned cuts; the
study's own run those of its cuts (in-sample: the data that identified the models). Nothing
here is computed from a planted parameter. Cuts without an outcome are left out; a
prediction is judged within its interval and within a relative tolerance (25 %).

Columns ``in_sample`` (:func:`robomill.plan.evidence.in_sample`) and ``held``: the outcome
inside the stated interval (for stability, the interval's verdict matching); empty where the
outcome is undetermined (a chatter verdict ``undetermined``).

Encoding of the ``stability`` rows (unit ``1``): ``predicted``, ``low``, ``high`` are the
stability margin a_crit/a − 1 and its interval (> 0 predicts stable); ``outcome`` is 1 when
the cut was stable, 0 when it chattered, NaN when undetermined. The row is judged on the
critical depth: the outcome says on which side of the true a_crit the cut's depth a
(``depth_mm``) lies — stable: a_crit > a, chatter: a_crit < a — and ``within_interval``
says whether the predicted interval [``a_crit_low_mm``, ``a_crit_high_mm``] reaches that
side (stable needs a_crit_high > a, chatter a_crit_low < a; without a critical depth, the
margin's ``high`` > 0 and ``low`` < 0); ``within_tolerance``: the nominal a_crit
(``a_crit_mm``) lies on the outcome's side. ``depth_over_a_crit`` is a / a_crit (nominal)
and ``decisive`` says whether the depth lies inside the a_crit interval, where the interval
leaves the verdict open and the outcome tests the critical depth itself (a cut at 1/100 of
a_crit confirms only the sign: :func:`decisive_summary`). ``p_stable``
the predicted probability of a stable cut (:mod:`robomill.plan.stability`), scored against
the outcome by the Brier score [Brier 1950] B = mean (p − o)² over every judged cut
(:func:`brier_score`; 0 perfect, 0.25 a coin).

**Sharpness** of each interval quantity: the median over its rows of the interval's
half-width over the prediction, (high − low)/(2 |predicted|) (:func:`sharpness`), beside its
coverage: an interval can hold every outcome by being wide, and the pair says which. The
stability row's interval is the critical depth's, so its sharpness is the a_crit interval's
half-width over the nominal a_crit.

Brier 1950: Brier, G. W. Verification of forecasts expressed in terms of probability.
*Monthly Weather Review* 78(1), 1–3, 1950.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from robomill import catalogue
from robomill.plan.evidence import (
    air_runs,
    coverage_summary,
    deflection_outcomes,
    in_sample,
    stated_verdict_held,
    verdict_stability,
)
from robomill.plan.measured import spectrum_amplitude_um
from robomill.settings import schema_default

CHECK_COLUMNS = ["cut", "quantity", "unit", "predicted", "low", "high", "outcome",
                 "within_interval", "within_tolerance", "held", "in_sample", "source",
                 "p_stable", "depth_mm", "a_crit_mm", "a_crit_low_mm", "a_crit_high_mm",
                 "depth_over_a_crit", "decisive"]


def force_outcomes(mean_forces: pd.DataFrame) -> pd.Series:
    """Mean-force magnitude per cut [N]."""
    F = mean_forces[["Fx_N", "Fy_N", "Fz_N"]].to_numpy(float)
    return pd.Series(np.linalg.norm(F, axis=1), index=mean_forces["cut"].astype(str))


WAVINESS_MIN_CYCLES = 4.5
"""A gear line counts as waviness where it completes at least this many periods along the
path: :func:`waviness_min_cycles` of the default settings (``straightness.fmin_cycles`` 2.5
and ``plan.waviness_noise.exclude_bins`` 2), the ``min_cycles`` default of
:func:`robomill.plan.measured.waviness_um` and of :func:`waviness_outcomes`."""


def waviness_min_cycles(fmin_cycles: float, exclude_bins: float) -> float:
    """Periods along the path from which a gear line counts as waviness, in the prediction and
    in its outcome alike: the straightness analysis' lowest analysed frequency
    (``fmin_cycles`` periods per record, below which the run's slow deviation is left as its
    line) plus the Hann main lobe's half width (``exclude_bins`` resolution bins), so that a
    line's read window (±0.5 bin) lies clear of the slow deviation's lobe. A line read closer
    reads the leakage of that slow deviation, not a gear: the window spreads the deviation's
    amplitude over its main lobe, so a read there returns a share of it where no peak stands
    out."""
    return float(fmin_cycles) + float(exclude_bins)


def waviness_elements(peaks: pd.DataFrame | None) -> pd.DataFrame:
    """The gear elements ``joint, stage, order`` the waviness prediction carries: those the
    study's tracker runs attributed (``results/straightness/peaks.csv``, mechanism ``gear``,
    joint given: the input of :func:`robomill.plan.measured.gear_joint_amplitudes`)."""
    cols = ["joint", "stage", "order"]
    if peaks is None or peaks.empty or "joint" not in peaks:
        return pd.DataFrame(columns=cols)
    g = peaks[(peaks["mechanism"] == "gear") & peaks["joint"].notna()]
    out = g[cols].astype({"joint": int}).astype({"stage": str, "order": str})
    return out.drop_duplicates().reset_index(drop=True)


def waviness_outcomes(elements: pd.DataFrame, run_gears: pd.DataFrame, profiles,
                      *, min_cycles: float = WAVINESS_MIN_CYCLES,
                      halfwidth_bins: float = 0.5,
                      merge_bins: float = schema_default("straightness", "merge_bins"),
                      skip_runs: frozenset[str] | set[str] = frozenset()) -> pd.Series:
    """Measured waviness normal to the wall per cut [µm], the quantity
    :func:`robomill.plan.measured.waviness_um` predicts: Σ_e A_lat(f_e), the in-phase sum over
    the predicted gear elements e (``elements``, :func:`waviness_elements`) of the run's
    lateral sinusoid amplitude at the element's spatial frequency f_e on that run's path.

    Same component: the wall normal of a cut, n = ẑ × u (:func:`robomill.plan.poses.cut_frames`),
    is the tracker's lateral axis Z × u (:func:`robomill.straightness.perpendicular_axes`).
    Same amplitude definition: A_lat is the Hann-windowed, coherent-gain corrected sinusoid
    amplitude of the lateral deviation (``amplitude_um`` of ``profiles.nc``,
    :func:`robomill.straightness.profile_spectrum`, thesis eqs. 2.1–2.3), the
    amplitude a in a·sin(2πfs) — as the joint amplitude δq_j carried through nᵀJ_v is. (A
    detected peak's ``amplitude_um`` is √(2P) of the lateral + vertical power: not this
    quantity.) The spectrum is read whether or not a peak was detected there, so a line below
    the detection threshold still gives an outcome (its measured amplitude, an upper bound of
    the line when the noise floor dominates). The prediction's interval for this read
    (``waviness_low_um``, ``waviness_high_um``) carries that noise: the tracker's floor near
    the lines, the max over the ±``halfwidth_bins`` window and the sum over the lines
    (:mod:`robomill.plan.noise`).

    Parameters
    ----------
    elements
        ``joint, stage, order`` of the gear lines the prediction used.
    run_gears
        ``results/straightness/gears.csv``: per ``run`` (and its ``cut``) the spatial frequency
        ``f_spatial_per_mm`` of every element on the run's path
        (:func:`robomill.straightness.gear_spatial_frequencies`).
    profiles
        ``results/straightness/profiles.nc`` (``amplitude_um`` over ``run, component, f``;
        ``length_mm`` and ``resolution_per_mm`` per run).
    min_cycles
        An element counts where f_e × path length ≥ ``min_cycles`` (the prediction's rule).
    halfwidth_bins
        A_lat(f_e) is the largest amplitude within ±``halfwidth_bins`` resolution bins 1/L of
        f_e (the kinematic frequency vs the zero-padded grid).
    merge_bins
        Elements closer than ``merge_bins`` resolution bins make one spectral line (the Hann
        main lobe; ``straightness.merge_bins``): it is read once, as the largest amplitude
        from the lowest to the highest of their frequencies (± the half width), not once per
        element (a coherent sum of close lines is at most the in-phase sum the prediction
        makes).
    skip_runs
        Runs not read (the air passes: the wall a cut leaves is its loaded pass').

    Returns
    -------
    pandas.Series
        Per cut id, the median over its runs of the run's sum (cuts without a run left out).
    """
    if elements is None or elements.empty or run_gears is None or profiles is None:
        return pd.Series(dtype=float)
    keys = set(zip(elements["joint"].astype(int), elements["stage"].astype(str),
                   elements["order"].astype(str), strict=True))
    runs = [str(r) for r in profiles["run"].values]
    out: dict[str, list[float]] = {}
    for k, run in enumerate(runs):
        g = run_gears[run_gears["run"].astype(str) == run]
        if g.empty or run in skip_runs:
            continue
        length = float(profiles["length_mm"].values[k])
        res = float(profiles["resolution_per_mm"].values[k])
        used = [(int(r["joint"]), str(r["stage"]), str(r["order"])) in keys
                for _, r in g.iterrows()]
        f_used = np.sort(g["f_spatial_per_mm"].to_numpy(float)[used])
        f_used = f_used[f_used * length >= min_cycles]
        total = 0.0
        # clusters of elements closer than merge_bins: one line each
        cuts = np.flatnonzero(np.diff(f_used) >= merge_bins * res) + 1
        for group in np.split(f_used, cuts) if f_used.size else []:
            a = spectrum_amplitude_um(profiles, run, "lateral", group[0], group[-1],
                                      halfwidth_bins=halfwidth_bins)
            total += a if np.isfinite(a) else 0.0
        out.setdefault(str(g["cut"].iloc[0]), []).append(total)
    return pd.Series({c: float(np.median(v)) for c, v in out.items()}, dtype=float)


@dataclass(frozen=True)
class RunOutcomes:
    """The outcome files of one pipeline run of cuts (``folder``: "" for the study's own run,
    :data:`robomill.plan.NEXT_RUN_DIR` for the planned cuts' run): its mean forces, force
    spectrum peaks, chatter verdicts (``results/chatter/verdicts.csv``), tracker gear
    frequencies (``gears.csv``), profiles (``profiles.nc``) and loaded-minus-air deflections
    (``deflection.csv``); each None where that run has none."""

    folder: str = ""
    mean_forces: pd.DataFrame | None = None
    force_peaks: pd.DataFrame | None = None
    verdicts: pd.DataFrame | None = None
    run_gears: pd.DataFrame | None = None
    profiles: Any = None
    deflection: pd.DataFrame | None = None

    def path(self, artefact: str) -> str:
        """Where ``artefact`` (``results/...``) of this run lies, from the study's folder."""
        return f"{self.folder}/{artefact}" if self.folder else artefact


def _present(table: pd.DataFrame | None) -> bool:
    return table is not None and len(table) > 0


def spectrum_stability(force_peaks: pd.DataFrame, mean_forces: pd.DataFrame,
                       chatter_fraction_of_mean: float = schema_default(
                           "plan", "chatter_fraction_of_mean")) -> pd.Series:
    """1 (stable) or 0 (chatter) per cut from its force spectrum: chatter when the dominant
    modal-band line √P exceeds ``chatter_fraction_of_mean`` × |F̄| (a cut without a dominant
    line is stable)."""
    F = force_outcomes(mean_forces)
    pk = force_peaks.set_index(force_peaks["cut"].astype(str))
    line = np.sqrt(pk["dominant_power"].astype(float).fillna(0.0))
    common = line.index.intersection(F.index)
    return (line[common] / F[common] <= chatter_fraction_of_mean).astype(float)


def stability_judgement(a_crit_low_mm: float, a_crit_high_mm: float, depth_mm: float,
                        stable: bool) -> bool:
    """Whether the critical depth's interval reaches the outcome's side of the cut's depth:
    a stable cut bounds the true a_crit from below (a_crit > a), so the interval holds where
    its high end exceeds a; a chattering cut bounds it from above (a_crit < a), so its low
    end must lie below a."""
    return bool(a_crit_high_mm > depth_mm if stable else a_crit_low_mm < depth_mm)


def _stability_row(cut: str, r: pd.Series, outcome: float, source: str) -> dict | None:
    p = float(r.get("stability_margin", np.nan))
    if not np.isfinite(p):
        return None
    lo = float(r.get("stability_margin_low", p))
    hi = float(r.get("stability_margin_high", p))
    depth = float(r.get("depth_mm", np.nan))
    a = float(r.get("a_crit_mm", np.nan))
    a_lo = float(r.get("a_crit_low_mm", a))
    a_hi = float(r.get("a_crit_high_mm", a))
    # a critical depth may be +inf (no chatter at any depth: the interval's high end, or the
    # nominal member's); NaN is no prediction
    on_depth = bool(np.isfinite(depth) and not np.isnan([a, a_lo, a_hi]).any())
    row = {"cut": cut, "quantity": "stability", "unit": "1", "predicted": p, "low": lo,
           "high": hi, "outcome": outcome, "within_interval": None, "within_tolerance": None,
           "held": None, "source": source, "p_stable": float(r.get("p_stable", np.nan)),
           "depth_mm": depth, "a_crit_mm": a, "a_crit_low_mm": a_lo, "a_crit_high_mm": a_hi,
           "depth_over_a_crit": depth / a if on_depth and a > 0 else np.nan,
           "decisive": bool(a_lo <= depth <= a_hi) if on_depth else None}
    if np.isfinite(outcome):
        stable = outcome >= 0.5
        if on_depth:
            inside = stability_judgement(a_lo, a_hi, depth, stable)
            nominal = bool((a > depth) == stable)
        else:
            inside = stated_verdict_held(lo, hi, stable)
            nominal = bool((p > 0) == stable)
        row.update({"outcome": float(stable), "within_interval": inside,
                    "within_tolerance": nominal, "held": inside})
    return row


def _rounding(x: float) -> float:
    """Half a unit of the 6th significant digit of ``x``: the rounding of the predictions'
    tables (``%.6g``, :func:`robomill.io.write_table`), the slack of the interval test, so a
    point interval (one run identified the quantity) admits the outcome it was identified
    from (the waviness of that run itself: δq = A / |nᵀJ|, then A = δq |nᵀJ|)."""
    return 0.5 * 10.0 ** (np.floor(np.log10(abs(x))) - 5) if np.isfinite(x) and x else 0.0


Outcome = tuple[str, str, pd.Series, str]
"""An outcome source: quantity, unit, the outcomes indexed by cut, and where they come from."""


def _outcomes(runs: list[RunOutcomes], peaks,
              min_cycles: float = WAVINESS_MIN_CYCLES) -> list[Outcome]:
    """Every force, deflection and waviness outcome source of ``runs``, first preferred for a
    cut and quantity. The waviness is read at the gear lines the study's tracker peaks
    attributed (those the prediction carries, :func:`waviness_elements`), on the loaded
    passes."""
    out: list[Outcome] = []
    elements = waviness_elements(peaks)
    for run in runs:
        if _present(run.mean_forces):
            out.append(("force", "N", force_outcomes(run.mean_forces),
                        run.path(catalogue.artefact("forces.mean_forces"))))
        if _present(run.deflection):
            for name, series in deflection_outcomes(run.deflection).items():
                out.append((name, "um", series,
                            run.path(catalogue.artefact("straightness.deflection"))))
        if _present(run.run_gears) and run.profiles is not None:
            out.append(("waviness", "um",
                        waviness_outcomes(elements, run.run_gears, run.profiles,
                                          min_cycles=min_cycles,
                                          skip_runs=air_runs(run.deflection)),
                        run.path(catalogue.artefact("straightness.profiles"))))
    return out


def _stabilities(runs: list[RunOutcomes],
                 chatter_fraction_of_mean: float) -> list[tuple[pd.Series, str]]:
    """The stability outcome sources of ``runs``, first preferred: each run's chatter verdicts,
    else its force spectrum."""
    out = []
    for run in runs:
        if _present(run.verdicts):
            out.append((verdict_stability(run.verdicts),
                        run.path(catalogue.artefact("chatter.verdicts"))))
        elif _present(run.force_peaks) and _present(run.mean_forces):
            out.append((spectrum_stability(run.force_peaks, run.mean_forces,
                                           chatter_fraction_of_mean),
                        run.path(catalogue.artefact("forces.peaks"))))
    return out


def check_table(predicted: pd.DataFrame, *, study: RunOutcomes | None = None,
                planned_run: RunOutcomes | None = None, peaks: pd.DataFrame | None = None,
                identified_cuts=(), tolerance: float = 0.25,
                chatter_fraction_of_mean: float = schema_default(
                    "plan", "chatter_fraction_of_mean"),
                waviness_min_cycles: float = WAVINESS_MIN_CYCLES) -> pd.DataFrame:
    """Rows :data:`CHECK_COLUMNS` for every predicted cut with an outcome (the ``stability``
    encoding in the module's docstring): one row per cut and quantity, its outcome from the
    first source that has the cut: the planned cuts' own run, then the study's.

    Parameters
    ----------
    predicted
        Rows with ``cut`` and the prediction columns (``force_N``, ``force_low_N``,
        ``force_high_N``, ``waviness_um``, ``stability_margin``, ``deflection_normal_um``, …):
        ``plan.csv`` and ``study_cuts.csv``.
    study
        The study's own run (``folder`` ""): its outcomes judge the study's cuts.
    planned_run
        The outcomes of the planned cuts' own pipeline run
        (``snakemake all --configfile results/plan/next/config.yaml``).
    peaks
        ``results/straightness/peaks.csv`` of the study: its gear-attributed lines are the
        elements whose waviness is read (:func:`waviness_elements`).
    identified_cuts
        The cuts whose data identified the models (the study's own): their rows are
        ``in_sample``.
    """
    runs = [r for r in (planned_run, study) if r is not None]
    outcomes = _outcomes(runs, peaks, waviness_min_cycles)
    stabilities = _stabilities(runs, chatter_fraction_of_mean)
    rows = []
    for _, r in predicted.iterrows():
        cut = str(r["cut"])
        done = set()
        for name, unit, series, source in outcomes:
            if cut not in series.index or f"{name}_{unit}" not in r or name in done:
                continue
            p = float(r[f"{name}_{unit}"])
            if not np.isfinite(p):  # no prediction, no row
                continue
            done.add(name)
            lo, hi = float(r[f"{name}_low_{unit}"]), float(r[f"{name}_high_{unit}"])
            o = float(series[cut])
            inside = bool(lo - _rounding(lo) <= o <= hi + _rounding(hi))
            rows.append({"cut": cut, "quantity": name, "unit": unit, "predicted": p,
                         "low": lo, "high": hi, "outcome": o, "within_interval": inside,
                         "within_tolerance": bool(abs(o - p) <= tolerance * abs(o)),
                         "held": inside, "source": source})
        for series, source in stabilities:
            if cut in series.index:
                row = _stability_row(cut, r, float(series[cut]), source)
                if row is not None:
                    rows.append(row)
                break
    table = pd.DataFrame(rows, columns=CHECK_COLUMNS)
    table["in_sample"] = in_sample(table["cut"], identified_cuts)
    for col in ("within_interval", "within_tolerance", "held", "decisive"):
        table[col] = table[col].astype("boolean")
    return table


def check_summary(check: pd.DataFrame, tolerance: float = 0.25,
                  nominal_coverage: float = 0.95) -> dict[str, float]:
    """Chapter 7's numbers about ``check.csv``, over the planned cuts (``plan_*``) and the
    study's own: per quantity q the rows ``n_<q>``, those within the interval
    ``n_<q>_in_interval`` and within the tolerance ``n_<q>_in_tolerance`` (``_plan`` suffix:
    planned cuts only); for stability the cuts predicted stable (nominal margin > 0)
    ``n_predicted_stable`` and those of them stable in the outcome
    ``n_predicted_stable_stable`` (also with ``_plan``), and ``n_stability_agree`` (nominal
    verdict = outcome); ``tolerance_percent`` the relative tolerance; the out-of-sample and
    in-sample counts and the coverage against ``nominal_coverage``
    (:func:`robomill.plan.evidence.coverage_summary`); ``brier_score`` and ``n_brier``
    (:func:`brier_score`) and ``sharpness_<q>_percent`` (:func:`sharpness`)."""
    out: dict[str, float] = {"tolerance_percent": 100.0 * float(tolerance)}
    plan = check["cut"].astype(str).str.startswith("plan_")

    def true(col: pd.Series) -> pd.Series:
        return col.astype("boolean").fillna(False).astype(bool)

    for suffix, rows in (("", check), ("_plan", check[plan])):
        for q, g in rows.groupby("quantity"):
            out[f"n_{q}{suffix}"] = float(len(g))
            out[f"n_{q}_in_interval{suffix}"] = float(true(g["within_interval"]).sum())
            out[f"n_{q}_in_tolerance{suffix}"] = float(true(g["within_tolerance"]).sum())
        s = rows[rows["quantity"] == "stability"]
        pred = s["predicted"].astype(float) > 0
        out[f"n_predicted_stable{suffix}"] = float(pred.sum())
        out[f"n_predicted_stable_stable{suffix}"] = float(
            (pred & (s["outcome"].astype(float) >= 0.5)).sum())
        out[f"n_stability_agree{suffix}"] = float(true(s["within_tolerance"]).sum())
    out.update(coverage_summary(check, nominal_coverage))
    out["brier_score"], n = brier_score(check)
    out["n_brier"] = float(n)
    out.update(sharpness(check))
    out.update(decisive_summary(check))
    return out


def decisive_summary(check: pd.DataFrame) -> dict[str, float]:
    """How hard the stability rows tested the critical depth, over the judged stability rows
    out of sample (``_oos``) and in sample (``_in``): ``n_stability_decisive<s>``, those cut
    at a depth inside the predicted a_crit interval (where the outcome bounds a_crit inside
    the interval rather than confirming a verdict the interval had already made),
    ``n_stability_decisive_agree<s>`` those of them whose nominal a_crit lay on the outcome's
    side, and ``median_depth_over_a_crit<s>`` the median depth over the nominal critical
    depth (≪ 1: the rows test only the sign of the margin)."""
    out: dict[str, float] = {}
    if "decisive" not in check:
        return out
    s = check[(check["quantity"] == "stability") & check["outcome"].astype(float).notna()]
    flag = s["in_sample"].astype("boolean").fillna(False).astype(bool)
    for suffix, rows in (("_oos", s[~flag]), ("_in", s[flag])):
        dec = rows["decisive"].astype("boolean").fillna(False).astype(bool)
        agree = rows["within_tolerance"].astype("boolean").fillna(False).astype(bool)
        ratio = rows["depth_over_a_crit"].astype(float)
        out[f"n_stability_decisive{suffix}"] = float(dec.sum())
        out[f"n_stability_decisive_agree{suffix}"] = float((dec & agree).sum())
        out[f"median_depth_over_a_crit{suffix}"] = (
            float(ratio[np.isfinite(ratio)].median()) if np.isfinite(ratio).any() else np.nan)
    return out


def brier_score(check: pd.DataFrame) -> tuple[float, int]:
    """Brier score of ``p_stable`` over the judged stability rows (outcome 0 or 1) that have a
    probability, and their count (NaN, 0 without any)."""
    if "p_stable" not in check:
        return float("nan"), 0
    s = check[check["quantity"] == "stability"]
    p = s["p_stable"].astype(float)
    o = s["outcome"].astype(float)
    ok = np.isfinite(p) & np.isfinite(o)
    n = int(ok.sum())
    return (float(np.mean((p[ok] - o[ok]) ** 2)) if n else float("nan")), n


def sharpness(check: pd.DataFrame) -> dict[str, float]:
    """``sharpness_<q>_percent``: per interval quantity the median of
    (high − low)/(2 |predicted|) × 100 over its rows with a finite prediction; also over the
    out-of-sample rows alone (``sharpness_<q>_oos_percent``). For stability (q = ``stability``)
    the interval is the critical depth's, (a_crit_high − a_crit_low)/(2 a_crit), over the
    judged rows whose interval is bounded (``n_stability_bounded``); ``n_stability_unbounded``
    counts the judged rows left out because an end of their interval is infinite (no chatter
    at any depth in some member); both also ``_oos``."""
    out = {}
    oos = ~check["in_sample"].astype("boolean").fillna(False).astype(bool)
    for suffix, part in (("", check), ("_oos", check[oos])):
        for q, g in part[part["quantity"] != "stability"].groupby("quantity"):
            p = g["predicted"].astype(float).abs()
            hw = (g["high"].astype(float) - g["low"].astype(float)) / 2
            ok = np.isfinite(p) & np.isfinite(hw) & (p > 0)
            if ok.any():
                out[f"sharpness_{q}{suffix}_percent"] = float(100 * np.median(hw[ok] / p[ok]))
        g = part[(part["quantity"] == "stability") & part["outcome"].astype(float).notna()]
        if "a_crit_mm" not in g or g.empty:
            continue
        a = g["a_crit_mm"].astype(float)
        lo, hi = g["a_crit_low_mm"].astype(float), g["a_crit_high_mm"].astype(float)
        bounded = np.isfinite(lo) & np.isfinite(hi) & np.isfinite(a) & (a > 0)
        out[f"n_stability_bounded{suffix}"] = float(bounded.sum())
        out[f"n_stability_unbounded{suffix}"] = float((~bounded & np.isfinite(a)).sum())
        if bounded.any():
            hw = (hi[bounded] - lo[bounded]) / (2 * a[bounded])
            out[f"sharpness_stability{suffix}_percent"] = float(100 * np.median(hw))
    return out


def summary_table(summary: dict[str, float]) -> pd.DataFrame:
    """:func:`check_summary` as ``results/plan/check_summary.csv`` (``key, value``)."""
    return pd.DataFrame({"key": list(summary), "value": list(summary.values())})
