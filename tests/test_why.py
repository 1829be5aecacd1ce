"""Which edits rerun what: a chapter notebook edit reruns that chapter only; a library module
edit reruns the rules that use it (and what depends on them), nothing else."""

import shutil

import pytest
from conftest import REPO, SNAKEMAKE, raw_copy_of_run

from robomill.why import parse_dry_run

pytestmark = pytest.mark.pipeline


def _copy_repo(dst):
    shutil.copytree(REPO, dst, ignore=shutil.ignore_patterns(
        ".venv", "results", ".snakemake", ".git", "__pycache__", "*.egg-info", ".pytest_cache",
        ".ruff_cache"))
    return dst


def _snakemake(repo, work, *args):
    import subprocess

    return subprocess.run([SNAKEMAKE, "-s", str(repo / "Snakefile"), "--directory", str(work),
                           "--configfile", str(work / "config.yaml"), *args],
                          capture_output=True, text=True, timeout=900)


def _planned(repo, work, target):
    proc = _snakemake(repo, work, "-n", target)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return {j.rule: j for j in parse_dry_run(proc.stdout + proc.stderr)}


def test_edits_rerun_only_what_uses_them(tiny_run, tmp_path):

    repo = _copy_repo(tmp_path / "repo")
    work = tmp_path / "work"
    work.mkdir()
    # the tiny run's synthetic raw files serve as a raw data set (no simulators to rerun)
    raw_copy_of_run(tiny_run, tmp_path / "raw", config_path=work / "config.yaml")
    proc = _snakemake(repo, work, "-j2", "ch0")
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert _planned(repo, work, "ch0") == {}

    nb = repo / "notebooks" / "ch0_experiment.ipynb"
    nb.write_text(nb.read_text() + "\n")
    jobs = _planned(repo, work, "ch0")
    assert set(jobs) == {"ch0"}
    assert jobs["ch0"].categories == ["input changed"]

    nb.write_text(nb.read_text().rstrip("\n") + "\n")
    proc = _snakemake(repo, work, "-j2", "ch0")
    assert proc.returncode == 0, proc.stderr[-3000:]
    module = repo / "src" / "robomill" / "experiment.py"
    module.write_text(module.read_text() + "\n# an edit\n")
    jobs = _planned(repo, work, "ch0")
    assert set(jobs) == {"ingest_manifest", "ch0"}
    assert "input changed" in jobs["ingest_manifest"].categories
