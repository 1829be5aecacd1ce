"""robomill.straightness and robomill.surface: inert packages (importing them imports no
submodule), every public name importable from the package, and the rule scripts and chapters
importing submodules, so that the workflow ties a rule only to the submodules it uses."""

from __future__ import annotations

import ast
import importlib
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
PACKAGES = ("straightness", "surface")


def _printed(code: str) -> str:
    """What ``code`` prints, run in a fresh interpreter (nothing imported yet)."""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stdout.strip()


def test_importing_the_packages_imports_no_submodule():
    assert _printed("import sys, robomill.straightness, robomill.surface\n"
                    "print(sorted(m for m in sys.modules if m.startswith("
                    "('robomill.straightness.', 'robomill.surface.'))))") == "[]"


@pytest.mark.parametrize("name", PACKAGES)
def test_every_public_name_comes_from_the_submodule_its_table_names(name):
    pkg = importlib.import_module(f"robomill.{name}")
    table = {public: sub for sub, names in pkg._EXPORTS.items() for public in names}
    assert sorted(pkg.__all__) == sorted(table) and set(table) <= set(dir(pkg))
    for public, sub in table.items():
        module = importlib.import_module(f"robomill.{name}.{sub}")
        assert getattr(pkg, public) is getattr(module, public)
    with pytest.raises(AttributeError, match="has no attribute 'nope'"):
        pkg.nope  # noqa: B018
    # every public top-level name of every submodule is in the table
    for path in (REPO / "src" / "robomill" / name).glob("*.py"):
        if path.stem == "__init__":
            continue
        for node in ast.parse(path.read_text()).body:
            names = ([node.name] if isinstance(node, ast.FunctionDef | ast.ClassDef) else
                     [t.id for t in getattr(node, "targets", [getattr(node, "target", None)])
                      if isinstance(t, ast.Name)]
                     if isinstance(node, ast.Assign | ast.AnnAssign) else [])
            for n in names:
                if not n.startswith("_"):
                    assert table.get(n) == path.stem, (path.name, n)


def test_rule_scripts_and_chapters_import_submodules():
    files = [*sorted((REPO / "workflow" / "scripts").glob("straightness_*.py")),
             *sorted((REPO / "workflow" / "scripts").glob("surface_*.py")),
             REPO / "notebooks" / "src" / "ch2.py",
             REPO / "notebooks" / "src" / "ch3_straightness.py"]
    offenders = []
    for path in files:
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module in (
                    "robomill.straightness", "robomill.surface"):
                offenders.append(f"{path.name}: from {node.module} import …")
            if isinstance(node, ast.ImportFrom) and node.module == "robomill" and any(
                    a.name in PACKAGES for a in node.names):
                offenders.append(f"{path.name}: from robomill import …")
    assert offenders == []


def test_the_plan_chapters_imports_load_no_scipy_signal():
    """Chapter 7 imports robomill.plan.compare, which needs only the straightness geometry
    (perpendicular_axes): SciPy's signal package (about 1 s of the chapter's kernel) stays
    unloaded until a spectrum is taken."""
    assert _printed("import sys\nfrom robomill.plan.compare import comparison_values\n"
                    "from robomill.straightness import perpendicular_axes\n"
                    "print('scipy.signal' in sys.modules)") == "False"
