"""The figure cache: a chapter rerun copies each unchanged figure's PNG instead of drawing it
again, and the file is the one a redraw writes; any change to the figure, its rcParams or
the drawing code draws it."""

import hashlib
import pickle
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import nbformat  # noqa: E402
import pytest  # noqa: E402

from robomill.pipeline import figure_workers  # noqa: E402
from robomill.pipeline.chapters import render_chapter  # noqa: E402
from robomill.pipeline.figure_cache import FigureCache, figure_blob, figure_key  # noqa: E402
from robomill.pipeline.figure_workers import FigureClient, FigureServer, draw  # noqa: E402
from robomill.plotting import save_figure  # noqa: E402

#: a figure with what makes Matplotlib's own pickle differ between processes: transforms
#: (their parents are kept by id) and shared axes (a group of axes kept as a set)
BUILD = """
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

def build(last=1.0):
    f = np.linspace(1, 100, 400)
    fig, axs = plt.subplots(2, 2, sharex=True, sharey="row")
    for k, ax in enumerate(axs.flat):
        y = 1 / np.abs(1 - (f / (20 + 10 * k)) ** 2 + 0.1j * f / 30)
        y[-1] = last
        ax.semilogy(f, y, "k", lw=0.8, label="|H|")
        twin = ax.twinx()
        twin.plot(f, np.cos(f / 9) ** 2, "b", lw=0.5)
        ax.set_title(f"pair {k}", fontsize=8)
    axs[0, 0].legend()
    fig.suptitle("four panels")
    fig.tight_layout()
    return fig
"""


def build(last: float = 1.0):
    namespace: dict = {}
    exec(BUILD, namespace)  # noqa: S102 - the test's own figure code, as the subprocess runs it
    return namespace["build"](last)


def _digests_in_a_new_process() -> tuple[str, str]:
    code = (BUILD + "\nimport hashlib, pickle\n"
            "from robomill.pipeline.figure_cache import figure_blob\n"
            "fig = build()\n"
            "print(hashlib.sha256(figure_blob(fig)).hexdigest(),"
            " hashlib.sha256(pickle.dumps(fig, protocol=5)).hexdigest())\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=120)
    canonical, plain = out.stdout.split()
    return canonical, plain


def test_the_same_figure_pickles_to_the_same_bytes_in_every_process():
    (c1, p1), (c2, p2) = _digests_in_a_new_process(), _digests_in_a_new_process()
    assert c1 == c2
    assert p1 != p2  # Matplotlib's own pickle would never find the figure again


def test_a_canonical_pickle_draws_the_same_bytes_as_the_figure(tmp_path):
    fig = build()
    direct = save_figure(fig, tmp_path / "direct", "f").read_bytes()
    rc = figure_workers.drawing_rc()
    drawn = Path(draw(figure_blob(fig), str(tmp_path / "blob"), "f", rc)).read_bytes()
    plain = Path(draw(pickle.dumps(fig), str(tmp_path / "plain"), "f", rc)).read_bytes()
    plt.close(fig)
    assert drawn == direct == plain


def test_the_key_changes_with_the_figure_and_its_rcparams():
    rc = figure_workers.drawing_rc()
    figs = build(), build(), build(last=1.5)  # the third differs in one data point
    keys = [figure_key(figure_blob(f), rc) for f in figs]
    assert keys[0] == keys[1] != keys[2]
    assert figure_key(figure_blob(figs[0]), {**rc, "savefig.pad_inches": 0.5}) != keys[0]
    for f in figs:
        plt.close(f)


def test_the_cache_writes_whole_files_and_keeps_only_the_last_runs(tmp_path):
    png = tmp_path / "a.png"
    png.write_bytes(b"\x89PNG first")
    cache = FigureCache(tmp_path / "cache")
    assert len(cache) == 0 and not cache.fetch("k1", tmp_path / "out" / "x.png")
    cache.store("k1", png)
    cache.store("k2", png)
    assert cache.fetch("k1", tmp_path / "out" / "x.png")
    assert (tmp_path / "out" / "x.png").read_bytes() == b"\x89PNG first"
    assert sorted(p.name for p in (tmp_path / "cache").iterdir()) == ["k1.png", "k2.png"]
    assert cache.keep_only(["k2"]) == 1
    assert len(cache) == 1 and not cache.fetch("k1", tmp_path / "y.png")
    (tmp_path / "a file").write_text("")  # a PNG that cannot be written: drawn instead
    assert not cache.fetch("k2", tmp_path / "a file" / "x.png")


def test_a_cache_file_that_cannot_be_removed_is_left_with_a_warning(tmp_path, monkeypatch,
                                                                    caplog):
    png = tmp_path / "a.png"
    png.write_bytes(b"\x89PNG")
    cache = FigureCache(tmp_path / "cache")
    cache.store("old", png)
    cache.store("new", png)

    def refuse(self, missing_ok=False):
        raise PermissionError(13, "Permission denied", str(self))

    monkeypatch.setattr(Path, "unlink", refuse)
    assert cache.keep_only(["new"]) == 0
    assert "old.png not removed" in caplog.text
    assert len(cache) == 2


def _one_run(tmp_path, cache, fig, out):
    with FigureServer(2, tmp_path, cache) as server:
        client = FigureClient(server.address)
        assert client.send("f1", fig, out, "f") is not None
        assert client.wait() == {"f1": None}
        started = server._pool is not None
        server.keep_only_used()
    return server, started


def test_a_rerun_copies_an_unchanged_figure_and_starts_no_worker(tmp_path):
    if figure_workers.usable_workers(2) == 0:
        pytest.skip("one processor: no figure workers")
    cache = FigureCache(tmp_path / "cache")
    first, started = _one_run(tmp_path, cache, build(), tmp_path / "first")
    assert (first.drawn, first.reused, started, len(cache)) == (1, 0, True, 1)
    again, started = _one_run(tmp_path, cache, build(), tmp_path / "again")
    assert (again.drawn, again.reused, started) == (0, 1, False)
    png = {run: (tmp_path / run / "f.png").read_bytes() for run in ("first", "again")}
    assert png["again"] == png["first"]
    changed, started = _one_run(tmp_path, cache, build(last=1.5), tmp_path / "changed")
    assert (changed.drawn, changed.reused, started, len(cache)) == (1, 0, True, 1)
    assert (tmp_path / "changed" / "f.png").read_bytes() != png["first"]


def _chapter(tmp_path, title: str) -> Path:
    from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

    params = new_code_cell("fig_dir: str = None")
    params.metadata["tags"] = ["parameters"]
    body = new_code_cell(
        "import numpy as np\nimport matplotlib.pyplot as plt\n"
        "from robomill.pipeline.captions import Numbering\n"
        "num = Numbering('9', fig_dir=fig_dir)\n"
        "num.figure('one', 'One')\nnum.figure('two', 'Two')\n"
        "print(num.ref('one'), num.ref('two'))\n"
        "fig, ax = plt.subplots()\nax.plot(np.arange(10) ** 2)\n"
        f"ax.set_title({title!r})\nnum.show(fig, 'one')\n"
        "fig, ax = plt.subplots()\nax.semilogy(np.arange(1, 30))\nnum.show(fig, 'two')\n"
        "num.check()")
    nb = new_notebook(cells=[new_markdown_cell("# Figures"), params, body], metadata={
        "kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"}})
    path = tmp_path / f"chapter_{hashlib.sha1(title.encode()).hexdigest()[:6]}.ipynb"
    nbformat.write(nb, path)
    return path


def _render(tmp_path, nb, name, cache):
    out = tmp_path / name
    render_chapter(nb, out / "c.ipynb", out / "c.html", out / "figs", {},
                   failed_copy=tmp_path / "logs" / "c.failed.ipynb", start_timeout_s=120,
                   figure_workers=2, figure_cache=cache)
    return out


def test_a_chapter_rerun_gives_the_same_page_from_its_cache(tmp_path):
    """The page and figures of a rerun served by the cache are those of a run that drew
    everything; a changed figure replaces its PNG in the cache, the other stays."""
    if figure_workers.usable_workers(2) == 0:
        pytest.skip("one processor: no figure workers")
    cache = tmp_path / "cache"
    nb = _chapter(tmp_path, "first")
    drawn = _render(tmp_path, nb, "drawn", None)
    first = _render(tmp_path, nb, "first", cache)
    before = set(FigureCache(cache).folder.iterdir())
    again = _render(tmp_path, nb, "again", cache)
    assert set(FigureCache(cache).folder.iterdir()) == before and len(before) == 2
    for out in (first, again):
        assert (out / "c.html").read_text() == (drawn / "c.html").read_text()
        for png in (drawn / "figs").iterdir():
            assert (out / "figs" / png.name).read_bytes() == png.read_bytes()
    edited = _render(tmp_path, _chapter(tmp_path, "edited"), "edited", cache)
    after = set(FigureCache(cache).folder.iterdir())
    assert len(after) == 2 and len(after & before) == 1  # figure 'two' kept, 'one' redrawn
    assert (edited / "figs" / "fig9_2_two.png").read_bytes() == (
        drawn / "figs" / "fig9_2_two.png").read_bytes()
    assert (edited / "figs" / "fig9_1_one.png").read_bytes() != (
        drawn / "figs" / "fig9_1_one.png").read_bytes()
