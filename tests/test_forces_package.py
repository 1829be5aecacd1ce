"""robomill.forces is a package of one-subject modules behind an inert, lazy __init__
: importing it loads no submodule, every public name resolves to its module, and
the workflow ties a rule only to the modules its script imports."""

import subprocess
import sys
from pathlib import Path

import pytest

import robomill.forces as forces
from robomill.pipeline.codedeps import code_files

REPO = Path(__file__).resolve().parents[1]
SRC = REPO / "src"


def test_import_is_inert():
    code = ("import sys, robomill.forces as f; "
            "print(sorted(m for m in sys.modules if m.startswith('robomill.forces.')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "[]"


@pytest.mark.parametrize("name", sorted(forces.__all__))
def test_every_public_name_resolves_to_its_module(name):
    obj = getattr(forces, name)
    from robomill.lazy import module_name

    mod = next(m for m, names in forces._EXPORTS.items() if name in names)
    full = module_name("robomill.forces", mod)
    assert getattr(sys.modules[full], name) is obj
    assert name in dir(forces)


def test_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        forces.nope  # noqa: B018


def test_rules_depend_only_on_the_modules_they_import():
    def deps(*paths):
        return {Path(p).relative_to(SRC).as_posix()
                for p in code_files([REPO / p for p in paths], SRC)}

    gather = deps("workflow/scripts/forces_gather.py")
    assert "robomill/forces/study.py" in gather and "robomill/forces/peaks.py" in gather
    assert "robomill/forces/stream.py" not in gather  # the streaming analysis is forces_cut's
    cut = deps("workflow/scripts/forces_cut.py")
    assert "robomill/forces/stream.py" in cut
    chapter = deps("notebooks/src/ch3_forces.py")  # loads, plots and renders
    assert {"robomill/forces/tables.py", "robomill/forces/figures.py",
            "robomill/forces/peaks.py"} <= chapter
    assert "robomill/forces/coefficients.py" in deps("workflow/scripts/forces_findings.py")
    assert not {"robomill/forces/stream.py", "robomill/forces/study.py"} & chapter
