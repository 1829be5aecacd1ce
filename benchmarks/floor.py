"""The measured floor of a study run: its wall time against the work it contains.

Every job writes two records under ``results/benchmarks``: Snakemake's ``rules/<job>.tsv``
(the job's wall time ``s``, Python start-up and imports included) and, for rule scripts,
``work/<job>.json`` (``work_s``: the seconds from :func:`robomill.pipeline.runlog.setup` to the
end of the process, i.e. the library call and its output; :func:`record_work_at_exit`). The
floor is the shortest wall time the measured work allows on ``cores`` cores: the larger of the
summed work over the cores and the largest single job's work.
"""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd

BENCHMARK = "floor"
"""``benchmark`` column of the rows in ``results/benchmarks/summary.csv``."""


def job_times_s(results: Path) -> pd.Series:
    """Wall time [s] per job (index: the job's path under ``benchmarks/rules``, no suffix);
    the largest of a tsv's rows when Snakemake repeated the job."""
    root = Path(results) / "benchmarks" / "rules"
    out = {tsv.relative_to(root).with_suffix("").as_posix():
           float(pd.read_csv(tsv, sep="\t")["s"].max()) for tsv in sorted(root.rglob("*.tsv"))}
    return pd.Series(out, dtype=float, name="job_s")


def work_times_s(results: Path) -> pd.Series:
    """Work [s] per job from ``benchmarks/work/<job>.json`` (same index as
    :func:`job_times_s`); a record that cannot be read is skipped."""
    root = Path(results) / "benchmarks" / "work"
    out = {}
    for path in sorted(root.rglob("*.json")):
        try:
            out[path.relative_to(root).with_suffix("").as_posix()] = float(
                json.loads(path.read_text())["work_s"])
        except (ValueError, KeyError, TypeError):
            continue
    return pd.Series(out, dtype=float, name="work_s")


def floor_summary(results: Path, wall_s: float, cores: int = 2) -> dict:
    """Wall, summed job time, summed work, the floor and wall/floor of one run whose results
    folder is ``results`` and whose ``snakemake -j<cores>`` took ``wall_s``."""
    jobs, work = job_times_s(results), work_times_s(results)
    measured = jobs.index.intersection(work.index)
    unmeasured = jobs.index.difference(work.index)
    work_sum = float(work[measured].sum())
    work_max = float(work[measured].max()) if len(measured) else 0.0
    floor_s = max(work_sum / cores, work_max)
    return {"wall_s": float(wall_s), "cores": int(cores), "jobs": int(jobs.size),
            "job_sum_s": float(jobs.sum()), "work_sum_s": work_sum, "work_max_s": work_max,
            "work_max_job": str(work[measured].idxmax()) if len(measured) else "",
            "jobs_measured": int(len(measured)), "jobs_unmeasured": int(len(unmeasured)),
            "unmeasured_job_s": float(jobs[unmeasured].sum()), "floor_s": floor_s,
            "wall_over_floor": float(wall_s) / floor_s if floor_s > 0 else float("nan")}


def floor_rows(label: str, results: Path, wall_s: float, cores: int = 2) -> list[dict]:
    """Rows of ``summary.csv`` (``benchmark, metric, value, unit, baseline, ratio, note``) for
    one run: each figure beside its baseline of the same run."""
    f = floor_summary(results, wall_s, cores)

    def row(metric, value, unit, baseline, note):
        ratio = value / baseline if baseline else None
        return {"benchmark": BENCHMARK, "metric": f"{label}: {metric}", "value": value,
                "unit": unit, "baseline": baseline, "ratio": ratio, "note": note}

    unmeasured = (f"; {f['jobs_unmeasured']} job(s) without a work record "
                  f"({f['unmeasured_job_s']:.1f} s of job time, not in the work)"
                  if f["jobs_unmeasured"] else "")
    return [
        row(f"wall of `snakemake -j{cores} all`", f["wall_s"], "s", f["floor_s"],
            f"{f['jobs']} jobs; baseline: the floor"),
        row("summed job time", f["job_sum_s"], "s", f["work_sum_s"],
            "every job's benchmark wall time; baseline: the summed work"),
        row("summed work (library calls)", f["work_sum_s"], "s", f["job_sum_s"],
            f"{f['jobs_measured']} job(s) measured from runlog.setup to exit{unmeasured}; "
            "baseline: the summed job time"),
        row(f"floor on {cores} cores", f["floor_s"], "s", f["wall_s"],
            f"max(summed work / {cores}, largest job's work {f['work_max_s']:.1f} s in "
            f"{f['work_max_job'] or '-'}); baseline: the wall time"),
        row("wall / floor", f["wall_over_floor"], "1", 1.0,
            "1.0 would be a run with no start-up or scheduling cost"),
    ]
