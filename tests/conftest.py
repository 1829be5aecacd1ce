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

    return load_config(REPO / ".test" / "config.yaml",
                       REPO / "src/robomill/data/schemas/config.schema.yaml")


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


# The book's PDF (rule book_pdf: headless Chromium, about 16 CPU s a study) is printed and
# checked once, for the tiny run (test_book.py); the other whole-study tests leave it out of
# `all` with this --config value (config book.pdf), having no assertion on it.
NO_BOOK_PDF = "book={pdf: false}"


def run_snakemake(workdir: Path, *args: str, configfile: Path | None = None,
                  timeout: int = 900) -> subprocess.CompletedProcess:
    """Run the repository's workflow in ``workdir`` (results land there)."""
    cmd = [SNAKEMAKE, "-s", str(REPO / "Snakefile"), "--directory", str(workdir),
           "--configfile", str(configfile or REPO / ".test" / "config.yaml"), *args]
    env = {**os.environ, "PYTHONHASHSEED": "0"}
    return subprocess.run(cmd, cwd=workdir, capture_output=True, text=True, timeout=timeout,
                          env=env)


#: markers of the tests that run the workflow, a browser, a cluster or the built wheel
WHOLE_RUN_MARKERS = ("pipeline", "browser", "cluster", "wheel")


def pytest_collection_modifyitems(config, items):
    """Order the test modules for two workers (`make test`: ``-n 2 --dist loadscope
    --no-loadscope-reorder`` hands whole modules out in this order): the first module that
    needs the shared tiny run (:func:`tiny_run`) goes first, so one worker starts building it
    at once; then the workflow modules that do not need it, which keep the other worker busy
    meanwhile; then the other modules that need it; last the unit-test modules (seconds
    each), which fill both workers' ends. In each group the modules marked ``whole_study``
    (they build whole studies: minutes each) go first. Within a module the order is
    unchanged, and a run without workers runs the same tests in this order."""
    modules: dict[str, int] = {}
    needs: dict[str, bool] = {}
    heavy: dict[str, bool] = {}
    runs: dict[str, bool] = {}
    for item in items:
        name = item.nodeid.split("::")[0]
        modules.setdefault(name, len(modules))
        needs[name] = needs.get(name, False) or "tiny_run" in getattr(item, "fixturenames", ())
        heavy[name] = heavy.get(name, False) or item.get_closest_marker("whole_study") is not None
        runs[name] = runs.get(name, False) or any(item.get_closest_marker(m) is not None
                                                  for m in WHOLE_RUN_MARKERS)
    first = next((m for m in modules if needs[m]), None)

    def rank(item):
        name = item.nodeid.split("::")[0]
        group = (0 if name == first else 3 if not (runs[name] or needs[name])
                 else 1 if not needs[name] else 2)
        return group, not heavy[name], modules[name]

    items.sort(key=rank)  # stable: a module's own order is kept


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """``--dist loadscope`` that hands a worker its next module only once the worker is on the
    last test of its current one. xdist's own queues a module ahead as soon as two tests are
    left, so a worker starting a whole-study module of one or two tests also took the next
    module, while the other worker ran out of work (the pipeline phase of `make test` took 540 s
    for 919 s of module time on 2 workers). (An xdist worker runs a test only once it holds the
    next one or is told to stop, so one test ahead is the least.)"""
    if config.getvalue("dist") != "loadscope":
        return None
    from xdist.scheduler import LoadScopeScheduling

    class OneModuleAhead(LoadScopeScheduling):
        def _reschedule(self, node):
            if node.shutting_down:
                return
            if not self.workqueue:
                node.shutdown()
                return
            if self._pending_of(self.assigned_work[node]) > 1:
                return
            self._assign_work_unit(node)

    return OneModuleAhead(config, log)


def _build_tiny_run(workdir: Path) -> str:
    """Run `all` on the tiny config in ``workdir``; "" when it succeeded, else why not."""
    proc = run_snakemake(workdir, "-j2", "all")
    if proc.returncode != 0:
        return (f"snakemake -j2 all failed on the tiny config:\n{proc.stdout[-4000:]}"
                f"\n{proc.stderr[-6000:]}")
    return ""


def _built_once(tmp_path_factory, name: str, build) -> Path:
    """The folder ``name`` made by ``build(folder)`` (returns "" when it succeeded, else why
    not) once per test session. Under pytest-xdist the first worker to need it builds it in
    the session's shared temporary folder while holding a lock; the others wait for it and
    read the same folder."""
    if not os.environ.get("PYTEST_XDIST_WORKER"):  # no workers (or xdist not loaded)
        workdir = tmp_path_factory.mktemp(name)
        why = build(workdir)
    else:
        import fcntl

        shared = tmp_path_factory.getbasetemp().parent  # the same for every worker
        workdir = shared / name
        outcome = shared / f"{name}.outcome"
        with open(shared / f"{name}.lock", "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file closes
            if not outcome.exists():  # a worker killed while building left no outcome:
                workdir.mkdir(exist_ok=True)  # the next one tries again in the same folder
                outcome.write_text(build(workdir))
            why = outcome.read_text()
    if why:
        pytest.fail(why)
    return workdir


@pytest.fixture(scope="session")
def tiny_run(tmp_path_factory) -> Path:
    """The whole workflow (`all`) run once on the tiny config; shared by pipeline tests.

    Under pytest-xdist (`make test` runs the pipeline tests on two workers) the run is built
    once for all workers (:func:`_built_once`). Tests only read it, except test_pipeline.py
    (a no-op run and ``--report`` in it) and test_book.py (screenshots into its book);
    `--dist loadscope` keeps each module on one worker, so those run one after the other
    (:func:`pytest_collection_modifyitems`)."""
    return _built_once(tmp_path_factory, "tiny_run", _build_tiny_run)


# the tiny study's planning request (chapter 7), as a user puts it: plan.yaml in the study's
# folder (config plan.request's default)
TINY_PLAN_REQUEST = REPO / ".test" / "plan.yaml"


@pytest.fixture(scope="session")
def planned_run(tiny_run, tmp_path_factory) -> Path:
    """A copy of :func:`tiny_run` with the tiny study's request (``plan.yaml``) in its
    folder and `snakemake plan` made in it (the plan, its check and chapter 7), once per
    session like the tiny run (:func:`_built_once`). Tests only read it; a test that runs
    anything more in it copies it first."""
    import shutil

    def build(workdir: Path) -> str:
        study = workdir / "study"
        if study.exists():  # a worker killed while copying
            shutil.rmtree(study)
        shutil.copytree(tiny_run, study, symlinks=True,
                        ignore=shutil.ignore_patterns(".chromium-profile", "locks"))
        shutil.copy(TINY_PLAN_REQUEST, study / "plan.yaml")
        proc = run_snakemake(study, "-j2", "plan", "--config", NO_BOOK_PDF, timeout=600)
        if proc.returncode != 0:
            return f"snakemake -j2 plan failed in a copy of the tiny run:\n{proc.stderr[-6000:]}"
        return ""

    return _built_once(tmp_path_factory, "planned_run", build) / "study"


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
