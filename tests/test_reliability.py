"""Determinism and interruption: -j1 and -j2 give identical numbers; a run killed with SIGKILL
half-way, then resumed, ends with artefacts identical to an uninterrupted run."""

import os
import signal
import subprocess
import time
from pathlib import Path

import pandas as pd
import pytest
import xarray as xr
from conftest import REPO, SNAKEMAKE, run_snakemake

pytestmark = pytest.mark.pipeline


def _artefacts(results: Path):
    nc = sorted(p.relative_to(results) for p in results.rglob("*.nc")
                if "benchmarks" not in p.parts and "logs" not in p.parts)
    csv = sorted(p.relative_to(results) for p in results.rglob("*.csv")
                 if "benchmarks" not in p.parts and "logs" not in p.parts)
    return nc, csv


def assert_same_results(a: Path, b: Path):
    """Every artefact's data variables (not bytes: attrs may differ) and every table equal."""
    nc_a, csv_a = _artefacts(a)
    nc_b, csv_b = _artefacts(b)
    assert nc_a == nc_b and csv_a == csv_b
    assert nc_a, "no artefacts compared"
    for rel in nc_a:
        with xr.open_dataset(a / rel, engine="h5netcdf") as da, \
                xr.open_dataset(b / rel, engine="h5netcdf") as db:
            xr.testing.assert_equal(da.load().drop_attrs(), db.load().drop_attrs())
    for rel in csv_a:
        pd.testing.assert_frame_equal(pd.read_csv(a / rel), pd.read_csv(b / rel),
                                      check_exact=True, obj=str(rel))


def test_j1_equals_j2(tiny_run, tmp_path):
    proc = run_snakemake(tmp_path, "-j1", "all")
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert_same_results(tiny_run / "results", tmp_path / "results")


def test_killed_run_resumes_to_identical_artefacts(tiny_run, tmp_path):
    cmd = [SNAKEMAKE, "-s", str(REPO / "Snakefile"), "--directory", str(tmp_path),
           "--configfile", str(REPO / ".test/config.yaml"), "-j2", "all"]
    proc = subprocess.Popen(cmd, cwd=tmp_path, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    # kill once some jobs have finished (some outputs exist), well before the end
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and proc.poll() is None:
        done = list((tmp_path / "results").rglob("*.nc")) if (tmp_path / "results").exists() \
            else []
        if len(done) >= 3:
            break
        time.sleep(0.2)
    assert proc.poll() is None, "the run finished before it could be interrupted"
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    resumed = run_snakemake(tmp_path, "-j2", "--rerun-incomplete", "all")
    assert resumed.returncode == 0, resumed.stderr[-3000:]
    assert_same_results(tiny_run / "results", tmp_path / "results")
