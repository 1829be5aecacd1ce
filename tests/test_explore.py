"""`make explore CHAPTER=…`: a copy of the chapter notebook with the run's paths injected."""

import nbformat
import pytest

from robomill.pipeline.explore import prepare_chapter

pytestmark = pytest.mark.pipeline


def test_chapter_copy_has_the_runs_parameters(tiny_run, repo):
    paths = prepare_chapter("ch0", repo=repo, results=tiny_run / "results")
    assert [p.name for p in paths] == ["ch0.ipynb"]
    nb = nbformat.read(paths[0], as_version=4)
    injected = [c for c in nb.cells if "injected-parameters" in c.metadata.get("tags", [])]
    assert injected
    src = injected[0].source
    assert str(tiny_run / "results/ingest/cuts.csv") in src
    assert "explore/figures/ch0" in src


def test_missing_chapter_says_how_to_build_it(tmp_path, repo):
    with pytest.raises(SystemExit, match="snakemake -j2 ch9"):
        prepare_chapter("ch9", repo=repo, results=tmp_path)


def test_explore_notebook_runs_on_a_finished_run(tiny_run, repo, tmp_path):
    """notebooks/explore.ipynb walks from the artefact list to a PSD, an FRF and a lobe map."""
    import papermill as pm

    out = tmp_path / "explore.ipynb"
    figs = tmp_path / "figs"
    pm.execute_notebook(str(repo / "notebooks/explore.ipynb"), str(out),
                        parameters={"results": str(tiny_run / "results"), "fig_dir": str(figs)},
                        kernel_name="python3", progress_bar=False, start_timeout=300)
    made = {p.name for p in figs.glob("*.png")}
    assert made == {"explore_surface_psd.png", "explore_frf.png", "explore_lobes.png"}


def test_list_artefacts_names_units_and_rules(tiny_run):
    import robomill

    cat = robomill.list_artefacts(tiny_run / "results")
    row = cat[cat.name == "modal/frf"].iloc[0]
    assert row.rule == "modal_frf"
    assert any(v.startswith("coherence [") for v in row.variables)
    assert set(cat.name) >= {"synthetic/truth", "surface/spectra", "chatter/lobes"}
