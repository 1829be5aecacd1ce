"""The virtual cell stays behind its boundary: only the simulator rules read config["synth"],
and only the simulators (and their rule scripts) import robomill.synth. The analyses read the
raw folder (manifest.yaml, cell.yaml, data files) the same way in both modes."""

import ast
import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SYNTH_RULES = REPO / "workflow" / "rules" / "synth.smk"
READS_SYNTH = re.compile(r"""config\s*(\[\s*["']synth["']\s*\]|\.get\(\s*["']synth["'])""")


def _imports_of(path: Path, package: str) -> list[str]:
    """The modules of ``robomill.<package>`` that ``path`` imports (any import form)."""
    tree = ast.parse(path.read_text(), filename=str(path))
    full, found = f"robomill.{package}", []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [a.name for a in node.names if a.name.startswith(full)]
        elif isinstance(node, ast.ImportFrom) and node.module:
            if node.module.startswith(full) or (
                    node.module == "robomill" and any(a.name == package for a in node.names)):
                found.append(node.module)
    return found


def _imports_synth(path: Path) -> list[str]:
    return _imports_of(path, "synth")


def test_no_rule_outside_synth_smk_reads_the_synth_section():
    files = [REPO / "Snakefile", *sorted((REPO / "workflow" / "rules").glob("*.smk"))]
    offenders = [f"{f.relative_to(REPO)}:{i}" for f in files if f != SYNTH_RULES
                 for i, line in enumerate(f.read_text().splitlines(), start=1)
                 if READS_SYNTH.search(line)]
    assert offenders == [], "config['synth'] read outside workflow/rules/synth.smk"
    assert READS_SYNTH.search(SYNTH_RULES.read_text())  # the pattern does match a reader


def test_no_module_outside_robomill_synth_imports_it():
    synth_pkg = REPO / "src" / "robomill" / "synth"
    modules = [p for p in sorted((REPO / "src" / "robomill").rglob("*.py"))
               if synth_pkg not in p.parents]
    offenders = {str(p.relative_to(REPO)): _imports_synth(p) for p in modules}
    assert {k: v for k, v in offenders.items() if v} == {}


def test_only_the_simulator_scripts_and_no_chapter_import_robomill_synth():
    synth_scripts = set(re.findall(r'"\.\./scripts/([\w]+\.py)"', SYNTH_RULES.read_text()))
    assert {"synth_truth.py", "synth_manifest.py", "straightness_synth_tracker.py"} <= \
        synth_scripts
    scripts = sorted((REPO / "workflow" / "scripts").glob("*.py"))
    offenders = {p.name: _imports_synth(p) for p in scripts if p.name not in synth_scripts}
    offenders.update({str(p.relative_to(REPO)): _imports_synth(p)
                      for p in sorted((REPO / "notebooks" / "src").glob("*.py"))})
    assert {k: v for k, v in offenders.items() if v} == {}


def test_the_checker_finds_an_offender(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text("import numpy\nfrom robomill.synth.cell import cell_from_config\n"
                   "from robomill import synth\n")
    assert _imports_synth(bad) == ["robomill.synth.cell", "robomill"]
    assert READS_SYNTH.search('params: seed=config["synth"]["seed"]')
    assert READS_SYNTH.search("x = config.get('synth', {})")


PLAN_CHECK = """
import sys
from robomill.pipeline.config import load_config
from robomill.io.manifest import parse_manifest
from robomill.synth.plan import SIMULATORS, synthetic_manifest
plan = parse_manifest(synthetic_manifest(load_config({config!r})), "manifest.yaml",
                      require_sha256=False)
print(len(plan.cuts), len(plan.files), plan.cell_file)
print(sorted(m for m in SIMULATORS if "robomill.synth." + m in sys.modules) or "none")
print("robomill.synth.cell" in sys.modules, "scipy.signal" in sys.modules)
"""


def test_planning_the_dag_imports_no_simulator():
    import subprocess
    import sys

    code = PLAN_CHECK.format(config=str(REPO / "config.yaml"))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    counts, simulators, heavy = out.stdout.splitlines()[:3]
    # the default study: 45 cuts; files: the cell, 45 profiles, 45 force records, 24 tracker
    # runs (3 directions x 8 feeds), 15 impact hits, 6 C-Track tables, 2 robots x 2 files
    assert counts == "45 140 cell.yaml"
    assert simulators == "none"
    assert heavy == "False False"


def _imports_pipeline(path: Path) -> list[str]:
    return _imports_of(path, "pipeline")


def test_the_science_imports_nothing_of_the_pipeline_tooling():
    """Two halves (issue 24): the science modules (calibration, surface, …, io, synth,
    importers) never import robomill.pipeline; only the package's top level (which re-exports
    list_artefacts), the command line and the tooling itself may."""
    pkg = REPO / "src" / "robomill"
    tooling = {pkg / "pipeline", pkg / "cli"}
    entry = {pkg / "__init__.py", pkg / "__main__.py"}
    modules = [p for p in sorted(pkg.rglob("*.py"))
               if p not in entry and not tooling & set(p.parents)]
    assert len(modules) > 40
    offenders = {str(p.relative_to(REPO)): _imports_pipeline(p) for p in modules}
    assert {k: v for k, v in offenders.items() if v} == {}
    for name in ("calibration", "surface", "forces", "straightness", "modal", "stiffness",
                 "beamframe", "hexapod", "kinematics", "spectra"):
        assert (pkg / f"{name}.py").exists() or (pkg / name).is_dir(), name
    for name in ("chapters", "book", "scorecard", "runlog", "failures", "why", "explore",
                 "catalog", "provenance", "config"):
        assert (pkg / "pipeline" / f"{name}.py").exists(), name
        assert not (pkg / f"{name}.py").exists(), name


def test_the_pipeline_checker_finds_an_offender(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text("from robomill.pipeline.config import prepare_config\n"
                   "from robomill import pipeline\nimport robomill.pipeline.book\n")
    assert _imports_pipeline(bad) == ["robomill.pipeline.config", "robomill",
                                      "robomill.pipeline.book"]
