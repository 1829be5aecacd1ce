"""The workflow plans from several raw folders (config data.raw_dirs): a dry run gets one force
job per cut of every folder, and a cut id two folders give different files stops the run with
one line before any job. Dry runs read only the manifests (empty data files suffice)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml
from conftest import REPO, run_snakemake

from robomill.io.synthetic_layout import synthetic_manifest

pytestmark = pytest.mark.pipeline


def _forces_folder(dst: Path, rename: str = "", sha: str = "0") -> tuple[Path, int]:
    """A raw folder with the default test design's force files (empty; their sha256 ``sha``
    repeated) and cuts, the ids prefixed with ``rename``."""
    cfg = yaml.safe_load((REPO / ".test" / "config.yaml").read_text())
    plan = synthetic_manifest(cfg)
    files = []
    for f in plan["files"]:
        if f["kind"] != "force":
            continue
        f = {**f, "cut": rename + f["cut"], "sha256": sha * 64,
             "path": f["path"].replace(f["cut"], rename + f["cut"])}
        (dst / f["path"]).parent.mkdir(parents=True, exist_ok=True)
        (dst / f["path"]).write_text("")
        files.append(f)
    cuts = [{**c, "id": rename + c["id"]} for c in plan["cuts"]]
    exp = {k: plan["experiment"][k] for k in ("spindle_rpm", "flutes", "tool_diameter_mm")}
    (dst / "manifest.yaml").write_text(yaml.safe_dump(
        {"experiment": exp, "cuts": cuts, "files": files}, sort_keys=False))
    return dst, len(files)


def _dry(workdir: Path, folders: list[Path]):
    workdir.mkdir()
    overlay = workdir / "data.yaml"
    overlay.write_text(yaml.safe_dump({"data": {"source": "raw",
                                                "raw_dirs": [str(f) for f in folders]}}))
    return run_snakemake(workdir, "-n", "results/forces/mean_forces.csv", "--configfile",
                         str(REPO / "config.yaml"), str(overlay), timeout=300)


def test_two_raw_folders_give_the_force_jobs_of_both(tmp_path):
    a, n_a = _forces_folder(tmp_path / "study")
    b, n_b = _forces_folder(tmp_path / "run", rename="r_")
    proc = _dry(tmp_path / "w", [a, b])
    assert proc.returncode == 0, proc.stderr[-2000:]
    jobs = re.search(r"^forces_cut\s+(\d+)$", proc.stdout, re.M)
    assert jobs and int(jobs.group(1)) == n_a + n_b


def test_a_cut_id_with_other_files_in_two_folders_stops_in_one_line(tmp_path):
    a, _ = _forces_folder(tmp_path / "study")
    b, _ = _forces_folder(tmp_path / "run", sha="1")
    proc = _dry(tmp_path / "w", [a, b])
    assert proc.returncode != 0
    said = [x for x in proc.stderr.splitlines() if "is also a cut of" in x]
    assert len(said) == 1 and str(b / "manifest.yaml") in said[0]
    assert "Traceback" not in proc.stderr
