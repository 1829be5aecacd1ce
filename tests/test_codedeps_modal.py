"""The modal subpackage and the workflow's code inputs: a rule depends on the
modal submodules its script imports, not on the whole package, and importing
``robomill.modal`` loads none of them."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from robomill.pipeline import codedeps

REPO = Path(__file__).resolve().parents[1]
SRC = REPO / "src"
MODAL = SRC / "robomill" / "modal"


def _modal_files(*sources: Path) -> set[str]:
    """Names (``lscf.py``…) of the modal submodules the sources depend on."""
    return {Path(f).name for f in codedeps.code_files([str(s) for s in sources], SRC)
            if Path(f).parent == MODAL}


def test_modal_frf_does_not_depend_on_lscf():
    """Editing the LSCF module must not rerun the FRF estimation (nor the report)."""
    frf = _modal_files(REPO / "workflow" / "scripts" / "modal_frf.py")
    assert {"frf.py", "hits.py", "layout.py", "__init__.py"} <= frf
    assert "lscf.py" not in frf and "identification.py" not in frf
    report = _modal_files(REPO / "workflow" / "scripts" / "modal_report.py")
    assert "checks.py" in report and "lscf.py" not in report
    identify = _modal_files(REPO / "workflow" / "scripts" / "modal_identify.py")
    assert {"lscf.py", "identification.py", "peaks.py", "band.py"} <= identify


def test_package_init_imports_no_library_module():
    """The package's ``__init__`` is a lazy table: its source imports nothing of the science,
    so depending on it is cheap, and no submodule is loaded by ``import robomill.modal``."""
    # only the shared lazy-table helper, which imports nothing of the science
    assert codedeps.file_imports(MODAL / "__init__.py", SRC) <= {"robomill.lazy",
                                                               "robomill.lazy.lazy_exports"}
    out = subprocess.run(
        [sys.executable, "-c", "import sys, robomill.modal; "
         "print(sorted(m for m in sys.modules if m.startswith('robomill.modal.')))"],
        capture_output=True, text=True, check=True).stdout.strip()
    assert out == "[]"


def test_every_public_name_loads_from_its_submodule():
    import importlib

    import robomill.modal as modal

    where = {name: module for module, names in modal._NAMES.items() for name in names}
    assert modal.__all__ == sorted(where)
    assert set(modal.__all__) <= set(dir(modal))
    for name, module in where.items():
        sub = importlib.import_module(f"robomill.modal.{module}")
        assert getattr(modal, name) is getattr(sub, name), name
    with pytest.raises(AttributeError, match="no_such_name"):
        modal.no_such_name  # noqa: B018


def test_scripts_and_notebooks_import_modal_submodules_only():
    """A name imported from the package itself would hide its submodule from the code
    inputs (the lazy table is not followed by ast): rule scripts and chapter notebooks
    import ``robomill.modal.<submodule>`` names only."""
    sources = [*(REPO / "workflow" / "scripts").glob("*.py"),
               *(REPO / "notebooks").glob("*.ipynb")]
    bad = []
    for s in sources:
        for name in codedeps.file_imports(s, SRC):
            parts = name.split(".")
            if parts[:2] == ["robomill", "modal"] and len(parts) > 2 \
                    and codedeps.module_file(".".join(parts[:3]), SRC) is None:
                bad.append(f"{s.name}: {name}")
            if name == "robomill.modal":
                submodules = {n for n in codedeps.file_imports(s, SRC)
                              if n.startswith("robomill.modal.")}
                if not submodules:
                    bad.append(f"{s.name}: imports the package robomill.modal")
    assert not bad, bad
