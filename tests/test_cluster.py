"""A real Slurm cluster: the tiny study's calibration stage and its chapter run as Slurm
jobs through `--profile workflow/profiles/slurm` (snakemake-executor-plugin-slurm) and give
the same artefacts as the local run.

The run reads the tiny run's raw files (as a raw data set) and builds the `calibration` and
`ch1` targets: every job of that stage, the chapter's papermill kernel included, goes through
sbatch/srun on a single-node cluster brought up from Debian's packages. The whole `all` (86
jobs) is left out of CI: on 2 cores each Slurm job costs 15-30 s, mostly the two nested
Snakemake start-ups the plugin runs per job, so it takes 7 min or more (README, Clusters).
Without root or the packages the test is skipped, saying why.
"""

import os
import re
import shutil
import subprocess

import pytest
from conftest import REPO, SNAKEMAKE, raw_copy_of_run
from slurm_cluster import missing_requirements, single_node_slurm
from test_reliability import assert_same_results

pytestmark = [pytest.mark.cluster, pytest.mark.pipeline]


def test_calibration_on_slurm_equals_local(tiny_run, tmp_path):
    why = missing_requirements()
    if why:
        pytest.skip(f"single-node Slurm not available: {why}")
    cfgfile = tmp_path / "config.yaml"
    raw_copy_of_run(tiny_run, tmp_path / "raw", config_path=cfgfile)
    work = tmp_path / "work"
    work.mkdir()
    with single_node_slurm(tmp_path / "slurm") as env:
        env = {**env, "SLURM_PARTITION": "debug"}
        proc = subprocess.run(
            ["timeout", "-k", "10", "600", SNAKEMAKE, "-s", str(REPO / "Snakefile"),
             "--directory", str(work), "--configfile", str(cfgfile),
             "--profile", str(REPO / "workflow/profiles/slurm"),
             "--slurm-init-seconds-before-status-checks", "2", "calibration", "ch1"],
            cwd=work, env=env, capture_output=True, text=True, timeout=700)
    out = proc.stdout + proc.stderr
    assert proc.returncode == 0, out[-4000:]
    assert "has been submitted with SLURM jobid" in out
    submitted = set(re.findall(r"slurm_logs/rule_(\w+)/", out))
    assert {"calibration_identify", "ch1"} <= submitted, submitted
    assert not re.search(r"^localrule (?!calibration:)", out, re.M), \
        "a job with outputs ran outside Slurm"
    html = (work / "results/chapters/ch1_calibration.html").read_text()
    assert "<img" in html
    (work / "local").mkdir()
    shutil.copytree(tiny_run / "results/calibration", work / "local/calibration")
    assert_same_results(work / "local", work / "results", subdirs=("calibration",))
    assert os.path.exists(work / "results/calibration/accuracy.csv")
