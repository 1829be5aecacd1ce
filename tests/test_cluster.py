"""A real Slurm cluster: the tiny study runs as Slurm jobs through
`--profile workflow/profiles/slurm` (snakemake-executor-plugin-slurm) and gives the same
artefacts as the local run.

In `make test` (and CI) the cluster runs the tiny study's calibration stage and its chapter
from the tiny run's raw files (as a raw data set): every job of that stage, the chapter's
papermill kernel included, goes through sbatch/srun on a single-node cluster brought up from
Debian's packages. The whole tiny `all` (76 jobs, synthetic) on Slurm is the same test on every
artefact; it is opt-in (`ROBOMILL_SLURM_ALL=1 make test-cluster`) because on 2 cores it takes
about 9 min (547 s on 2026-12-01; docs/usage.md, Clusters), mostly the two nested Snakemake
start-ups the plugin runs inside every job and its status polling. Without root or the
packages the tests are skipped, saying why — except under `CI=true`, where they fail.
"""

import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest
from conftest import REPO, SNAKEMAKE, missing_system_package, raw_copy_of_run
from slurm_cluster import missing_requirements, single_node_slurm
from test_reliability import assert_same_results

pytestmark = [pytest.mark.cluster, pytest.mark.pipeline, pytest.mark.whole_study]


def _on_slurm(tmp_path: Path, work: Path, cfgfile: Path, targets: list[str],
              timeout_s: int) -> str:
    """Run ``targets`` with the Slurm profile on a fresh single-node cluster; return the log
    after checking that it succeeded and that every job with outputs went through sbatch."""
    why = missing_requirements()
    if why:
        missing_system_package(f"single-node Slurm not available: {why}")
    work.mkdir()
    with single_node_slurm(tmp_path / "slurm") as env:
        env = {**env, "SLURM_PARTITION": "debug", "PYTHONHASHSEED": "0"}
        proc = subprocess.run(
            ["timeout", "-k", "10", str(timeout_s), SNAKEMAKE, "-s", str(REPO / "Snakefile"),
             "--directory", str(work), "--configfile", str(cfgfile),
             "--profile", str(REPO / "workflow/profiles/slurm"),
             "--slurm-init-seconds-before-status-checks", "2", *targets],
            cwd=work, env=env, capture_output=True, text=True, timeout=timeout_s + 60)
    out = proc.stdout + proc.stderr
    assert proc.returncode == 0, out[-4000:]
    assert "has been submitted with SLURM jobid" in out
    local = re.findall(r"^localrule (\w+):", out, re.M)
    assert set(local) <= set(targets), f"jobs run outside Slurm: {local}"
    return out


def test_calibration_stage_and_chapter_on_slurm_equal_local(tiny_run, tmp_path):
    cfgfile = tmp_path / "config.yaml"
    raw_copy_of_run(tiny_run, tmp_path / "raw", config_path=cfgfile)
    work = tmp_path / "work"
    out = _on_slurm(tmp_path, work, cfgfile, ["calibration", "ch1"], timeout_s=600)
    submitted = set(re.findall(r"slurm_logs/rule_(\w+)/", out))
    assert {"calibration_identify", "ch1"} <= submitted, submitted
    assert "<img" in (work / "results/chapters/ch1.html").read_text()
    (work / "local").mkdir()
    shutil.copytree(tiny_run / "results/calibration", work / "local/calibration")
    assert_same_results(work / "local", work / "results", subdirs=("calibration",))
    assert os.path.exists(work / "results/calibration/accuracy.csv")


@pytest.mark.skipif(os.environ.get("ROBOMILL_SLURM_ALL") != "1",
                    reason="the whole tiny study on Slurm takes about 9 min on 2 cores; "
                           "set ROBOMILL_SLURM_ALL=1 to run it")
def test_whole_tiny_study_on_slurm_equals_local(tiny_run, tmp_path):
    work = tmp_path / "work"
    out = _on_slurm(tmp_path, work, REPO / ".test/config.yaml", ["all"], timeout_s=2400)
    n = len(re.findall(r"has been submitted with SLURM jobid", out))
    print(f"{n} Slurm jobs")
    assert_same_results(tiny_run / "results", work / "results")
    assert sorted(p.name for p in (work / "results/chapters").glob("*.html")) == \
        sorted(p.name for p in (tiny_run / "results/chapters").glob("*.html"))
