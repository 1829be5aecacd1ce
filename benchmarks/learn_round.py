"""`make learn-round`: a learn round on the default study, as docs/usage.md tells a lab to run
it, and the narrowing of the production plan's binding interval it measured.

In a working folder: plan with ``purpose: learn`` and at most ``LEARN_CUTS`` cuts
(``snakemake -j2 plan``), keep its
``binding.csv`` (the production plan's binding interval before), cut the learn cuts on the
virtual cell (``snakemake -j2 all --configfile results/plan/next/config.yaml``), keep their raw
folder, then plan with ``purpose: production`` from the larger study (``data.raw_dirs``: the
study's folder and the learn cuts', ``plan.binding_before``: the kept file). Writes
``learn_round.csv`` (the production plan's ``binding.csv``: before, now, ``width_same_cut``,
``narrowing``; ``a_crit_*``: the critical depth's interval at the binding cut, the one the
learn cuts aim at, and its narrowing at the same cut), ``learn_round_plan.csv`` (the learn
cuts, their reasons, expected narrowing and verdicts: each cut's as the plan takes it, and
each recording's) and ``learn_round_check_summary.csv`` (the production plan's check, with
the Brier score of ``p_stable`` over every judged cut) under ``--out``.

``--members N`` runs the round with N members of the stability model in both requests
(``stability.members``; default: ``plan.yaml``'s), to see whether the narrowing holds with
more members than the default request draws.
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import pandas as pd
import yaml
from studyloop import REPO, out_and_work, snakemake

from robomill.plan.evidence import verdict_stability


def _snakemake(work: Path, target: str, *configfiles: Path) -> None:
    snakemake(work, target, ["config.yaml", *configfiles])


LEARN_CUTS = 4
"""A learn round is at most this many cuts (the default request's ``n_cuts`` is the production
plan's)."""


def _request(work: Path, purpose: str, members: int | None = None) -> None:
    req = yaml.safe_load((REPO / "plan.yaml").read_text())
    req["purpose"] = purpose
    if members:
        req["stability"]["members"] = int(members)
    if purpose == "learn":
        req["n_cuts"] = min(int(req["n_cuts"]), LEARN_CUTS)
    (work / "plan.yaml").write_text(yaml.safe_dump(req, sort_keys=False))


def summary_line(binding: pd.DataFrame, learn: pd.DataFrame) -> str:
    """One line: the critical depth's interval at the earlier binding cut before and after,
    its narrowing, the binding prediction's, and the round's verdicts."""
    b, n = binding.iloc[0], binding.iloc[-1]
    counts = learn["verdict"].value_counts().to_dict()
    return (f"binding cut {b['cut']} ({b['spindle_rpm']:g} rpm): a_crit "
            f"[{b['a_crit_low_mm']:.4g}, {b['a_crit_high_mm']:.4g}] mm (width "
            f"{b['a_crit_width_mm']:.4g}) -> width {n['a_crit_width_same_cut_mm']:.4g} mm at "
            f"the same cut: narrowing {100 * n['a_crit_narrowing']:.1f} %; binding "
            f"{b['constraint']} width {b['width']:.4g} -> {n['width_same_cut']:.4g}: "
            f"narrowing {100 * n['narrowing']:.1f} %; verdicts {counts}")


def main(argv: list[str] | None = None) -> int:
    import argparse

    ap = argparse.ArgumentParser(add_help=False)
    ap.add_argument("--members", type=int, default=None)
    known, rest = ap.parse_known_args(argv)
    out, work, remove = out_and_work(__doc__, "learn_round", rest)
    _request(work, "learn", known.members)
    _snakemake(work, "plan")
    shutil.copy(work / "results/plan/binding.csv", work / "binding_before.csv")
    learn = pd.read_csv(work / "results/plan/plan.csv")
    _snakemake(work, "all", work / "results/plan/next/config.yaml")
    raw = work / "learn_raw"
    shutil.rmtree(raw, ignore_errors=True)
    shutil.copytree(work / "results/plan/next/run/results/synthetic/raw", raw)
    verdicts = pd.read_csv(work / "results/plan/next/run/results/chatter/verdicts.csv")
    # each cut's verdict as the plan takes it (chatter in any recording, else stable or
    # forced: stable by evidence), and its recordings' verdicts
    per_cut = verdict_stability(verdicts)
    learn["verdict"] = [{1.0: "stable", 0.0: "chatter"}.get(per_cut.get(c), "undetermined")
                        for c in learn["cut"].astype(str)]
    learn["recordings"] = [
        "; ".join(f"{r.kind}: {r.verdict}" + (f" at {r.chatter_hz:.4g} Hz"
                                              if pd.notna(r.chatter_hz) else "")
                  for r in verdicts[verdicts["cut"].astype(str) == c].itertuples())
        for c in learn["cut"].astype(str)]
    _request(work, "production", known.members)
    (work / "round.yaml").write_text(yaml.safe_dump(
        {"data": {"raw_dirs": ["results/synthetic/raw", str(raw)]},
         "plan": {"binding_before": str(work / "binding_before.csv")}}))
    _snakemake(work, "plan", work / "round.yaml")
    binding = pd.read_csv(work / "results/plan/binding.csv")
    binding.to_csv(out / "learn_round.csv", index=False)
    cols = [c for c in ("cut", "placement", "direction", "spindle_rpm", "depth_mm",
                        "feed_mm_s", "reason", "learn_target", "expected_narrowing", "p_stable",
                        "a_crit_low_mm", "a_crit_mm", "a_crit_high_mm", "verdict",
                        "recordings") if c in learn]
    learn[cols].to_csv(out / "learn_round_plan.csv", index=False)
    check = work / "results/plan/check_summary.csv"
    if check.exists():
        shutil.copy(check, out / "learn_round_check_summary.csv")
    with pd.option_context("display.width", 200, "display.max_columns", 30,
                           "display.max_colwidth", 120):
        print(learn[cols].to_string(index=False))
        print(binding.T.to_string())
    print(summary_line(binding, learn))
    if remove:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
