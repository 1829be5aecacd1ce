"""`make learn-round`: a learn round on the default study, as docs/usage.md tells a lab to run
it, and the narrowing of the production plan's binding interval it measured.

In a working folder: plan with ``purpose: learn`` and at most ``LEARN_CUTS`` cuts
(``snakemake -j2 plan``), keep its
``binding.csv`` (the production plan's binding interval before), cut the learn cuts on the
virtual cell (``snakemake -j2 all --configfile results/plan/next/config.yaml``), keep their raw
folder, then plan with ``purpose: production`` from the larger study (``data.raw_dirs``: the
study's folder and the learn cuts', ``plan.binding_before``: the kept file). Writes
``learn_round.csv`` (the production plan's ``binding.csv``: before, now, ``width_same_cut``,
``narrowing``) and ``learn_round_plan.csv`` (the learn cuts, their reasons and verdicts) under
``--out``.
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import pandas as pd
import yaml
from studyloop import REPO, out_and_work, snakemake


def _snakemake(work: Path, target: str, *configfiles: Path) -> None:
    snakemake(work, target, ["config.yaml", *configfiles])


LEARN_CUTS = 4
"""A learn round is at most this many cuts (the default request's ``n_cuts`` is the production
plan's)."""


def _request(work: Path, purpose: str) -> None:
    req = yaml.safe_load((REPO / "plan.yaml").read_text())
    req["purpose"] = purpose
    if purpose == "learn":
        req["n_cuts"] = min(int(req["n_cuts"]), LEARN_CUTS)
    (work / "plan.yaml").write_text(yaml.safe_dump(req, sort_keys=False))


def main(argv: list[str] | None = None) -> int:
    out, work, remove = out_and_work(__doc__, "learn_round", argv)
    _request(work, "learn")
    _snakemake(work, "plan")
    shutil.copy(work / "results/plan/binding.csv", work / "binding_before.csv")
    learn = pd.read_csv(work / "results/plan/plan.csv")
    _snakemake(work, "all", work / "results/plan/next/config.yaml")
    raw = work / "learn_raw"
    shutil.rmtree(raw, ignore_errors=True)
    shutil.copytree(work / "results/plan/next/run/results/synthetic/raw", raw)
    verdicts = pd.read_csv(work / "results/plan/next/run/results/chatter/verdicts.csv")
    learn = learn.merge(verdicts[verdicts["kind"] == "force"][["cut", "verdict", "chatter_hz"]],
                        on="cut", how="left")
    _request(work, "production")
    (work / "round.yaml").write_text(yaml.safe_dump(
        {"data": {"raw_dirs": ["results/synthetic/raw", str(raw)]},
         "plan": {"binding_before": str(work / "binding_before.csv")}}))
    _snakemake(work, "plan", work / "round.yaml")
    binding = pd.read_csv(work / "results/plan/binding.csv")
    binding.to_csv(out / "learn_round.csv", index=False)
    cols = [c for c in ("cut", "placement", "spindle_rpm", "depth_mm", "feed_mm_s", "reason",
                        "learn_target", "expected_narrowing", "a_crit_low_mm", "a_crit_mm",
                        "a_crit_high_mm", "verdict", "chatter_hz") if c in learn]
    learn[cols].to_csv(out / "learn_round_plan.csv", index=False)
    with pd.option_context("display.width", 200, "display.max_columns", 30):
        print(learn[cols].to_string(index=False))
        print(binding.to_string(index=False))
    if remove:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
