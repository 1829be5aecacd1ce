"""Shared fixtures: the repository, the default and tiny configurations, a snakemake runner."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))


def missing_system_package(why: str) -> None:
    """Skip a test whose Debian packages (chromium, slurm, …) are missing, saying why; under
    ``CI=true`` fail it instead, so that CI never passes by skipping what it should test
    (`.ci/run` installs the packages of `.ci/apt-packages.txt`)."""
    if os.environ.get("CI", "").lower() in ("true", "1"):
        pytest.fail(f"{why} (CI=true: a missing system package fails, it does not skip; "
                    "install .ci/apt-packages.txt, see docs/usage.md, System packages)",
                    pytrace=False)
    pytest.skip(why)


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def config():
    from robomill.pipeline.config import load_config

    return load_config(REPO / "config.yaml")


@pytest.fixture(scope="session")
def tiny_config():
    from robomill.pipeline.config import load_config

    return load_config(REPO / ".test" / "config.yaml", REPO / "workflow/schemas/config.schema.yaml")


def tree_digest(folder: Path) -> str:
    """sha256 over every path and file byte below ``folder`` (raw folders must not change)."""
    import hashlib

    h = hashlib.sha256()
    for p in sorted(folder.rglob("*")):
        h.update(str(p.relative_to(folder)).encode())
        if p.is_file():
            h.update(p.read_bytes())
    return h.hexdigest()


def raw_copy_of_run(run_dir: Path, dst: Path, *, config_path: Path) -> Path:
    """Copy a finished run's synthetic raw files to ``dst`` (a raw data set, as a user would
    have) and write the tiny config pointing at it (``data.source: raw``) to ``config_path``.
    Returns the raw folder; callers may alter files (and the manifest) before running."""
    import shutil

    import yaml

    shutil.copytree(run_dir / "results/synthetic/raw", dst)
    cfg = yaml.safe_load((REPO / ".test" / "config.yaml").read_text())
    cfg["data"] = {"source": "raw", "raw_dir": str(dst)}
    config_path.write_text(yaml.safe_dump(cfg, sort_keys=False))
    return dst


def run_snakemake(workdir: Path, *args: str, configfile: Path | None = None,
                  timeout: int = 900) -> subprocess.CompletedProcess:
    """Run the repository's workflow in ``workdir`` (results land there)."""
    cmd = [SNAKEMAKE, "-s", str(REPO / "Snakefile"), "--directory", str(workdir),
           "--configfile", str(configfile or REPO / ".test" / "config.yaml"), *args]
    env = {**os.environ, "PYTHONHASHSEED": "0"}
    return subprocess.run(cmd, cwd=workdir, capture_output=True, text=True, timeout=timeout,
                          env=env)


@pytest.fixture(scope="session")
def tiny_run(tmp_path_factory) -> Path:
    """The whole workflow (`all`) run once on the tiny config; shared by pipeline tests."""
    workdir = tmp_path_factory.mktemp("tiny_run")
    proc = run_snakemake(workdir, "-j2", "all")
    if proc.returncode != 0:
        pytest.fail(f"snakemake -j2 all failed on the tiny config:\n{proc.stdout[-4000:]}"
                    f"\n{proc.stderr[-6000:]}")
    return workdir


def chapter_outputs(workdir, name):
    """What a reader sees of an executed chapter: its markdown and text outputs (the code
    cells, with their gated "thesis: ..." strings, are left out)."""
    import json

    nb = json.loads((workdir / "results" / "chapters" / f"{name}.ipynb").read_text())
    parts = []
    for cell in nb["cells"]:
        for out in cell.get("outputs", []):
            data = out.get("data", {})
            for kind in ("text/markdown", "text/plain"):
                if kind in data:
                    parts.append("".join(data[kind]))
            if out.get("output_type") == "stream":
                parts.append("".join(out["text"]))
    return "\n".join(parts)


def default_cell_posture(point_mm):
    """The default cell's robot (``config.yaml`` ``cell:``) and its posture ``(1, n)`` with
    the TCP at ``point_mm`` and the cell's tool orientation (tests of the plan's gear-line
    waviness at one pose)."""
    import numpy as np
    import yaml

    from robomill.kinematics import robot_from_mapping
    from robomill.stiffness import solve_poses

    cfg = yaml.safe_load((REPO / "config.yaml").read_text())
    rb = robot_from_mapping(cfg["cell"]["robot"])
    R0 = np.asarray(cfg["cell"]["tool_rotation"], float)
    q, ok = solve_poses(rb, np.atleast_2d(np.asarray(point_mm, float)), R0,
                        np.deg2rad(cfg["cell"]["q_home_deg"]))
    assert ok.all(), f"{point_mm} mm is not reachable"
    return rb, q
