"""``make bench``'s floor (benchmarks/floor.py) on fake job records, and the work record that
``robomill.pipeline.runlog.setup`` leaves at the end of a rule script's process."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from floor import floor_rows, floor_summary  # noqa: E402

TSV_HEADER = "s\th:m:s\tmax_rss\tmax_vms\tmax_uss\tmax_pss\tio_in\tio_out\tmean_load\tcpu_time\n"


def _job(results: Path, job: str, s: float, work_s: float | None = None) -> None:
    tsv = results / "benchmarks" / "rules" / f"{job}.tsv"
    tsv.parent.mkdir(parents=True, exist_ok=True)
    tsv.write_text(TSV_HEADER + f"{s}\t0:00:00\t100\t200\t90\t95\t0\t0\t50\t{s}\n")
    if work_s is not None:
        js = results / "benchmarks" / "work" / f"{job}.json"
        js.parent.mkdir(parents=True, exist_ok=True)
        js.write_text(json.dumps({"work_s": work_s, "log": f"results/logs/{job}.log"}))


@pytest.fixture
def results(tmp_path):
    r = tmp_path / "results"
    _job(r, "chatter/simulation", 26.0, 20.0)
    _job(r, "synth/truth", 12.0, 8.0)
    _job(r, "stiffness/maps/cut_s1_g1_px", 3.5, 0.5)
    _job(r, "chapters/ch2", 9.0)  # a job without a work record
    return r


def test_floor_sums_jobs_and_work_and_takes_the_longest_job_as_the_bound(results):
    f = floor_summary(results, wall_s=40.0, cores=2)
    assert f["jobs"] == 4 and f["jobs_measured"] == 3 and f["jobs_unmeasured"] == 1
    assert f["job_sum_s"] == pytest.approx(26 + 12 + 3.5 + 9)
    assert f["work_sum_s"] == pytest.approx(28.5)
    assert f["unmeasured_job_s"] == pytest.approx(9.0)
    # 28.5 s of work on 2 cores is 14.25 s, but the 20 s job alone takes longer
    assert f["floor_s"] == pytest.approx(20.0) and f["work_max_job"] == "chatter/simulation"
    assert f["wall_over_floor"] == pytest.approx(2.0)
    f4 = floor_summary(results, wall_s=40.0, cores=1)
    assert f4["floor_s"] == pytest.approx(28.5)


def test_floor_rows_keep_the_summary_schema(results):
    rows = pd.DataFrame(floor_rows("tiny", results, wall_s=40.0))
    assert list(rows.columns) == ["benchmark", "metric", "value", "unit", "baseline", "ratio",
                                  "note"]
    assert (rows["benchmark"] == "floor").all() and rows["metric"].str.startswith("tiny: ").all()
    by = rows.set_index("metric")
    assert by.loc["tiny: wall / floor", "value"] == pytest.approx(2.0)
    assert by.loc["tiny: summed work (library calls)", "value"] == pytest.approx(28.5)
    assert "1 job(s) without a work record" in by.loc["tiny: summed work (library calls)",
                                                       "note"]
    wall = by.loc["tiny: wall of `snakemake -j2 all`"]
    assert wall["ratio"] == pytest.approx(40.0 / 20.0)


def test_unreadable_work_record_is_skipped(results):
    bad = results / "benchmarks" / "work" / "chapters" / "ch2.json"
    bad.parent.mkdir(parents=True, exist_ok=True)
    bad.write_text("{not json")
    assert floor_summary(results, wall_s=40.0)["jobs_measured"] == 3


def test_runlog_setup_records_the_work_of_the_process(tmp_path):
    log = tmp_path / "results" / "logs" / "chatter" / "simulation.log"
    code = ("import time\nfrom robomill.pipeline.runlog import setup\n"
            f"setup({str(log)!r}, 'x')\ntime.sleep(0.3)\n")
    subprocess.run([sys.executable, "-c", code], check=True)
    rec = json.loads((tmp_path / "results" / "benchmarks" / "work" / "chatter"
                      / "simulation.json").read_text())
    assert 0.3 <= rec["work_s"] < 5.0 and rec["log"] == str(log)
