"""`make explore CHAPTER=…`: a copy of the chapter notebook with the run's paths injected."""

import nbformat
import pytest

from robomill.explore import prepare_chapter

pytestmark = pytest.mark.pipeline


def test_chapter_copy_has_the_runs_parameters(tiny_run, repo):
    paths = prepare_chapter("ch0", repo=repo, results=tiny_run / "results")
    assert [p.name for p in paths] == ["ch0_experiment.ipynb"]
    nb = nbformat.read(paths[0], as_version=4)
    injected = [c for c in nb.cells if "injected-parameters" in c.metadata.get("tags", [])]
    assert injected
    src = injected[0].source
    assert str(tiny_run / "results/ingest/cuts.csv") in src
    assert "explore/figures/ch0_experiment" in src


def test_missing_chapter_says_how_to_build_it(tmp_path, repo):
    with pytest.raises(SystemExit, match="snakemake -j2 ch9"):
        prepare_chapter("ch9", repo=repo, results=tmp_path)
