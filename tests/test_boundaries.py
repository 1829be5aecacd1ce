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


_SMK_IMPORTS_SYNTH = re.compile(r"^\s*(from\s+robomill\.synth\b|import\s+robomill\.synth\b|"
                                r"from\s+robomill\s+import\s+.*\bsynth\b)", re.M)


def test_no_rule_file_but_synth_smk_imports_robomill_synth():
    """The DAG of a synthetic study is planned from the layout (robomill.io.synthetic_layout),
    which imports no simulator: only synth.smk and its synth_* scripts reach the virtual cell."""
    files = sorted((REPO / "workflow" / "rules").glob("*.smk")) + [REPO / "Snakefile"]
    offenders = [p.name for p in files
                 if p != SYNTH_RULES and _SMK_IMPORTS_SYNTH.search(p.read_text())]
    assert offenders == []
    assert _SMK_IMPORTS_SYNTH.search("from robomill.synth.layout import synthetic_manifest\n")


def test_only_the_simulator_scripts_and_no_chapter_import_robomill_synth():
    synth_scripts = set(re.findall(r'"\.\./scripts/([\w]+\.py)"', SYNTH_RULES.read_text()))
    assert {"synth_truth.py", "synth_manifest.py", "synth_tracker.py"} <= \
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
from robomill.io.synthetic_layout import SIMULATORS, synthetic_manifest
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
    """Two halves: the science modules (calibration, surface, …, io, synth,
    importers) never import robomill.pipeline; only the package's top level (which looks up
    list_artefacts on first use), the command line and the tooling itself may."""
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


# --- the layers of issue 31: science, readers, tooling; errors; an inert package import ---

PKG = REPO / "src" / "robomill"
#: the packages outside the science: the pipeline's tooling, the command line, the importers
#: of native exports, the simulators and the readers/writers
NOT_SCIENCE = ("pipeline", "cli", "importers", "synth", "io")
#: top-level modules outside the science: the study artefact (robomill.study), read from the
#: manifest by the ingestion rule and by the analysis rules' scripts, never by the science
NOT_SCIENCE_MODULES = ("study.py",)
#: the readers a science module may import (raw-file formats it reads or writes itself; each
#: loads neither the artefact writer nor the manifest: robomill.io's names are lazy)
SCIENCE_MAY_READ = {"robomill.io.forces", "robomill.io.impact", "robomill.io.cell",
                    "robomill.io.robots", "robomill.io.tables", "robomill.io.profiles",
                    "robomill.io.tracker", "robomill.io.ctrack",
                    # the atomic file write (temporary file, then rename) of the UFF writers
                    "robomill.io.atomic",
                    # the recordings of the cut (sound, vibration) the verdicts judge
                    "robomill.io.recordings",
                    # the tool frame of a cell file (translation and roll-pitch-yaw), read by
                    # the kinematics that carry it
                    "robomill.io.tool_frame",
                    # the controller's conventions (flange, joints) of a cell file, which the
                    # plan's program is written in
                    "robomill.io.controller",
                    # the CSV table writer of the plan's program folder (stations.csv)
                    "robomill.io.artefacts"}
ERROR_TYPES = {"RawDataError", "ConfigError"}


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(PKG.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path, *, top_level_only: bool = False, text: str | None = None
             ) -> list[tuple[str, list[str]]]:
    """(module, names) of every import in ``path`` (inside functions too, unless
    ``top_level_only``), relative imports resolved: ``import a.b`` gives ``("a.b", [])``,
    ``from a import b, c`` gives ``("a", ["b", "c"])``; ``text`` stands in for the file's."""
    tree = ast.parse(path.read_text() if text is None else text, filename=str(path))
    package = _module_name(path).split(".")
    if path.name != "__init__.py":
        package = package[:-1]
    nodes = tree.body if top_level_only else ast.walk(tree)
    found = []
    for node in nodes:
        if isinstance(node, ast.Import):
            found += [(a.name, []) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package[: len(package) - (node.level - 1)]
                base = ".".join(up + ([base] if base else []))
            found.append((base, [a.name for a in node.names]))
    return found


def _robomill_modules(path: Path, text: str | None = None) -> set[str]:
    """The ``robomill`` modules (and package attributes) ``path`` imports, as dotted names:
    ``from robomill import io`` gives ``robomill.io``."""
    out = set()
    for module, names in _imports(path, text=text):
        if module == "robomill" or module.startswith("robomill."):
            out.add(module)
            out.update(f"{module}.{n}" for n in names if n != "*")
    return out


def _science_files() -> list[Path]:
    skip = {PKG / d for d in NOT_SCIENCE}
    entry = {PKG / "__init__.py", PKG / "__main__.py", *(PKG / m for m in NOT_SCIENCE_MODULES)}
    return [p for p in sorted(PKG.rglob("*.py")) if p not in entry and not skip & set(p.parents)]


def _layer_offences(path: Path, text: str | None = None) -> list[str]:
    bad = []
    for name in sorted(_robomill_modules(path, text)):
        top = name.split(".")[:2]
        if top in (["robomill", "pipeline"], ["robomill", "cli"]):
            bad.append(name)
        elif top == ["robomill", "io"] and not any(
                name == r or name.startswith(r + ".") for r in SCIENCE_MAY_READ):
            bad.append(name)
    return bad


def test_science_imports_no_tooling_and_only_the_readers_it_is_allowed():
    files = _science_files()
    assert len(files) > 25 and PKG / "spectra.py" in files and PKG / "lazy.py" in files
    offenders = {str(p.relative_to(REPO)): _layer_offences(p) for p in files}
    assert {k: v for k, v in offenders.items() if v} == {}


def test_nobody_imports_error_types_from_io():
    offenders = {}
    for p in sorted(PKG.rglob("*.py")):
        bad = [f"{m}: {', '.join(n)}" for m, n in _imports(p)
               if m == "robomill.io.errors"
               or (m == "robomill.io" and (ERROR_TYPES & set(n) or "errors" in n))]
        if bad:
            offenders[str(p.relative_to(REPO))] = bad
    assert offenders == {}
    assert (PKG / "errors.py").exists() and not (PKG / "io" / "errors.py").exists()


def test_the_package_top_level_imports_no_submodule():
    found = [m for m, _ in _imports(PKG / "__init__.py", top_level_only=True)]
    assert all(m in {"__future__", "robomill.lazy"} for m in found), found


def test_no_import_cycle_within_synth():
    synth = PKG / "synth"
    files = {_module_name(p): p for p in sorted(synth.rglob("*.py"))}
    graph = {}
    for name, path in files.items():
        graph[name] = {m for m in _robomill_modules(path) if m in files and m != name}
    cycles, state = [], {}

    def visit(node, stack):
        state[node] = "open"
        for nxt in sorted(graph[node]):
            if state.get(nxt) == "open":
                cycles.append(stack[stack.index(nxt):] + [nxt])
            elif nxt not in state:
                visit(nxt, stack + [nxt])
        state[node] = "done"

    for node in sorted(graph):
        if node not in state:
            visit(node, [node])
    assert graph["robomill.synth.truth"]
    assert cycles == []
    # the layout the DAG is planned from reaches no simulator
    assert _imports_synth(PKG / "io" / "synthetic_layout.py") == []


def test_the_layer_checkers_find_offenders():
    text = ("from robomill.pipeline.runlog import setup\nfrom ..io import write_artefact\n"
            "from robomill.io.forces import open_force_record\nfrom robomill import cli\n"
            "def f():\n    from robomill.io.errors import RawDataError\n"
            "    from ..io.manifest import load_manifest\n    from .hits import check_hits\n")
    frf = PKG / "modal" / "frf.py"  # a module of a subpackage: `..io` is robomill.io
    assert _layer_offences(frf, text) == [
        "robomill.cli", "robomill.io", "robomill.io.errors", "robomill.io.errors.RawDataError",
        "robomill.io.manifest", "robomill.io.manifest.load_manifest",
        "robomill.io.write_artefact", "robomill.pipeline.runlog",
        "robomill.pipeline.runlog.setup"]  # the reader io.forces and .hits pass
    assert "robomill.modal.hits.check_hits" in _robomill_modules(frf, text)
    assert ("robomill.io.errors", ["RawDataError"]) in _imports(frf, text=text)


INERT_CHECK = """
import sys
import robomill
heavy = ("scipy", "xarray", "jsonschema", "snakemake", "pandas", "robomill.io",
         "robomill.pipeline")
print(sorted(m for m in heavy if m in sys.modules) or "none")
print(robomill.open_artefact.__module__, robomill.list_artefacts.__module__)
"""

SCIENCE_CHECK = """
import importlib, sys
for name in {names!r}:
    importlib.import_module(name)
tooling = ("snakemake", "jsonschema", "papermill", "nbformat", "robomill.pipeline",
           "robomill.cli", "robomill.io.artefacts", "robomill.io.manifest")
print(sorted(m for m in tooling if m in sys.modules) or "none")
"""


def _python(code: str) -> list[str]:
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stderr
    return out.stdout.splitlines()


def test_import_robomill_loads_nothing_heavy_and_still_offers_the_artefact_functions():
    loaded, modules = _python(INERT_CHECK)[:2]
    assert loaded == "none"
    assert modules == "robomill.io.artefacts robomill.pipeline.catalog"


def test_importing_every_science_module_loads_no_tooling():
    names = sorted({_module_name(p) for p in _science_files()})
    assert _python(SCIENCE_CHECK.format(names=names))[0] == "none"


# The study reaches the analyses by one channel: results/ingest/study.yaml (robomill.study).
MANIFEST_READERS = {"ingest_manifest.py", "ingest_study.py", "synth_manifest.py"}
#: the book takes the manifest as a file only: its provenance records the sha256
#: (robomill.pipeline.provenance.run_provenance), nothing reads its cuts
MANIFEST_HASHERS = {"book.py"}


_JOB_IMPORT = re.compile(r"^from (robomill\.(?:pipeline|synth)\.jobs)(?:\.(\w+))? import (\w+)",
                         re.M)


def _script_and_job(script: Path) -> str:
    """A rule script's text with the job modules it calls (``robomill.pipeline.jobs``,
    ``robomill.synth.jobs``: each script is one call of one, tests/test_rule_scripts.py)."""
    text = script.read_text()
    parts = [text]
    for package, module, name in _JOB_IMPORT.findall(text):
        path = REPO / "src" / Path(*package.split(".")) / f"{module or name}.py"
        parts.append(path.read_text())
    return "\n".join(parts)


def test_no_analysis_script_opens_the_manifest():
    """Only the ingestion scripts (and the virtual cell's writer) read manifest.yaml; every
    other rule script (with the job it calls) reads the study (``load_study``), never
    ``load_manifest``."""
    scripts = sorted((REPO / "workflow" / "scripts").glob("*.py"))
    texts = {p.name: _script_and_job(p) for p in scripts}
    assert "def run(" in texts["forces_cut.py"]  # the job's text is read
    allowed = MANIFEST_READERS | MANIFEST_HASHERS
    offenders = sorted(name for name, text in texts.items() if name not in allowed
                       and re.search(r"\bload_manifest\b|\binputs?\.manifest\b", text))
    assert offenders == []
    readers = [name for name, text in texts.items() if "load_study(" in text]
    assert len(readers) >= 10  # the pattern does find the readers of the study


def test_every_rule_that_reads_raw_files_takes_the_study():
    """The analysis rules' input is the study artefact; the manifest is an input only of
    the ingestion rules and of the book (whose provenance records its sha256)."""
    rules = {p.name: p.read_text() for p in (REPO / "workflow" / "rules").glob("*.smk")}
    takes_manifest = sorted(name for name, text in rules.items()
                            if "manifest=MANIFEST" in text)
    assert takes_manifest == ["book.smk", "ingest.smk"]
    assert sum(text.count("study=STUDY") for text in rules.values()) >= 13


READS_EXPERIMENT = re.compile(
    r"""config\s*(\[\s*["']experiment["']\s*\]|\.get\(\s*["']experiment["'])""")


def test_the_configured_design_is_read_by_the_simulators_alone():
    """The design reaches the analyses from the study (the manifest's keys); the
    configuration's experiment is read by the simulator rules, and by the ingestion rule for
    one key: the block layout, resolved into the study where the manifest gives none."""
    files = [REPO / "Snakefile", *sorted((REPO / "workflow" / "rules").glob("*.smk"))]
    readers = {f"{f.name}:{i}": line.strip() for f in files if f != SYNTH_RULES
               for i, line in enumerate(f.read_text().splitlines(), start=1)
               if READS_EXPERIMENT.search(line)}
    assert len(readers) == 1, readers
    (where, line), = readers.items()
    assert where.startswith("ingest.smk:") and '["layout"]' in line
    assert READS_EXPERIMENT.search(SYNTH_RULES.read_text())


def test_the_synthetic_layout_is_one_module_and_no_simulator_wraps_it():
    """``robomill.plan`` is the planner; the virtual study's raw-file layout is
    ``robomill.io.synthetic_layout``, and no simulator keeps a ``plan()`` that only forwards
    to it."""
    synth = PKG / "synth"
    assert (PKG / "io" / "synthetic_layout.py").exists()
    assert not (synth / "layout.py").exists() and not (synth / "plan.py").exists()
    wrappers = [p.name for p in sorted(synth.glob("*.py"))
                for node in ast.parse(p.read_text()).body
                if isinstance(node, ast.FunctionDef) and node.name == "plan"]
    assert wrappers == []
