"""A real Slurm cluster: the tiny study's calibration stage runs as Slurm jobs through
`--profile workflow/profiles/slurm` (snakemake-executor-plugin-slurm) and gives the same
artefacts as the local run.

The run reads the tiny run's raw files (as a raw data set) and builds the `calibration`
target: every job of that stage goes through sbatch/srun on a single-node cluster brought up
from Debian's packages. (The whole `all` would take many minutes, dominated by the plugin's
status polling, so the test keeps to one stage.) Without root or the packages it is skipped,
saying why.
"""

import os
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
             "--slurm-init-seconds-before-status-checks", "2", "calibration"],
            cwd=work, env=env, capture_output=True, text=True, timeout=700)
    out = proc.stdout + proc.stderr
    assert proc.returncode == 0, out[-4000:]
    assert "has been submitted with SLURM jobid" in out
    slurm_logs = list((work / ".snakemake/slurm_logs").rglob("*.log"))
    assert slurm_logs or "SLURM jobid" in out
    (work / "local").mkdir()
    shutil.copytree(tiny_run / "results/calibration", work / "local/calibration")
    assert_same_results(work / "local", work / "results", subdirs=("calibration",))
    assert os.path.exists(work / "results/calibration/accuracy.csv")
