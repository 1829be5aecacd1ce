"""The package carries its contracts: the configuration schemas, the chapter registry and the
prose templates are package data (``robomill/data/``), read from the package and never from
the checkout around it; a wheel installed into a fresh environment runs ``robomill init`` and
``robomill check`` in a folder outside the checkout, and ``robomill predict`` there on a built
study. The raw-folder kinds (:mod:`robomill.io.kinds`) are read by the manifest's parser and
the command line's tools alike, so that neither imports the other."""

from __future__ import annotations

import ast
import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
PACKAGE = REPO / "src" / "robomill"


def _imports(path: Path) -> set[str]:
    """Every module ``path`` imports (at any depth: functions' local imports too)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module:
            found.add(node.module)
    return found


def test_the_manifest_parser_does_not_import_the_command_line():
    for name in ("io/manifest.py", "io/kinds.py"):
        cli = sorted(m for m in _imports(PACKAGE / name) if m.startswith("robomill.cli"))
        assert cli == [], (name, cli)


def test_no_module_of_the_package_over_500_lines():
    sizes = {str(p.relative_to(PACKAGE)): len(p.read_text().splitlines())
             for p in PACKAGE.rglob("*.py")}
    assert len(sizes) > 50 and "importers/smats.py" in sizes
    assert {name: n for name, n in sizes.items() if n > 500} == {}


def test_the_contracts_are_read_from_the_package():
    from robomill.pipeline.prose import TEMPLATES_DIR
    from robomill.registry import REGISTRY_FILE, chapters
    from robomill.settings import SCHEMAS

    package = Path(__import__("robomill").__file__).parent
    for path in (SCHEMAS, TEMPLATES_DIR, REGISTRY_FILE):
        assert path.resolve().is_relative_to(package.resolve()), path
    assert (SCHEMAS / "config.schema.yaml").is_file()
    # every chapter's template is package data
    for c in chapters():
        assert (TEMPLATES_DIR / f"{c.template}.yaml").is_file(), c.id
    # no module of the library reaches above the package for its data
    for path in PACKAGE.rglob("*.py"):
        text = path.read_text()
        assert '"workflow" / "schemas"' not in text and '"notebooks" / "templates"' not in text, (
            path)
        assert "ROBOMILL_CHAPTERS" not in text, path


def _run(cmd: list[str], cwd: Path, **kw) -> subprocess.CompletedProcess:
    return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=300, **kw)


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> tuple[str, dict[str, str], Path]:
    """``pip install .`` (not editable) into a fresh environment; the libraries it depends on
    are those of this environment (a ``.pth`` line: no download of the dependencies), the
    package itself only the installed copy. Returns the environment's ``robomill``, the
    environment variables to run it with (no ``PYTHONPATH``) and its site-packages."""
    tmp_path = tmp_path_factory.mktemp("wheel")
    # the package's source copied (setuptools builds in the source folder: build/, egg-info)
    source = tmp_path / "source"
    source.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(REPO / name, source / name)
    shutil.copytree(REPO / "src", source / "src",
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "*.egg-info"))
    env_dir = tmp_path / "venv"
    made = _run([sys.executable, "-m", "venv", str(env_dir)], tmp_path)
    assert made.returncode == 0, made.stderr
    py = env_dir / "bin" / "python"
    # pip builds the wheel in an isolated environment with the build backend of
    # pyproject.toml (setuptools, from the package index or pip's cache)
    built = _run([str(py), "-m", "pip", "install", "-q", "--no-deps", str(source)], tmp_path,
                 env={**os.environ, "PIP_DISABLE_PIP_VERSION_CHECK": "1"})
    if built.returncode != 0 and ("No matching distribution" in built.stderr
                                  or "Could not find a version" in built.stderr):
        pytest.skip("the build backend (setuptools) cannot be fetched: no package index")
    assert built.returncode == 0, built.stderr[-2000:]
    purelib = Path(_run([str(py), "-c", "import sysconfig; print(sysconfig.get_paths()"
                         "['purelib'])"], tmp_path).stdout.strip())
    # this environment's library folders: its site-packages and those its own .pth files add
    # there (pinocchio's cmeel prefix), never the checkout's source
    deps = sysconfig.get_paths()["purelib"]
    (purelib / "zz_dependencies.pth").write_text(
        "".join(f"{p}\n" for p in dict.fromkeys([deps, *sys.path]) if p.startswith(deps)))
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    where = _run([str(py), "-c", "import robomill; print(robomill.__file__)"], tmp_path,
                 env=env)
    assert where.returncode == 0, where.stderr
    assert Path(where.stdout.strip()).is_relative_to(purelib), where.stdout
    return str(env_dir / "bin" / "robomill"), env, purelib


@pytest.mark.wheel
def test_a_wheel_installed_elsewhere_runs_init_and_check(wheel, tmp_path):
    """In an empty folder outside the checkout, the installed wheel's ``robomill init``,
    ``robomill manifest`` and ``robomill check``."""
    exe, env, _ = wheel
    work = tmp_path / "elsewhere"
    work.mkdir()
    init = _run([exe, "init", "raw"], work, env=env)
    assert init.returncode == 0, init.stdout + init.stderr
    assert (work / "raw" / "manifest.yaml").is_file() and (work / "raw" / "forces").is_dir()
    # the skeleton's cell.yaml is not listed yet: check says so in one line and fails
    first = _run([exe, "check", "raw"], work, env=env)
    assert first.returncode == 1 and "cell.yaml" in first.stdout, first.stdout + first.stderr
    assert "Traceback" not in first.stderr
    listed = _run([exe, "manifest", "raw"], work, env=env)
    assert listed.returncode == 0, listed.stdout + listed.stderr
    checked = _run([exe, "check", "raw"], work, env=env)
    assert checked.returncode == 0, checked.stdout + checked.stderr
    assert "0 problem(s)" in checked.stdout


@pytest.mark.pipeline
@pytest.mark.wheel
def test_a_wheel_installed_elsewhere_predicts_a_built_studys_cuts(wheel, planned_run, tmp_path):
    """``robomill predict STUDY CUTS`` of the installed wheel, run in an empty folder outside
    the checkout on a study whose plan was made: the plan's own predictions of those cuts
    (``study_cuts.csv``), so nothing of the checkout was needed. The study is the tiny study
    with its plan made, shared (conftest.planned_run)."""
    import pandas as pd
    import yaml

    from robomill.plan.cutlist import PREDICT_COLUMNS

    exe, env, _ = wheel
    study = planned_run
    resolved = yaml.safe_load((study / "results/ingest/study.yaml").read_text())
    cuts = [{k: v for k, v in c.items() if k != "process"} for c in resolved["cuts"]][:3]
    work = tmp_path / "elsewhere"
    work.mkdir()
    (work / "cuts.yaml").write_text(yaml.safe_dump(cuts))
    run = _run([exe, "predict", str(study), "cuts.yaml", "--out", "pred.csv"], work, env=env)
    assert run.returncode == 0, run.stdout + run.stderr[-3000:]
    got = pd.read_csv(work / "pred.csv")
    assert list(got.columns) == list(PREDICT_COLUMNS) and len(got) == len(cuts)
    ref = pd.read_csv(study / "results/plan/study_cuts.csv").set_index("cut").loc[got["cut"]]
    for col in ("p_stable", "a_crit_mm", "force_N", "deflection_normal_um", "waviness_um"):
        assert got[col].to_numpy() == pytest.approx(ref[col].to_numpy(), rel=1e-5,
                                                    nan_ok=True), col


# --- the artefact catalogue -------------------------------------------------------------

SMK = sorted((REPO / "workflow" / "rules").glob("*.smk")) + [REPO / "Snakefile"]
#: results/ paths that are no artefact of the catalogue: logs, benchmark tables, the chapters'
#: pages and figures (the chapter registry) and the virtual cell's raw folder
NOT_ARTEFACTS = ("results/logs/", "results/benchmarks/", "results/chapters/",
                 "results/figures/", "results/synthetic/raw")
#: the library's modules that name the artefacts they read: every stage's findings, the
#: plan's check
READERS = sorted(PACKAGE.rglob("*findings.py")) + [PACKAGE / "plan" / "check.py"]


def test_every_artefact_has_one_name_and_one_path():
    from robomill.catalogue import CatalogueError, artefact, catalogue, wildcards

    table = catalogue()
    assert len(set(table.values())) == len(table)
    assert artefact("forces.mean_forces") == "results/forces/mean_forces.csv"
    assert artefact("forces.cut") == "results/forces/cuts/{cut}.nc"  # a rule's pattern
    assert artefact("forces.cut", cut="slot-3b") == "results/forces/cuts/slot-3b.nc"
    assert wildcards("stiffness.map") == ("height", "angle")
    assert artefact("stiffness.map", height=1) == "results/stiffness/maps/h1_r{angle}.nc"
    with pytest.raises(CatalogueError, match="did you mean 'forces.mean_forces'"):
        artefact("forces.mean_force")
    with pytest.raises(CatalogueError, match="no wildcard 'run'"):
        artefact("forces.cut", run="x")


def test_the_workflow_and_the_readers_take_paths_from_the_catalogue():
    import re

    from robomill.catalogue import catalogue

    literal = re.compile(r'"(results/[a-z_]+/[^"]*)"')
    for path in SMK + READERS:
        text = path.read_text()
        found = [m for m in literal.findall(text) if not m.startswith(NOT_ARTEFACTS)
                 and "<" not in m and not m.endswith("/")]  # folders; "<robot>" describes
        if path.suffix == ".py":  # an error message may name a file the user should make
            found = [m for m in found if f'run.path("{m}")' in text or f'= "{m}"' in text
                     or f'artefact="{m}"' in text]
        assert found == [], (path.name, found)
    # and the catalogue lists no artefact the workflow does not make or read
    used = set()
    for path in SMK:
        used |= set(re.findall(r'"([a-z]+\.[a-z0-9_]+)"', path.read_text()))
    assert sorted(set(catalogue()) - used) == []
