"""The laptop budget of the whole study, measured on this machine in this run.

- a default ``snakemake -j2 all`` (full thesis scale, synthetic data) in an empty folder of
  this checkout, whose kernels and bytecode are compiled (the warm figure; a fresh clone's,
  caches cold, is :mod:`bench_fresh`'s): wall time, then the no-op rerun right after, then
  ``ch2 --forcerun ch2`` (one chapter's figures again) with the number of jobs it ran, then
  each chapter's ``--forcerun`` against the no-op rerun (every cell run and every figure
  drawn again);
- per rule, the largest wall time and peak RSS over its jobs (their ``benchmark:`` files);
- the floor (:mod:`floor`) of that run and of a fresh tiny study (``.test/config.yaml``):
  wall time, summed job time, summed work of the library calls, wall / floor;
- ``synth.sets`` scaling: the per-cut stages (``SCALE_TARGETS``) for 3 and 9 sets in fresh
  folders, total wall time, summed job time and the largest job RSS; the 3-set run is the
  baseline of the ratio (linear scaling gives 3.0 for the time and 1.0 for the RSS).

Set ``ROBOMILL_BENCH_STUDY=0`` to skip it (it takes about half an hour on 2 cores).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import yaml
from floor import floor_rows, floor_summary

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
SCALE_TARGETS = ["surface", "forces", "straightness"]
SCALE_SETS = (3, 9)
BUDGET_S, RSS_BUDGET_MB = 600.0, 2048.0
GOAL_ALL_S, GOAL_NOOP_S, GOAL_CHAPTER_S = 180.0, 2.0, 10.0
"""The goals (2 cores) for the default `all`, the no-op rerun and one chapter's ``--forcerun``,
stated beside the measured baselines (the floor of the same run, Snakemake's own start-up,
the no-op rerun)."""


def chapter_targets() -> dict[str, str]:
    """The chapter targets ``all`` builds and their page stems, in the chapter registry's
    order (``src/robomill/data/chapters.yaml``)."""
    from robomill.registry import chapters

    return {c.id: c.id for c in chapters() if c.in_all}


def _snakemake_version_s(repeats: int = 3) -> float:
    """Best of ``repeats`` wall times of `snakemake --version`: importing Snakemake and
    starting its command line, the least any `snakemake` call costs on this machine."""
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        subprocess.run([SNAKEMAKE, "--version"], capture_output=True, check=True)
        best = min(best, time.perf_counter() - t0)
    return best


def _snakemake(work: Path, config: Path, *targets: str, extra: tuple = ()) -> tuple[float, str]:
    # targets before the options: `--forcerun` takes every word after it, so
    # `--forcerun ch2 ch2` would force ch2 and leave the default target `all`
    t0 = time.perf_counter()
    proc = subprocess.run([SNAKEMAKE, "-s", str(REPO / "Snakefile"), "--directory", str(work),
                           "--configfile", str(config), "-j2", *targets, *extra],
                          capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode:
        raise RuntimeError(f"snakemake {' '.join(targets)} failed in {work}:\n"
                           f"{proc.stderr[-3000:]}")
    return wall, proc.stdout + proc.stderr


def _jobs_run(log: str) -> int:
    m = re.search(r"(\d+) of (\d+) steps \(100%\) done", log)
    return int(m.group(2)) if m else 0


def rule_table(work: Path) -> pd.DataFrame:
    """Per rule: jobs, largest and summed wall time [s], largest peak RSS [MB]."""
    rows = []
    root = work / "results/benchmarks/rules"
    for tsv in sorted(root.rglob("*.tsv")):
        df = pd.read_csv(tsv, sep="\t")
        rel = tsv.relative_to(root).with_suffix("")
        rows.append({"stage": rel.parts[0], "job": rel.as_posix(), "s": df["s"].max(),
                     "max_rss": pd.to_numeric(df["max_rss"], errors="coerce").max()})
    jobs = pd.DataFrame(rows)
    if jobs.empty:
        return jobs
    # rule = job path without the wildcard part (cut_<id>, case names, shards)
    jobs["rule"] = jobs["job"].str.replace(r"_[^/_]*\d[^/]*$", "", regex=True)
    return (jobs.groupby("rule").agg(jobs=("s", "size"), wall_max_s=("s", "max"),
                                     wall_sum_s=("s", "sum"), rss_max_mb=("max_rss", "max"))
            .reset_index())


def _config_with_sets(out: Path, sets: int) -> Path:
    cfg = yaml.safe_load((REPO / "config.yaml").read_text())
    cfg["synth"]["sets"] = int(sets)
    path = out / f"config_sets{sets}.yaml"
    path.write_text(yaml.safe_dump(cfg, sort_keys=False))
    return path


def run(out_dir: Path) -> list[dict]:
    if os.environ.get("ROBOMILL_BENCH_STUDY", "1") == "0":
        return []
    out_dir = Path(out_dir).resolve()
    rows: list[dict] = []

    def row(metric, value, unit, baseline=None, note=""):
        ratio = value / baseline if baseline else None
        rows.append({"benchmark": "study", "metric": metric, "value": value, "unit": unit,
                     "baseline": baseline, "ratio": ratio, "note": note})

    work = out_dir / "study_default"
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    cfg = REPO / "config.yaml"
    t_all, log = _snakemake(work, cfg, "all")
    n_all = _jobs_run(log)
    # the floor before the reruns below overwrite a job's records
    rows.extend(floor_rows("default", work / "results", t_all, cores=2))
    t_noop, log_noop = _snakemake(work, cfg, "all")
    t_ch2, log_ch2 = _snakemake(work, cfg, "ch2", extra=("--forcerun", "ch2"))
    # the chapters `all` made (not chapter 7, the plan, which is a target of its own)
    chapters = {ch: _snakemake(work, cfg, ch, extra=("--forcerun", ch))
                for ch, stem in chapter_targets().items()
                if (work / "results" / "chapters" / f"{stem}.html").exists()}
    rules = rule_table(work)
    rules.to_csv(out_dir / "rules.csv", index=False)
    tiny = out_dir / "study_tiny"
    shutil.rmtree(tiny, ignore_errors=True)
    tiny.mkdir(parents=True)
    t_tiny, _ = _snakemake(tiny, REPO / ".test" / "config.yaml", "all")
    rows.extend(floor_rows("tiny", tiny / "results", t_tiny, cores=2))
    shutil.rmtree(tiny, ignore_errors=True)
    floor_s = floor_summary(work / "results", t_all, cores=2)["floor_s"]
    row("warm: default `snakemake -j2 all` in an empty folder", t_all, "s", floor_s,
        f"{n_all} jobs; baseline: the floor of this run (summed work / 2 cores, floor.py); "
        f"the goal {GOAL_ALL_S:g} s, the laptop budget {BUDGET_S:g} s")
    t_version = _snakemake_version_s()
    row("no-op rerun of `all`", t_noop, "s", t_version,
        "baseline: `snakemake --version` in this run (Snakemake's own start-up); "
        f"the goal {GOAL_NOOP_S:g} s; "
        + ("nothing to do" if "Nothing to be done" in log_noop else "JOBS RAN"))
    row("`snakemake -j2 ch2 --forcerun ch2`", t_ch2, "s", t_all,
        f"{_jobs_run(log_ch2)} job(s) rerun; baseline: the whole study")
    for ch, (t_ch, log_ch) in chapters.items():
        row(f"`snakemake -j2 {ch} --forcerun {ch}`", t_ch, "s", t_noop,
            f"{_jobs_run(log_ch)} job(s) rerun; baseline: the no-op rerun of this run; "
            f"the goal {GOAL_CHAPTER_S:g} s")
    within = sum(t <= GOAL_CHAPTER_S for t, _ in chapters.values())
    if chapters:  # none where `all` made no page (a run that stopped early)
        row(f"chapters whose `--forcerun` takes at most {GOAL_CHAPTER_S:g} s", within,
            "chapters",
            len(chapters), "baseline: every chapter; the slowest "
            + max(chapters, key=lambda c: chapters[c][0]))
    row("largest job peak RSS", float(rules["rss_max_mb"].max()), "MB", RSS_BUDGET_MB,
        f"rule {rules.loc[rules['rss_max_mb'].idxmax(), 'rule']}; baseline: the 2 GiB budget")
    for r in rules.itertuples():
        row(f"rule {r.rule}: wall (largest job)", float(r.wall_max_s), "s", None,
            f"{r.jobs} job(s), {r.wall_sum_s:.1f} s in all")
        row(f"rule {r.rule}: peak RSS", float(r.rss_max_mb), "MB", RSS_BUDGET_MB)

    scale = {}
    for sets in SCALE_SETS:
        w = out_dir / f"study_sets{sets}"
        shutil.rmtree(w, ignore_errors=True)
        w.mkdir(parents=True)
        wall, log = _snakemake(w, _config_with_sets(out_dir, sets), *SCALE_TARGETS)
        rt = rule_table(w)
        scale[sets] = (wall, float(rt["wall_sum_s"].sum()), float(rt["rss_max_mb"].max()),
                       _jobs_run(log))
    (w3, j3, r3, n3), (w9, j9, r9, n9) = scale[SCALE_SETS[0]], scale[SCALE_SETS[1]]
    targets = " ".join(SCALE_TARGETS)
    row(f"{SCALE_SETS[1]} sets vs {SCALE_SETS[0]}: wall of `{targets}`", w9, "s", w3,
        f"{n9} vs {n3} jobs; linear scaling gives {SCALE_SETS[1] / SCALE_SETS[0]:.1f}")
    row(f"{SCALE_SETS[1]} sets vs {SCALE_SETS[0]}: summed job time", j9, "s", j3,
        f"linear scaling gives {SCALE_SETS[1] / SCALE_SETS[0]:.1f}")
    row(f"{SCALE_SETS[1]} sets vs {SCALE_SETS[0]}: largest job RSS", r9, "MB", r3,
        "flat per-job memory gives 1.0")
    for sets in SCALE_SETS:
        shutil.rmtree(out_dir / f"study_sets{sets}", ignore_errors=True)
    return rows
