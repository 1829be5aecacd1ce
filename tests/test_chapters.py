"""Chapters fail honestly: a raising cell fails the render, keeps the failed notebook, and
leaves no half-written outputs; parameters are checked against the declared ones first."""

import nbformat
import pytest
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

from robomill.chapters import ChapterError, check_parameters, render_chapter


def _notebook(tmp_path, body, params="data: str = None\nn: int = 2\nfig_dir: str = None"):
    cell = new_code_cell(params)
    cell.metadata["tags"] = ["parameters"]
    nb = new_notebook(cells=[new_markdown_cell("# Test chapter"), cell, new_code_cell(body)],
                      metadata={"kernelspec": {"name": "python3", "display_name": "Python 3",
                                               "language": "python"}})
    path = tmp_path / "chapter.ipynb"
    nbformat.write(nb, path)
    return path


def _render(tmp_path, nb, **params):
    out = tmp_path / "out"
    render_chapter(nb, out / "c.ipynb", out / "c.html", out / "figs", params,
                   failed_copy=tmp_path / "logs" / "c.failed.ipynb", start_timeout_s=120)
    return out


def test_good_chapter_renders_with_parameter_table(tmp_path):
    nb = _notebook(tmp_path, "import pathlib\npathlib.Path(fig_dir, 'f.png').write_bytes(b'x')\n"
                   "print('value', n * 21)")
    out = _render(tmp_path, nb, data="a.csv", n=2)
    html = (out / "c.html").read_text()
    assert "value 42" in html
    assert "Parameters of this run" in html and "a.csv" in html
    assert (out / "figs" / "f.png").exists()


def test_figures_are_inline_even_when_the_environment_forces_agg(tmp_path, monkeypatch):
    """Headless machines often export MPLBACKEND=Agg; the chapter page must still show figures."""
    monkeypatch.setenv("MPLBACKEND", "Agg")
    nb = _notebook(tmp_path, "import matplotlib.pyplot as plt\nimport robomill.plotting\n"
                   "plt.plot([0, 1], [1, 0])\nplt.show()")
    out = _render(tmp_path, nb, data="a.csv")
    assert "<img" in (out / "c.html").read_text()


def test_failing_cell_fails_the_chapter_and_keeps_the_notebook(tmp_path):
    nb = _notebook(tmp_path, "raise ValueError('planted failure')")
    with pytest.raises(ChapterError, match="planted failure") as info:
        _render(tmp_path, nb, data="a.csv")
    kept = tmp_path / "logs" / "c.failed.ipynb"
    assert kept.exists() and str(kept) in str(info.value)
    assert not (tmp_path / "out" / "c.html").exists()
    assert not (tmp_path / "out" / "c.ipynb").exists()
    assert not (tmp_path / "out" / "figs").exists()


def test_error_output_fails_even_if_execution_continues(tmp_path):
    """A cell tagged raises-exception lets papermill carry on; the chapter still fails."""
    nb_path = _notebook(tmp_path, "print('after')")
    nb = nbformat.read(nb_path, as_version=4)
    bad = new_code_cell("1/0")
    bad.metadata["tags"] = ["raises-exception"]
    nb.cells.insert(2, bad)
    nbformat.write(nb, nb_path)
    with pytest.raises(ChapterError, match="ZeroDivisionError"):
        _render(tmp_path, nb_path, data="a.csv")


def test_misspelt_parameter_is_refused_before_execution(tmp_path):
    nb = _notebook(tmp_path, "raise RuntimeError('must not run')")
    with pytest.raises(ChapterError, match=r"unknown parameter 'dta' \(did you mean 'data'\?\)"):
        check_parameters(nb, {"dta": "a.csv"})
    with pytest.raises(ChapterError, match="'n' must be int"):
        check_parameters(nb, {"n": "two"})


def test_untyped_parameter_is_refused(tmp_path):
    nb = _notebook(tmp_path, "pass", params="data = None")
    with pytest.raises(ChapterError, match="no type annotation"):
        check_parameters(nb, {"data": "x"})


def test_repository_chapters_declare_typed_parameters(repo):
    from robomill.chapters import declared_parameters

    notebooks = sorted((repo / "notebooks").glob("ch*.ipynb"))
    assert notebooks
    for nb in notebooks:
        declared = declared_parameters(nb)
        assert "fig_dir" in declared, nb
        assert all(t not in ("None", "") for t in declared.values()), (nb, declared)
