"""Style gates: ruff, snakefmt and `snakemake --lint` are clean."""

import subprocess
import sys
from pathlib import Path

import pytest

BIN = Path(sys.executable).parent


def _run(repo, *cmd):
    return subprocess.run([str(BIN / cmd[0]), *cmd[1:]], cwd=repo, capture_output=True,
                          text=True, timeout=300)


def test_ruff_clean(repo):
    proc = _run(repo, "ruff", "check", ".")
    assert proc.returncode == 0, proc.stdout[-3000:]


def test_snakefmt_clean(repo):
    proc = _run(repo, "snakefmt", "--check", "Snakefile", "workflow/rules")
    assert proc.returncode == 0, proc.stderr[-3000:]


@pytest.mark.pipeline
def test_snakemake_lint_clean(repo):
    proc = _run(repo, "snakemake", "--lint")
    out = proc.stdout + proc.stderr
    assert "Congratulations, your workflow is in a good condition!" in out, out[-4000:]
