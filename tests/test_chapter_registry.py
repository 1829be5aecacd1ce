"""The chapter registry (robomill/data/chapters.yaml, :mod:`robomill.registry`): one row per
chapter, read by the workflow, ``robomill check``, the book and the figure numbering; a chapter
added by one row, one notebook and one template in a copy of the repository is built by
``all``, asked for by ``robomill check`` and placed by the book."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import nbformat
import pytest
import yaml
from conftest import REPO, SNAKEMAKE

from robomill import registry
from robomill.pipeline.book_print import book_part, chapter_key, print_document
from robomill.pipeline.captions import Numbering

TABLE = REPO / "src" / "robomill" / "data" / "chapters.yaml"


# --- the repository's table ----------------------------------------------------------------

def test_every_row_names_files_that_exist():
    rows = registry.chapters(TABLE)
    assert len(rows) == 12
    for c in rows:
        assert (REPO / "notebooks" / f"{c.notebook}.ipynb").is_file(), c.id
        assert (REPO / "notebooks" / "src" / f"{c.notebook}.py").is_file(), c.id
        assert (REPO / "src/robomill/data/templates" / f"{c.template}.yaml").is_file(), c.id
        assert (REPO / "workflow" / "report" / f"{c.report}.rst").is_file(), c.id


def test_each_chapter_has_one_spelling():
    """Notebook, template, figure folder, report caption and page are all named by the id:
    the repository's rows carry none of those fields, and each file exists under the id."""
    raw = yaml.safe_load(TABLE.read_text())
    for row in raw:
        assert not {"notebook", "template", "figures", "report"} & set(row), row["id"]
    for c in registry.chapters(TABLE):
        assert (c.notebook, c.template, c.figures, c.report) == (c.id,) * 4, c
        assert c.page == f"results/chapters/{c.id}.html"
        assert (REPO / "notebooks" / "src" / f"{c.id}.py").is_file(), c.id


def test_each_chapter_title_is_the_one_its_notebook_prints():
    """The contents' title and the page's own heading (``# Chapter 3.1 — Cutting forces``)
    say the same; the reference studies' headings may say more after the title."""
    for c in registry.chapters(TABLE):
        head = (REPO / "notebooks" / "src" / f"{c.notebook}.py").read_text().splitlines()[1]
        m = re.match(r"# # Chapter (\S+) — (.*)", head)
        assert m, (c.id, head)
        assert m[1] == c.number, (c.id, head)
        assert m[2].startswith(c.title.rstrip(".")), (c.id, c.title, m[2])


def test_the_public_target_names_stay():
    """The targets README and docs/usage.md document build the same pages as before."""
    rows = {c.id: c for c in registry.chapters(TABLE)}
    assert rows["ch3_forces"].page == "results/chapters/ch3_forces.html"
    assert rows["ch6_hexapod"].page == "results/chapters/ch6_hexapod.html"
    assert {c.id for c in rows.values() if "ch3" in c.groups} == {
        "ch3_forces", "ch3_straightness", "ch3_modal"}
    assert {c.id for c in rows.values() if "ch6" in c.groups} == {
        "ch6_chatter", "ch6_stiffness", "ch6_hexapod"}
    usage = (REPO / "docs" / "usage.md").read_text()
    for cid in rows:
        assert f"| `{cid}` |" in usage, cid


def test_pages_of_one_chapter_number_share_the_figure_numbers_without_overlap():
    # the reference studies: 6.1 Figures 6.1-6.6 and Table 6.1, 6.2 from Figure 6.7 and
    # Table 6.2, 6.3 from Figure 6.11 and Table 6.8 (the pages as printed)
    assert registry.figure_range("ch6_chatter", "figure", TABLE) == (1, 7)
    assert registry.figure_range("ch6_stiffness", "figure", TABLE) == (7, 11)
    assert registry.figure_range("ch6_hexapod", "figure", TABLE) == (11, None)
    assert registry.figure_range("ch6_stiffness", "table", TABLE) == (2, 8)
    assert registry.figure_range("ch2", "figure", TABLE) == (1, None)


def test_numbering_refuses_a_number_outside_its_page():
    num = Numbering.for_chapter("ch6_stiffness", registry=TABLE)
    assert num.chapter == "6"
    assert num.table("first", "a table") == "Table 6.2"  # continues after page 6.1's
    assert num.figure("a", "a figure", number=10) == "Figure 6.10"
    with pytest.raises(ValueError, match=r"Figure 6\.11.*6\.7.*6\.10"):
        num.figure("b", "one too far", number=11)
    assert Numbering.for_chapter("ch3_forces").chapter == "3"


def test_a_bad_row_is_one_line_naming_the_row_and_field(tmp_path):
    bad = tmp_path / "chapters.yaml"
    bad.write_text(yaml.safe_dump([{"id": "ch9", "number": "9", "title": "T",
                                    "part": "appendix"}]))
    with pytest.raises(registry.RegistryError, match=r"row 1 \(ch9\): part 'appendix'"):
        registry.chapters(bad)
    bad.write_text(yaml.safe_dump([{"id": "ch9", "number": "9", "title": "T", "part": "study",
                                    "requires": ["coolant"]}]))
    with pytest.raises(registry.RegistryError, match=r"requires: unknown condition"):
        registry.chapters(bad)
    rows = yaml.safe_load(TABLE.read_text())
    bad.write_text(yaml.safe_dump([*rows, {**rows[0], "id": "ch0b"}]))
    with pytest.raises(registry.RegistryError, match="number '0' of chapter ch0b"):
        registry.chapters(bad)


# --- a chapter added in a copy of the repository --------------------------------------------

NEW_ROW = {
    "id": "ch8",
    "number": "8",
    "title": "Tool wear",
    "part": "study",
    "stage": "forces",
    "needs": {"kinds": ["force"], "experiment": ["coolant_l_min"]},
    "inputs": {"findings": "results/forces/findings.yaml"},
}


@pytest.fixture(scope="module")
def copy_with_chapter(tmp_path_factory) -> Path:
    """The repository's workflow, notebooks and library copied, plus chapter 8: one registry
    row, one notebook and one template (docs/chapters.md)."""
    root = tmp_path_factory.mktemp("repo")
    skip = shutil.ignore_patterns("__pycache__", "*.pyc", ".ipynb_checkpoints")
    for name in ("workflow", "notebooks", "src"):
        shutil.copytree(REPO / name, root / name, ignore=skip, symlinks=True)
    for name in ("Snakefile", "config.yaml", "plan.yaml"):
        shutil.copy(REPO / name, root / name)
    os.symlink("workflow/profiles", root / "profiles")
    table = root / "src" / "robomill" / "data" / "chapters.yaml"
    with open(table, "a") as fh:
        fh.write("\n" + yaml.safe_dump([NEW_ROW], sort_keys=False))
    nb = nbformat.v4.new_notebook()
    params = nbformat.v4.new_code_cell('findings: str = ""\ntemplates: str = ""\n'
                                       'fig_dir: str = ""')
    params.metadata["tags"] = ["parameters"]
    nb.cells = [nbformat.v4.new_markdown_cell("# Chapter 8 — Tool wear"), params,
                nbformat.v4.new_code_cell("print(open(findings).read()[:80])")]
    nbformat.write(nb, root / "notebooks" / "ch8.ipynb")
    (root / "src/robomill/data/templates/ch8.yaml").write_text("intro: Tool wear.\n")
    return root


def test_the_new_row_reads_as_a_chapter(copy_with_chapter):
    table = copy_with_chapter / "src" / "robomill" / "data" / "chapters.yaml"
    new = registry.chapter("ch8", table)
    assert (new.notebook, new.template, new.figures, new.report) == (
        "ch8", "ch8", "ch8", "ch8")
    assert new.page == "results/chapters/ch8.html"
    assert len(registry.chapters(table)) == len(registry.chapters(TABLE)) + 1


@pytest.mark.pipeline
def test_the_dag_builds_the_new_chapter_in_all(copy_with_chapter):
    root = copy_with_chapter
    # the copy's package (its chapter table is package data) imported by the DAG and the jobs
    env = {**os.environ, "PYTHONHASHSEED": "0", "PYTHONPATH": str(root / "src")}
    proc = subprocess.run(
        [SNAKEMAKE, "all", "-s", str(root / "Snakefile"), "--directory", str(root), "-n",
         "--quiet", "rules"],
        cwd=root, capture_output=True, text=True, timeout=600, env=env)
    assert proc.returncode == 0, proc.stderr[-3000:]
    # the job table of the dry run: one job of rule ch8, and `all` asks for it
    jobs = dict(re.findall(r"^(\w+)\s+(\d+)$", proc.stdout + proc.stderr, re.M))
    assert jobs.get("ch8") == "1", proc.stdout[-3000:]
    proc = subprocess.run(
        [SNAKEMAKE, "ch8", "-s", str(root / "Snakefile"), "--directory", str(root), "-n",
         "--quiet", "rules"],
        cwd=root, capture_output=True, text=True, timeout=600, env=env)
    assert proc.returncode == 0, proc.stderr[-3000:]
    jobs = dict(re.findall(r"^(\w+)\s+(\d+)$", proc.stdout + proc.stderr, re.M))
    # its page needs the forces' findings, so the forces' jobs run before it
    assert jobs.get("ch8") == "1" and jobs.get("forces_findings") == "1", jobs


def test_robomill_check_asks_for_what_the_new_chapter_needs(copy_with_chapter, tmp_path):
    from test_cli import complete_manifest, make_raw

    raw = make_raw(tmp_path / "raw")
    complete_manifest(raw)
    table = copy_with_chapter / "src" / "robomill" / "data" / "chapters.yaml"
    cmd = [sys.executable, "-m", "robomill", "check", str(raw), "--quiet"]
    env = dict(os.environ)
    before = subprocess.run(cmd, capture_output=True, text=True, timeout=120, env=env)
    assert before.returncode == 0, before.stdout  # the repository's chapters: a good folder
    # the copy's package, whose chapter table has chapter 8
    assert table.is_file()
    after = subprocess.run(cmd, capture_output=True, text=True, timeout=120,
                           env={**env, "PYTHONPATH": str(copy_with_chapter / "src")})
    assert after.returncode == 1
    lines = after.stdout.strip().splitlines()
    assert len(lines) == 1, lines
    assert "coolant_l_min" in lines[0] and "chapter 8" in lines[0], lines


def test_the_book_places_the_new_chapter_in_its_part(copy_with_chapter, tmp_path):
    table = copy_with_chapter / "src" / "robomill" / "data" / "chapters.yaml"
    pages = []
    for stem, title in [("ch6_chatter", "Chapter 6.1 — Reference study"),
                        ("ch8", "Chapter 8 — Tool wear"), ("ch2", "Chapter 2 — S"),
                        ("ch7", "Chapter 7 — The next cuts")]:
        p = tmp_path / f"{stem}.html"
        p.write_text(f"<html><head></head><body><h1>{title}</h1></body></html>")
        pages.append(p)
    assert book_part("ch8", table) == "The study"
    assert sorted(["ch8", "ch6_chatter", "ch7", "ch2"],
                  key=lambda s: chapter_key(s, table)) == ["ch2", "ch7", "ch8", "ch6_chatter"]
    html = print_document(pages, tmp_path / "book.html", registry=table).read_text()
    contents = html[html.index("Contents"):html.index('<section class="chapter"')]
    order = [contents.index(t) for t in ("Chapter 2 —", "Chapter 7 —", "Chapter 8 —",
                                         "Reference studies", "Chapter 6.1 —")]
    assert order == sorted(order), order
