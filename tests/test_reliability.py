"""Determinism, interruption and isolation of bad input.

* A run started with ``-j1``, killed with SIGKILL after its first artefacts and resumed with
  ``-j2``, ends with artefacts identical to the uninterrupted ``-j2`` run in another fresh
  folder (so: resume, jobs run at -j1 and at -j2 agree, two fresh folders agree), on the
  chain from the virtual cell's simulators to chapter 4's artefacts.
* With ``--keep-going`` one bad cut fails only its own jobs: every other cut's artefacts and the
  chapters that do not need the bad cut are produced; the raw folder is byte-identical.
  It asks for four chapters, two that read the bad cut's stage and two that do not, rather than
  `all` (every stage and the reference chapters besides, none of which reads a profile: 2.5×
  the work for the same question of Snakemake's ``--keep-going``)."""

import os
import signal
import subprocess
import time
from pathlib import Path

import pandas as pd
import pytest
import xarray as xr
from conftest import REPO, SNAKEMAKE, raw_copy_of_run, run_snakemake, tree_digest

pytestmark = [pytest.mark.pipeline, pytest.mark.whole_study]


def _artefacts(results: Path, subdirs=None):
    def keep(p):
        rel = p.relative_to(results)
        return ("benchmarks" not in rel.parts and "logs" not in rel.parts
                and (subdirs is None or rel.parts[0] in subdirs))

    nc = sorted(p.relative_to(results) for p in results.rglob("*.nc") if keep(p))
    csv = sorted(p.relative_to(results) for p in results.rglob("*.csv") if keep(p))
    return nc, csv


def assert_same_results(a: Path, b: Path, subdirs=None, built_only=False):
    """Every artefact's data variables (not bytes: attrs may differ) and every table equal
    (optionally only under the given top-level folders of the results; ``built_only``: those
    that ``b``, a run of a narrower target, built)."""
    nc_a, csv_a = _artefacts(a, subdirs)
    nc_b, csv_b = _artefacts(b, subdirs)
    if built_only:
        assert set(nc_b) <= set(nc_a) and set(csv_b) <= set(csv_a)
        nc_a, csv_a = nc_b, csv_b
    assert nc_a == nc_b and csv_a == csv_b
    assert nc_a, "no artefacts compared"
    for rel in nc_a:
        with xr.open_dataset(a / rel, engine="h5netcdf") as da, \
                xr.open_dataset(b / rel, engine="h5netcdf") as db:
            xr.testing.assert_equal(da.load().drop_attrs(), db.load().drop_attrs())
    for rel in csv_a:
        pd.testing.assert_frame_equal(pd.read_csv(a / rel), pd.read_csv(b / rel),
                                      check_exact=True, obj=str(rel))


def test_killed_run_resumes_to_identical_artefacts(tiny_run, tmp_path):
    """A run killed mid-way (SIGKILL: no clean-up) and resumed gives the same artefacts as
    the uninterrupted tiny run. It runs the target `chatter` (chapter 4's artefacts: every
    simulator of the virtual cell, the ingestion, the force and modal stages it reads, and
    its own), not `artefacts` (the same kind of jobs, twice as many: that `artefacts` plans
    exactly the jobs of `all` less the pages is test_partial_targets.py's dry run)."""
    cmd = [SNAKEMAKE, "-s", str(REPO / "Snakefile"), "--directory", str(tmp_path),
           "--configfile", str(REPO / ".test/config.yaml"), "-j1", "chatter"]
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
    # a killed Snakemake leaves its lock behind: release it, then resume (README documents this)
    unlock = run_snakemake(tmp_path, "--unlock", "chatter")
    assert unlock.returncode == 0, unlock.stderr[-2000:]
    resumed = run_snakemake(tmp_path, "-j2", "--rerun-incomplete", "chatter")
    assert resumed.returncode == 0, resumed.stderr[-3000:]
    assert not (tmp_path / "results/chapters").exists()
    folders = {p.name for p in (tmp_path / "results").iterdir() if p.is_dir()}
    assert {"synthetic", "forces", "modal", "chatter"} <= folders, folders
    assert_same_results(tiny_run / "results", tmp_path / "results", subdirs=folders,
                        built_only=True)


def test_one_bad_cut_fails_only_its_own_jobs(tiny_run, tmp_path):

    import yaml

    from robomill.io.hashing import sha256_file

    cfgfile = tmp_path / "config.yaml"
    raw = raw_copy_of_run(tiny_run, tmp_path / "raw", config_path=cfgfile)
    manifest = yaml.safe_load((raw / "manifest.yaml").read_text())
    profiles = [f for f in manifest["files"] if f["kind"] == "profile"]
    bad = profiles[0]
    lines = (raw / bad["path"]).read_text().splitlines()
    lines[5] = lines[5].split(",")[0] + ",abc"
    (raw / bad["path"]).write_text("\n".join(lines) + "\n")
    bad["sha256"] = sha256_file(raw / bad["path"])  # a consistent manifest, a malformed file
    (raw / "manifest.yaml").write_text(yaml.safe_dump(manifest, sort_keys=False))
    before = tree_digest(raw)
    work = tmp_path / "work"
    work.mkdir()
    # chapters 2 and 3.2 read the profiles; chapters 0 and 3.1 do not
    proc = run_snakemake(work, "-j2", "--keep-going", "ch0", "ch2", "ch3_forces",
                         "ch3_straightness", configfile=cfgfile)
    assert proc.returncode != 0
    summary = proc.stderr[-3000:]
    assert f"surface_profile (cut={bad['cut']})" in summary
    assert "RawDataError" in summary and bad["path"].split("/")[-1] in summary
    assert "row 6, column z_um" in summary  # lines[5]: the 6th line of the file
    # every other cut's surface artefact, and the chapters that do not need the bad cut
    for f in profiles[1:]:
        assert (work / f"results/surface/cuts/{f['cut']}.nc").exists(), f["cut"]
    assert not (work / f"results/surface/cuts/{bad['cut']}.nc").exists()
    chapters = {p.name for p in (work / "results/chapters").glob("*.html")}
    assert chapters == {"ch0.html", "ch3_forces.html"}
    # the tracker's runs do not read the profiles: built, though their chapter is not
    assert list((work / "results/straightness/runs").glob("*.nc"))
    assert tree_digest(raw) == before
