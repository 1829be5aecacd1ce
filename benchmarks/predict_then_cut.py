"""Predict, then cut: cuts the study never made, predicted with ``robomill predict`` from a
study's plan and then cut on the virtual cell as their own study, on any study (the issue's
out-of-sample test: "other sets will be tried").

The set: at each of three speeds (12 000, 20 000 and 28 000 rpm) and both feed directions (px,
py), one probe (0.5 mm) gives the predicted critical depth a_crit, and two cuts are made at 0.5
and 1.8 times it (one on each side of the predicted boundary), at 5 mm/s, laid out on the
block's top face beside the request's placement box (its lowest corner, 25 mm apart along x, 30
mm along y); ``--feed-per-tooth-mm``: at that feed per tooth instead (the request's flutes). The
cuts are predicted (``robomill predict``, the plan's code) and cut by the virtual cell with the
study's own configuration (``--config``, the files the study was run with, in order) and the
experiment of the plan's next run (``results/plan/next/config.yaml``, its cuts replaced), in
their own folder, recorded by the instruments that recorded the study's own cuts
(``--recordings``: also by those the next run adds, an accelerometer or microphone with its air
passes); the verdicts are read from that run's ``results/chatter/verdicts.csv`` (a cut is
chatter when any of its records is). Printed and written (``<out>/predict_then_cut.csv``): per
judged cut its depth, the predicted a_crit and interval, ``p_stable``, the verdict, whether the
nominal prediction agrees, and ``unsafe`` (predicted stable, judged chatter); the tally also
gives the Brier score of ``p_stable`` over the set.

    .venv/bin/python benchmarks/predict_then_cut.py STUDY --config config.yaml --out DIR \
        [--recordings] [--speeds-rpm 12000,20000,28000] [--factors 0.5,1.8] \
        [--feed-per-tooth-mm 0.025]

(``--cuts FILE``: any YAML list of cuts, predicted and cut the same way;
``--speeds-rpm`` and ``--factors``: another set of the same kind, at other speeds or at other
multiples of each predicted limit.)

``STUDY``: a study folder whose plan was made (``snakemake -j2 plan``).
``tests/test_pipeline_predict_oos.py`` runs the same procedure on the tiny study.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import yaml
from studyloop import REPO

SPEEDS_RPM = (12000.0, 20000.0, 28000.0)
DIRECTIONS = ("px", "py")
FACTORS = (("below", 0.5), ("above", 1.8))
FEED_MM_S = 5.0
PROBE_DEPTH_MM = 0.5


def positive_floats(text: str) -> list[float]:
    """An option's comma-separated positive numbers (``argparse`` type: one line, never a
    traceback, on anything else)."""
    try:
        values = [float(x) for x in str(text).split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected comma-separated positive numbers, got {text!r}") from None
    if not values or not all(np.isfinite(v) and v > 0 for v in values):
        raise argparse.ArgumentTypeError(f"expected comma-separated positive numbers, got {text!r}")
    return values


def positive_float(text: str) -> float:
    """An option's one positive number (``argparse`` type: one line on anything else)."""
    values = positive_floats(text)
    if len(values) != 1:
        raise argparse.ArgumentTypeError(f"expected one positive number, got {text!r}")
    return values[0]


class SetError(Exception):
    """A study the set cannot be predicted or cut from (one line naming the file)."""


def layout_origin_mm(study: Path) -> tuple[np.ndarray, float]:
    """The lowest corner of the study's request placement box [mm] and the request's cut
    length [mm] (the plan's record, :func:`robomill.plan.inputs.load_recorded`)."""
    from robomill.errors import RawDataError
    from robomill.plan.inputs import load_recorded
    from robomill.plan.request import PlanRequestError

    try:
        req = load_recorded(study).req
    except (RawDataError, PlanRequestError) as exc:
        raise SetError(str(exc)) from exc
    return np.asarray(req.placements_mm, float).min(axis=0), float(req.length_mm)


def placed_cut(origin: tuple[np.ndarray, float], cid: str, rpm: float, depth_mm: float,
               direction: str, i: int, feed_mm_s: float = FEED_MM_S) -> dict:
    """Cut ``i`` of the set: its manifest keys, started beside the request's placement box
    (``origin``, :func:`layout_origin_mm`: its lowest corner less half the cut's length along
    x, 25 mm apart along x, 30 mm along y, six per row), ``depth_mm`` below the top face
    (``depth_mm`` rounded to the µm in the cut's keys, the start's height from the depth as
    given)."""
    lo, length_mm = origin
    depth = float(depth_mm)
    start = [float(lo[0] - length_mm / 2 + 25.0 * (i % 6)), float(lo[1] + 30.0 * (i // 6)),
             float(lo[2] - depth)]
    return {"id": cid, "spindle_rpm": float(rpm), "depth_mm": float(round(depth, 3)),
            "feed_mm_s": float(round(feed_mm_s, 4)), "direction": direction,
            "start_mm": start}


def predict_cuts(study: Path, cuts: list[dict], path: Path) -> pd.DataFrame:
    """``robomill predict STUDY path`` of ``cuts`` (written to ``path``, a YAML cut list)."""
    from robomill.cli import main

    path.write_text(yaml.safe_dump(cuts))
    out = path.with_suffix(".csv")
    if main(["predict", str(study), str(path), "--out", str(out)]) != 0:
        raise SetError(f"{path}: robomill predict failed on these cuts (its line above)")
    return pd.read_csv(out)


def feed_mm_s(rpm: float, feed_per_tooth_mm: float | None = None, flutes: int | None = None
              ) -> float:
    """The set's feed [mm/s] at a speed [rpm]: :data:`FEED_MM_S`, or ``feed_per_tooth_mm`` on
    a tool of ``flutes``, f = f_z N n/60."""
    if feed_per_tooth_mm is None:
        return FEED_MM_S
    return float(feed_per_tooth_mm) * int(flutes) * float(rpm) / 60.0


def boundary_set(study: Path, work: Path, speeds=SPEEDS_RPM, directions=DIRECTIONS,
                 factors=FACTORS, feed_per_tooth_mm: float | None = None
                 ) -> tuple[list[dict], pd.DataFrame]:
    """The set (module docstring) and its predictions (indexed by cut); its cut lists and
    their predictions are written in ``work``."""
    work.mkdir(parents=True, exist_ok=True)
    origin = layout_origin_mm(study)
    flutes = None
    if feed_per_tooth_mm is not None:
        from robomill.plan.inputs import load_recorded

        flutes = int(load_recorded(study).req.flutes)

    def feed(rpm):
        return feed_mm_s(rpm, feed_per_tooth_mm, flutes)
    pairs = [(n, d) for n in speeds for d in directions]
    probe = [placed_cut(origin, f"probe_{k}", n, PROBE_DEPTH_MM, d, k, feed(n))
             for k, (n, d) in enumerate(pairs)]
    a = predict_cuts(study, probe, work / "probe.yaml")["a_crit_mm"].to_numpy(float)
    if not np.all(np.isfinite(a) & (a > 0)):
        raise SetError(f"{work / 'probe.csv'}: expected a finite positive a_crit_mm at every "
                       f"probe, got {np.round(a, 4).tolist()}")
    cuts = []
    for (n, d), a_k in zip(pairs, a, strict=True):
        for side, f in factors:
            cuts.append(placed_cut(origin, f"oos_{int(n / 1000)}k_{d}_{side}", n, f * a_k, d,
                                   len(cuts), feed(n)))
    return cuts, predict_cuts(study, cuts, work / "oos.yaml").set_index("cut")


def cut_on_cell(study: Path, cuts: list[dict], configfiles: list[Path], run: Path, *,
                recordings: bool = False) -> pd.Series:
    """The virtual cell cuts ``cuts`` as their own study in ``run`` (the study's
    ``configfiles`` and its next run's experiment with the cuts replaced: recorded by the
    instruments that recorded the study's own cuts, whose verdicts the model was weighted
    by; ``recordings``: also by the next run's recordings, the accelerometer or microphone
    and its air passes); the chatter verdicts per cut (1 stable or forced, 0 chatter, NaN
    undetermined)."""
    from robomill.plan.evidence import read_verdicts, verdict_stability

    next_config = study / "results/plan/next/config.yaml"
    if not next_config.is_file():
        raise SetError(f"{next_config}: not found (the plan writes it: snakemake -j2 plan)")
    nxt = yaml.safe_load(next_config.read_text())
    overlay = {"workdir": str(run),
               "experiment": {**{k: v for k, v in nxt["experiment"].items() if k != "cuts"},
                              "cuts": cuts}}
    synth = nxt.get("synth") or {}
    overlay["synth"] = {}
    if (synth.get("process") or {}).get("reference_point_mm") is not None:
        # the study's cell: its modes planted where the study's impact test was made, not
        # at the centre of these cuts (the cell's default for a study that does not say)
        overlay["synth"]["process"] = {
            "reference_point_mm": synth["process"]["reference_point_mm"]}
    if recordings and synth.get("recordings"):
        overlay["synth"]["recordings"] = synth["recordings"]
    run.mkdir(parents=True, exist_ok=True)
    (run.parent / "oos_overlay.yaml").write_text(yaml.safe_dump(overlay))
    cmd = [str(Path(sys.executable).with_name("snakemake")), "-s", str(REPO / "Snakefile"),
           "--directory", str(run), "--configfile", *[str(c) for c in configfiles],
           str(run.parent / "oos_overlay.yaml"), "-j2", "results/chatter/verdicts.csv"]
    done = subprocess.run(cmd, cwd=run.parent, capture_output=True, text=True, timeout=1800)
    if done.returncode != 0:
        raise SetError(f"{run}: the cell's run failed (its log: {run}/.snakemake/log):\n"
                       + done.stderr[-4000:])
    return verdict_stability(read_verdicts(run / "results/chatter/verdicts.csv"))


def agreement_table(pred: pd.DataFrame, stable: pd.Series) -> pd.DataFrame:
    """Per judged cut: depth, predicted a_crit and interval, ``p_stable``, ``stable`` (the
    verdict), ``agree`` (the nominal prediction's side) and ``unsafe`` (predicted stable,
    judged chatter)."""
    judged = stable.dropna()
    t = pred.loc[judged.index, ["depth_mm", "a_crit_mm", "a_crit_low_mm", "a_crit_high_mm",
                                "p_stable"]].assign(stable=judged)
    predicted = t["a_crit_mm"] > t["depth_mm"]
    t["agree"] = predicted == (t["stable"] >= 0.5)
    t["unsafe"] = predicted & (t["stable"] < 0.5)
    return t


def set_summary(t: pd.DataFrame) -> dict:
    """The set's tally (:func:`agreement_table`): the judged cuts, those the nominal prediction
    got right, those predicted stable and judged chatter, and the Brier score of ``p_stable``
    against the verdicts (:func:`robomill.plan.check.brier_score`, the score chapter 7 gives
    the study's own cuts: 0 perfect, 0.25 a coin), the calibration of the probabilities
    beside the nominal's tally."""
    from robomill.plan.check import brier_score

    brier, _ = brier_score(pd.DataFrame({"quantity": "stability", "p_stable": t["p_stable"],
                                         "outcome": t["stable"]}))
    return {"n_judged": len(t), "n_agree": int(t["agree"].sum()),
            "n_unsafe": int(t["unsafe"].sum()), "brier_score": round(brier, 4)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("study", type=Path)
    ap.add_argument("--config", nargs="+", type=Path, required=True,
                    help="the study's configuration files, in order (relative: to the repo)")
    ap.add_argument("--out", type=Path, default=Path("results/benchmarks"))
    ap.add_argument("--work", type=Path, help="working folder (default <out>/predict_then_cut)")
    ap.add_argument("--speeds-rpm", type=positive_floats, default=list(SPEEDS_RPM),
                    help="the set's spindle speeds, comma-separated")
    ap.add_argument("--factors", type=positive_floats, default=None,
                    help="depths as multiples of each probe's predicted critical depth, "
                    "comma-separated (default 0.5,1.8: cuts named below/above; others are "
                    "named by their percentage, e.g. oos_12k_px_250pct)")
    ap.add_argument("--feed-per-tooth-mm", type=positive_float, default=None,
                    help="the cuts' feed per tooth [mm] on the request's tool (default: "
                    f"{FEED_MM_S:g} mm/s at every speed)")
    ap.add_argument("--cuts", type=Path,
                    help="a YAML cut list (the manifest's cut keys) to predict and cut instead "
                    "of the set")
    ap.add_argument("--recordings", action="store_true",
                    help="also record the cuts as the plan's next run does (accelerometer or "
                    "microphone with air passes) and judge those records too")
    args = ap.parse_args(argv)
    study = args.study.resolve()
    work = (args.work or args.out / "predict_then_cut").resolve()
    work.mkdir(parents=True, exist_ok=True)
    configs = [c if c.is_absolute() else REPO / c for c in args.config]
    missing = [str(c) for c in configs if not c.is_file()]
    if missing:
        ap.error(f"--config: no such file: {', '.join(missing)}")
    factors = (FACTORS if args.factors is None else
               [(f"{round(100 * f)}pct", f) for f in args.factors])
    if len({name for name, _ in factors}) < len(factors):
        ap.error(f"--factors: two factors name the same cut at the percent: {args.factors}")
    if args.cuts is not None and not args.cuts.is_file():
        ap.error(f"--cuts: no such file: {args.cuts}")
    try:
        if args.cuts is not None:
            try:
                cuts = yaml.safe_load(args.cuts.read_text())
            except yaml.YAMLError as exc:
                raise SetError(f"{args.cuts}: not YAML ({str(exc).splitlines()[0]})") from exc
            if not isinstance(cuts, list) or not all(isinstance(c, dict) for c in cuts):
                raise SetError(f"{args.cuts}: expected a YAML list of cuts (manifest keys)")
            pred = predict_cuts(study, cuts, work / "oos.yaml").set_index("cut")
        else:
            cuts, pred = boundary_set(study, work, speeds=args.speeds_rpm, factors=factors,
                                      feed_per_tooth_mm=args.feed_per_tooth_mm)
        t = agreement_table(pred, cut_on_cell(study, cuts, configs, work / "run",
                                              recordings=args.recordings))
    except SetError as exc:
        print(f"predict_then_cut: {exc}", file=sys.stderr)
        return 1
    args.out.mkdir(parents=True, exist_ok=True)
    t.to_csv(args.out / "predict_then_cut.csv")
    print(t.round(3).to_string())
    tally = set_summary(t)
    print(f"{tally['n_agree']} of {tally['n_judged']} judged cuts predicted right "
          f"({len(cuts)} cut); {tally['n_unsafe']} predicted stable and judged chatter; "
          f"Brier score of p_stable {tally['brier_score']:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
