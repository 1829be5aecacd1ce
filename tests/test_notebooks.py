"""Each chapter notebook the pipeline runs holds exactly the cells of its jupytext source
(notebooks/src/<name>.py, percent format); `make notebooks` rebuilds the pairs."""


import jupytext
import nbformat
import pytest
from conftest import REPO


def _pipeline_notebooks() -> list[str]:
    """Notebook names the rules run: every row of the chapter registry."""
    from robomill.registry import chapters

    return sorted(f"{c.notebook}.ipynb" for c in chapters())


def _cells(nb):
    return [(c.cell_type, c.source.strip("\n"), tuple(c.metadata.get("tags", ())))
            for c in nb.cells]


def test_the_rules_run_notebooks():
    names = _pipeline_notebooks()
    assert "ch0.ipynb" in names and len(names) >= 9, names


@pytest.mark.parametrize("name", _pipeline_notebooks() + ["explore.ipynb"])
def test_notebook_equals_its_jupytext_source(name):
    ipynb = REPO / "notebooks" / name
    source = REPO / "notebooks" / "src" / name.replace(".ipynb", ".py")
    assert source.exists(), f"{ipynb} has no source {source}"
    built = nbformat.read(ipynb, as_version=4)
    expected = jupytext.read(source)
    assert _cells(built) == _cells(expected), (
        f"{ipynb} differs from {source}: run `make notebooks` and commit both")


def test_a_stale_notebook_is_caught(tmp_path):
    """The comparison sees a cell that the source has and the notebook lacks."""
    source = REPO / "notebooks" / "src" / "ch0.py"
    nb = jupytext.read(source)
    assert _cells(nb) == _cells(jupytext.read(source))
    nb.cells.pop()
    assert _cells(nb) != _cells(jupytext.read(source))


def test_no_home_made_converter():
    assert not (REPO / "notebooks" / "build.py").exists()
