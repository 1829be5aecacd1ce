"""`make plan-check`: the plan checked through the next run's files, on the default study and on
examples/other_cell, and the out-of-sample coverage of the stated intervals pooled over both.

For each study, in its own working folder: ``snakemake -j2 plan`` (the study and its plan),
``snakemake -j2 all --configfile results/plan/next/config.yaml`` (the virtual cell cuts the
planned cuts and writes their instrument files under ``results/plan/next/run/``), and
``snakemake -j2 plan`` again (``check.csv`` from those files). The pooled coverage is
:func:`robomill.plan.evidence.coverage_summary` over both studies' ``check.csv`` rows: the share
of out-of-sample rows inside their stated interval against the nominal level, with the count
range the nominal level gives 95 % of the time. Written to ``plan_coverage.csv`` (one row per
study and one pooled) and each study's ``misses.csv`` copied beside it.

Then, on each study's plan, predict then cut (``benchmarks/predict_then_cut.py``): cuts the
study never made, on both sides of the predicted boundary at three speeds and both feed
directions, predicted with ``robomill predict`` and cut by the virtual cell as their own study:
``predict_then_cut_<study>.csv`` (per judged cut) and ``predict_then_cut.csv`` (per study: the
judged cuts, those the nominal prediction got right, those predicted stable that were judged
chatter, and the Brier score of ``p_stable`` over them; beside them the same tally of the
candidate two-regime model with the edge force's switching, ``n_agree_two_regime`` and
``n_unsafe_two_regime``, per cut in ``two_regime_<study>.csv``, which the planner does not use
yet: ``benchmarks/modes_at_cuts.py``). The set is cut twice: at the check's
5 mm/s (chips of 4–13 µm, near the study's own 1–11 µm) and at a production chip of
:data:`PRODUCTION_FEED_PER_TOOTH_MM` on the request's tool
(``predict_then_cut_<study>_production.csv``; column ``feed``).

    .venv/bin/python benchmarks/plan_coverage.py [--out DIR] [--work DIR] [--overlay FILE ...]

``--overlay``: configuration files merged over each study's own, last (the same files for
both studies and for their predict-then-cut runs): the same loop on another truth of the
virtual cell, e.g. a file holding ``synth: {process: {robot_modes: eigen}}`` (the robot's
modes from the joints' eigenproblem at every pose instead of the planted law).
"""

from __future__ import annotations

import argparse
import shutil
import sys
import time
from pathlib import Path

import pandas as pd
from predict_then_cut import agreement_table, boundary_set, cut_on_cell, set_summary
from studyloop import REPO, out_and_work, snakemake

STUDIES = {
    "default": (["config.yaml"], "plan.yaml"),
    "other_cell": (["config.yaml", "examples/other_cell/config.yaml"],
                   "examples/other_cell/plan.yaml"),
}


def study_configs(name: str, overlays: list[Path]) -> list[Path]:
    """The configuration files of study ``name`` in order (absolute), ``overlays`` last."""
    return [REPO / c for c in STUDIES[name][0]] + [Path(o).resolve() for o in overlays]


def run_study(name: str, root: Path, overlays: list[Path] = ()) -> pd.DataFrame:
    """One study's loop (module docstring) with ``overlays`` over its configuration; its
    ``check.csv`` with a ``study`` column."""
    _, request = STUDIES[name]
    configs = study_configs(name, list(overlays))
    work = root / name
    work.mkdir(parents=True, exist_ok=True)
    shutil.copy(REPO / request, work / "plan.yaml")  # the request, as a lab keeps it
    snakemake(work, "plan", configs)
    snakemake(work, "all", configs + [work / "results/plan/next/config.yaml"])
    snakemake(work, "plan", configs)
    check = pd.read_csv(work / "results/plan/check.csv")
    check.insert(0, "study", name)
    return check


PRODUCTION_FEED_PER_TOOTH_MM = 0.025
"""The production set's chip [mm per tooth]: inside the 20–50 µm a production request offers
(the study's own cuts: 1–11 µm)."""


def predict_then_cut_row(name: str, root: Path, out: Path, overlays: list[Path] = (),
                         feed_per_tooth_mm: float | None = None) -> dict:
    """Predict then cut on one study's plan (module docstring), at the set's 5 mm/s or at
    ``feed_per_tooth_mm``; its summary row."""
    study = root / name
    tag = "" if feed_per_tooth_mm is None else "_production"
    work = study / f"predict_then_cut{tag}"
    cuts, pred = boundary_set(study, work, feed_per_tooth_mm=feed_per_tooth_mm)
    configs = study_configs(name, list(overlays))
    t = agreement_table(pred, cut_on_cell(study, cuts, configs, work / "run"))
    t.to_csv(out / f"predict_then_cut_{name}{tag}.csv")
    feed = ("5 mm/s" if feed_per_tooth_mm is None
            else f"{1e3 * feed_per_tooth_mm:g} um per tooth")
    return {"study": name, "feed": feed, "n_cut": len(cuts), **set_summary(t),
            **two_regime_row(study, work, configs, out / f"two_regime_{name}{tag}.csv")}


def two_regime_row(study: Path, work: Path, configs: list[Path], out_csv: Path) -> dict:
    """The same judged cuts predicted by the candidate model the planner does not use yet: its
    nominal member's axial form with the edge force's switching, read in two regimes
    (``benchmarks/modes_at_cuts.py --planner-only``, per cut in ``out_csv``): the cuts it
    gets right and those it predicts stable that were judged chatter."""
    from modes_at_cuts import main as modes_at_cuts
    from modes_at_cuts import tally

    rc = modes_at_cuts([str(study), "--cuts", str(work / "oos.yaml"), "--verdicts",
                        str(work / "run/results/chatter/verdicts.csv"), "--config",
                        *map(str, configs), "--planner-only", "--out", str(out_csv)])
    if rc != 0 or not out_csv.is_file():
        return {"n_agree_two_regime": None, "n_unsafe_two_regime": None}
    n_agree, n_unsafe = tally(pd.read_csv(out_csv), "Pa_two_regime_mm")
    return {"n_agree_two_regime": n_agree, "n_unsafe_two_regime": n_unsafe}


def main(argv: list[str] | None = None) -> int:
    from robomill.plan.evidence import coverage_case, coverage_summary
    from robomill.settings import schema_default

    ap = argparse.ArgumentParser(add_help=False)
    ap.add_argument("--overlay", nargs="+", type=Path, default=[])
    known, rest = ap.parse_known_args(argv)
    missing = [str(o) for o in known.overlay if not o.is_file()]
    if missing:
        print(f"plan_coverage: --overlay: no such file: {', '.join(missing)}", file=sys.stderr)
        return 2
    out, work, remove = out_and_work(__doc__, "plan_coverage", rest)
    nominal = float(schema_default("plan", "interval_level"))
    rows, checks = [], []
    for name in STUDIES:
        t0 = time.perf_counter()
        check = run_study(name, work, known.overlay)
        checks.append(check)
        shutil.copy(work / name / "results/plan/misses.csv", out / f"plan_misses_{name}.csv")
        s = coverage_summary(check, nominal)
        rows.append({"study": name, **_row(s, coverage_case(s)),
                     "seconds": round(time.perf_counter() - t0, 1)})
    pooled = coverage_summary(pd.concat(checks, ignore_index=True), nominal)
    rows.append({"study": "pooled", **_row(pooled, coverage_case(pooled)), "seconds": None})
    table = pd.DataFrame(rows)
    table.to_csv(out / "plan_coverage.csv", index=False)
    pd.concat(checks, ignore_index=True).to_csv(out / "plan_coverage_check.csv", index=False)
    print(table.to_string(index=False))
    cut = pd.DataFrame([predict_then_cut_row(name, work, out, known.overlay, fz)
                        for fz in (None, PRODUCTION_FEED_PER_TOOTH_MM) for name in STUDIES])
    cut.to_csv(out / "predict_then_cut.csv", index=False)
    print(cut.to_string(index=False))
    if remove:
        shutil.rmtree(work, ignore_errors=True)
    return 0


def _row(s: dict, case: str) -> dict:
    return {"n_judged_oos": s["n_judged_oos"], "n_held_oos": s["n_held_oos"],
            "coverage_oos_percent": s["coverage_oos_percent"],
            "nominal_coverage_percent": s["nominal_coverage_percent"],
            "held_range_low_oos": s["held_range_low_oos"],
            "held_range_high_oos": s["held_range_high_oos"], "case": case}


if __name__ == "__main__":
    sys.exit(main())
