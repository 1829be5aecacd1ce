"""An instrument kind is one record (:data:`robomill.io.kinds.KIND_RECORDS`) and its reader:
in a copy of the package, a thermal camera's kind is added by one record and one reader
module, and ``robomill init``, ``robomill manifest``, ``robomill check`` and the workflow's
DAG (ingestion of a raw folder holding its files) take it up; the package as it is refuses
the same folder with one line naming the unknown kind (docs/design.md, "Adding an instrument
kind")."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from robomill.io.kinds import KIND_FOLDERS, KIND_KEYS, KIND_RECORDS, KINDS

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = str(Path(sys.executable).parent / "snakemake")

RECORD = ('    Kind("thermal", "thermal", {"cut": (str,), "fs_hz": (int, float)},\n'
          '         "robomill.io.thermal:check_thermal", ("thermal",)),\n')
READER = '''"""A thermal camera's spot-temperature record: CSV with t_s and T_C."""

import pandas as pd

from robomill.errors import RawDataError


def check_thermal(path, entry):
    table = pd.read_csv(path)
    missing = [c for c in ("t_s", "T_C") if c not in table.columns]
    if missing:
        raise RawDataError(path, f"columns {missing} are missing", expected="t_s, T_C")
'''


def test_the_tables_are_read_from_the_records():
    assert set(KINDS) == {k.name for k in KIND_RECORDS} == set(KIND_KEYS)
    assert KIND_FOLDERS == {k.name: k.folder for k in KIND_RECORDS if k.folder}
    assert KINDS["force"].keys == KIND_KEYS["force"] == {"cut": (str,), "fs_hz": (int, float)}
    for k in KIND_RECORDS:
        if k.check is not None:
            assert callable(k.checker()), k.name
    from robomill.cli.check import CHECKERS

    assert set(CHECKERS) == {k.name for k in KIND_RECORDS if k.check is not None}


@pytest.fixture(scope="module")
def copy_with_thermal(tmp_path_factory) -> Path:
    """The repository's package and workflow copied, plus the thermal kind: one record in
    io/kinds.py and one reader module."""
    root = tmp_path_factory.mktemp("repo")
    skip = shutil.ignore_patterns("__pycache__", "*.pyc", ".ipynb_checkpoints")
    for name in ("workflow", "notebooks", "src"):
        shutil.copytree(REPO / name, root / name, ignore=skip, symlinks=True)
    for name in ("Snakefile", "config.yaml", "plan.yaml"):
        shutil.copy(REPO / name, root / name)
    os.symlink("workflow/profiles", root / "profiles")
    kinds = root / "src" / "robomill" / "io" / "kinds.py"
    text = kinds.read_text()
    anchor = "KIND_RECORDS: tuple[Kind, ...] = (\n"
    assert anchor in text
    kinds.write_text(text.replace(anchor, anchor + RECORD))
    (root / "src" / "robomill" / "io" / "thermal.py").write_text(READER)
    return root


def _raw(tmp_path: Path, env: dict) -> Path:
    """A raw folder made by `robomill init`, one thermal record of cut s1_g1_px, listed by
    `robomill manifest` and completed as a user would (the record's rate, the cut's feed and
    depth, the experiment)."""
    raw = tmp_path / "raw"
    cli = [sys.executable, "-m", "robomill"]
    made = subprocess.run([*cli, "init", str(raw)], capture_output=True, text=True, env=env,
                          timeout=120)
    assert made.returncode == 0, made.stdout + made.stderr
    (raw / "thermal" / "s1_g1_px.csv").write_text("t_s,T_C\n0.0,21.5\n0.1,22.0\n")
    listed = subprocess.run([*cli, "manifest", str(raw)], capture_output=True, text=True,
                            env=env, timeout=120)
    assert listed.returncode == 0, listed.stdout + listed.stderr
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    (entry,) = [f for f in m["files"] if f["kind"] == "thermal"]
    assert entry["cut"] == "s1_g1_px" and entry["path"] == "thermal/s1_g1_px.csv"
    entry["fs_hz"] = 10.0
    m["cuts"] = [{**c, "feed_mm_s": 1.0, "depth_mm": 0.25} for c in m["cuts"]]
    m["experiment"] = {"spindle_rpm": 6000, "flutes": 2, "tool_diameter_mm": 6.0,
                       "cut_length_mm": 40.0}
    (raw / "manifest.yaml").write_text(yaml.safe_dump(m, sort_keys=False))
    return raw


def test_one_record_and_a_reader_add_a_kind(copy_with_thermal, tmp_path):
    env = {**os.environ, "PYTHONPATH": str(copy_with_thermal / "src")}
    raw = _raw(tmp_path, env)
    assert (raw / "thermal").is_dir()  # robomill init made its folder
    cmd = [sys.executable, "-m", "robomill", "check", str(raw)]
    good = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=120)
    assert good.returncode == 0, good.stdout + good.stderr
    assert "no reader" not in good.stdout  # the record's reader checked it
    # a record the reader refuses: one line naming the file and what was expected
    (raw / "thermal" / "s1_g1_px.csv").write_text("t_s,temperature\n0.0,21.5\n")
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    from robomill.io.hashing import sha256_file

    for f in m["files"]:
        if f["kind"] == "thermal":
            f["sha256"] = sha256_file(raw / f["path"])
    (raw / "manifest.yaml").write_text(yaml.safe_dump(m, sort_keys=False))
    bad = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=120)
    assert bad.returncode == 1
    lines = [x for x in bad.stdout.splitlines() if "s1_g1_px.csv" in x]
    assert len(lines) == 1 and "T_C" in lines[0], bad.stdout
    # the package without the record refuses the kind, in one line
    plain = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    refused = subprocess.run(cmd, capture_output=True, text=True, env=plain, timeout=120)
    assert refused.returncode == 1 and "unknown kind 'thermal'" in refused.stdout


@pytest.mark.pipeline
def test_the_dag_takes_the_new_kind_up(copy_with_thermal, tmp_path):
    """The workflow of the copy plans the ingestion of a folder with thermal files (the study
    written with them); the repository's refuses the folder with one line."""
    env = {**os.environ, "PYTHONPATH": str(copy_with_thermal / "src")}
    raw = _raw(tmp_path, env)
    work = tmp_path / "work"
    work.mkdir()
    cmd = [SNAKEMAKE, "-s", str(copy_with_thermal / "Snakefile"), "--directory", str(work),
           "--configfile", str(copy_with_thermal / "config.yaml"), "-n", "--config",
           f"data={raw}", "--", "results/ingest/study.yaml"]
    proc = subprocess.run(cmd, cwd=work, capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 0, (proc.stdout + proc.stderr)[-3000:]
    assert "ingest_study" in proc.stdout + proc.stderr
    plain = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    cmd[2], cmd[6] = str(REPO / "Snakefile"), str(REPO / "config.yaml")
    proc = subprocess.run(cmd, cwd=work, capture_output=True, text=True, env=plain, timeout=300)
    assert proc.returncode != 0 and "unknown kind 'thermal'" in proc.stderr
