"""A rule's code inputs follow the import graph of its script and notebook
(robomill.pipeline.codedeps)."""

import json
import re

import pytest
from conftest import REPO

from robomill.pipeline import codedeps


@pytest.fixture
def planted(tmp_path):
    """A small package: a script imports pkg.a; a imports .b lazily; b imports the
    subpackage sub (whose __init__ imports pkg.c); d is never imported."""
    src = tmp_path / "src"
    pkg = src / "robomill"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("def f():\n    from .b import g\n    return g()\n")
    (pkg / "b.py").write_text("from robomill import sub\nimport numpy\n")
    (pkg / "sub" / "__init__.py").write_text("from ..c import x\n")
    (pkg / "c.py").write_text("x = 1\n")
    (pkg / "d.py").write_text("import robomill.a\n")
    script = tmp_path / "script.py"
    script.write_text("import os\nfrom robomill.a import f\n")
    nb = tmp_path / "chapter.ipynb"
    nb.write_text(json.dumps({"cells": [
        {"cell_type": "markdown", "source": ["import robomill.d  # not code\n"]},
        {"cell_type": "code", "source": ["%matplotlib inline\n", "from robomill import c\n"]}]}))
    codedeps._CACHE.clear()
    codedeps._DEPS.clear()
    return src, script, nb


def _names(files, src):
    return sorted(str(f).replace(str(src / "robomill") + "/", "") for f in files)


def test_script_closure_follows_lazy_relative_and_package_imports(planted):
    src, script, _ = planted
    assert _names(codedeps.code_files([script], src), src) == [
        "__init__.py", "a.py", "b.py", "c.py", "sub/__init__.py"]


def test_notebook_code_cells_only_and_magics_skipped(planted):
    src, _, nb = planted
    assert _names(codedeps.code_files([nb], src), src) == ["__init__.py", "c.py"]


def test_cache_round_trip_and_a_changed_file_is_parsed_again(planted, tmp_path):
    src, script, _ = planted
    codedeps.code_files([script], src)
    cache = tmp_path / "cache.json"
    assert codedeps.save_cache(cache) and cache.exists()
    assert not codedeps.save_cache(cache)  # nothing new parsed
    codedeps._CACHE.clear()
    assert codedeps.load_cache(cache) >= 5
    (src / "robomill" / "c.py").write_text("import robomill.d\nx = 2\n")
    codedeps._DEPS.clear()
    assert "d.py" in _names(codedeps.code_files([script], src), src)
    assert codedeps.load_cache(tmp_path / "missing.json") >= 0  # ignored
    (tmp_path / "bad.json").write_text("{not json")
    codedeps.load_cache(tmp_path / "bad.json")


def test_every_rule_derives_its_code_inputs_and_none_is_hand_kept():
    """No rule keeps a hand-written list of library modules any more (issue 24: they drifted);
    the derived inputs cover the modules the drifted rules use (stiffness_maps,
    stiffness_optimal, synth_loadtests_robot, ch1, ch3_modal)."""
    src = REPO / "src"
    scripts = {}
    for smk in (REPO / "workflow" / "rules").glob("*.smk"):
        text = smk.read_text()
        assert "code=code(" not in text and "def code(" not in text, smk.name
        for block in re.split(r"\n(?=(?:use )?rule \w+)", text):
            m = re.match(r"rule (\w+):|use rule chapter as (\w+) with:", block)
            s = re.search(r'script:\s*\n\s*"\.\./scripts/([\w.]+)"', block)
            if m and m[2]:  # a chapter: the one chapter rule's script (chapter.smk)
                s = (None, "render_chapter.py")
            if not (m and s):
                continue
            nb = re.search(r'notebook\("([^"]+)"\)', block)
            sources = [REPO / "workflow" / "scripts" / s[1]]
            if nb:
                sources.append(REPO / "notebooks" / nb[1])
            scripts[m[1] or m[2]] = set(codedeps.code_files(sources, src))
    from robomill.registry import chapters

    for c in chapters():  # a chapter: its registry row's notebook, run by the chapter rule
        scripts[c.id] = set(codedeps.code_files(
            [REPO / "workflow" / "scripts" / "render_chapter.py",
             REPO / "notebooks" / f"{c.notebook}.ipynb"], src))
    assert len(scripts) > 30

    def has(rule, module):
        return str(src / "robomill" / module) in scripts[rule]

    assert has("stiffness_maps", "stiffness/maps.py")
    assert has("stiffness_optimal", "stiffness/poses.py")
    assert has("synth_loadtests_robot", "stiffness/model.py")
    assert has("ch1", "calibration/accuracy.py")
    # a subpackage's rule depends on the submodules it uses, not on its siblings
    assert has("hexapod_sensitivity", "hexapod/sensitivity.py")
    assert not has("hexapod_sensitivity", "hexapod/motion.py")
    assert not has("stiffness_identify", "stiffness/maps.py")
    assert not has("stiffness_identify", "stiffness/cuts.py")
    assert has("ch3_modal", "modal/ncio.py") and has("ch3_modal", "io/impact.py")


def test_each_rule_declares_the_code_of_its_own_script():
    """Every rule with a script declares the library files that script imports as its named
    input ``code`` (``code_inputs("<its script>")``, common.smk; a chapter through
    ``chapter_files``): the one name written twice in a rule is checked here, so that a
    renamed script cannot leave another script's code behind."""
    checked = 0
    for smk in (REPO / "workflow" / "rules").glob("*.smk"):
        text = smk.read_text()
        for block in re.split(r"\n(?=\s*(?:use )?rule \w+)", text):
            s = re.search(r'script:\s*\n\s*"\.\./scripts/([\w.]+)"', block)
            if not s or s[1] == "render_chapter.py":
                continue
            declared = re.findall(r'code=code_inputs\("([\w.]+)"\)', block)
            assert declared == [s[1]], (smk.name, s[1], declared)
            checked += 1
    assert checked > 40
