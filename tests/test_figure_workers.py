"""Figure workers draw a chapter's figures in other processes: the files and the page are the
same bytes as when the kernel draws them, a figure that cannot be drawn fails the chapter
naming it, a worker lost or a figure that cannot be pickled costs nothing but time, and
nothing waits or hangs at the end."""

import os
import sys
import threading
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import nbformat  # noqa: E402
import pytest  # noqa: E402
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook  # noqa: E402

from robomill.pipeline import figure_workers  # noqa: E402
from robomill.pipeline.chapters import ChapterError, render_chapter  # noqa: E402
from robomill.pipeline.figure_workers import FigureClient, FigureServer  # noqa: E402
from robomill.plotting import save_figure  # noqa: E402

HERE = Path(__file__).resolve().parent


def _figure(title="a figure"):
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.plot(range(50), [(i * 7919) % 23 for i in range(50)], label="trace")
    ax.set_title(title)
    ax.legend()
    return fig


def test_a_worker_saves_the_same_bytes_under_the_senders_rcparams(tmp_path, monkeypatch):
    """The worker is another process with its own rcParams: the sender's are applied, so a
    setting read only when saving (the padding of the tight box) reaches the file."""
    if figure_workers.usable_workers(2) == 0:
        pytest.skip("one processor: no figure workers")
    with plt.rc_context({"savefig.pad_inches": 0.6, "savefig.facecolor": "#ffe0c0"}):
        fig = _figure()
        here = save_figure(fig, tmp_path / "kernel", "f")
        with FigureServer(2, tmp_path) as server:
            monkeypatch.setenv(*next(iter(server.environment().items())))
            sent = FigureClient(server.address)
            assert sent.send("f1", fig, tmp_path / "worker", "f") is not None
            assert sent.wait() == {"f1": None}
    plain = save_figure(_figure(), tmp_path / "plain", "f")
    assert (tmp_path / "worker" / "f.png").read_bytes() == here.read_bytes()
    assert plain.read_bytes() != here.read_bytes()  # the settings did change the file


def test_usable_workers_never_exceed_the_processors(monkeypatch):
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0}, raising=False)
    assert figure_workers.usable_workers(4) == 0  # one processor: the kernel draws
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1, 2}, raising=False)
    assert figure_workers.usable_workers(8) == 3
    assert figure_workers.usable_workers(2) == 2
    assert figure_workers.usable_workers(0) == 0


def test_the_server_ends_with_a_kernel_still_connected(tmp_path):
    """A client that never hangs up does not keep the job waiting at the end."""
    if figure_workers.usable_workers(2) == 0:
        pytest.skip("one processor: no figure workers")
    done = threading.Event()

    def run():
        with FigureServer(2, tmp_path) as server:
            FigureClient(server.address)  # connected, never closed
        done.set()

    threading.Thread(target=run, daemon=True).start()
    assert done.wait(timeout=60), "FigureServer did not end with a client connected"


def test_the_server_leaves_no_process_behind(tmp_path):
    """Workers and multiprocessing's resource tracker have ended, and been reaped, when the
    server exits: none is left to become an orphan (a zombie where nothing reaps orphans)."""
    if figure_workers.usable_workers(2) == 0:
        pytest.skip("one processor: no figure workers")
    import subprocess

    code = ("import psutil\nfrom robomill.pipeline.figure_workers import FigureServer\n"
            f"with FigureServer(2, {str(tmp_path)!r}) as server:\n"
            "    inside = psutil.Process().children()\n"
            "print(len(inside), [p.name() for p in psutil.Process().children()])\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120, check=True)
    assert out.stdout.split()[0] == "3"  # two workers and the tracker while it ran
    assert out.stdout.strip().endswith("[]"), out.stdout
    assert "leaked" not in out.stderr, out.stderr


# --- whole chapters ----------------------------------------------------------------------


def _chapter(tmp_path, body: str, check: bool = True) -> Path:
    params = new_code_cell("fig_dir: str = None")
    params.metadata["tags"] = ["parameters"]
    setup = new_code_cell(
        f"import sys\nsys.path.insert(0, {str(HERE)!r})\n"
        "import matplotlib.pyplot as plt\n"
        "from robomill.pipeline.captions import Numbering\n"
        "num = Numbering('9', fig_dir=fig_dir)\n"
        "num.figure('wave', 'A wave')\nnum.figure('steps', 'Steps')\n"
        "num.figure('third', 'A third')\n"
        "print(num.ref('wave'), num.ref('steps'), num.ref('third'))")
    cells = [new_markdown_cell("# Figures"), params, setup, new_code_cell(body)]
    if check:
        cells.append(new_code_cell("num.check()"))
    nb = new_notebook(cells=cells, metadata={"kernelspec": {
        "name": "python3", "display_name": "Python 3", "language": "python"}})
    path = tmp_path / "chapter.ipynb"
    nbformat.write(nb, path)
    return path


THREE_FIGURES = """
import numpy as np
x = np.linspace(0, 20, 4000)
fig, ax = plt.subplots()
ax.plot(x, np.sin(x) * np.exp(-x / 9), lw=0.5)
ax.set_title(r"$e^{-x/9}\\,\\sin x$")
num.show(fig, "wave")
fig, axs = plt.subplots(2, 1, sharex=True)
axs[0].step(range(30), np.arange(30) % 7)
axs[1].semilogy(np.arange(1, 31) ** 2)
fig.suptitle("steps")
num.show(fig, "steps")
print("between the figures")
fig, ax = plt.subplots()
ax.bar(["a", "b", "c"], [3, 1, 2])
num.show(fig, "third")
"""


def _render(tmp_path, nb, workers: int) -> Path:
    out = tmp_path / f"out{workers}"
    render_chapter(nb, out / "c.ipynb", out / "c.html", out / "figs", {},
                   failed_copy=tmp_path / "logs" / "c.failed.ipynb", start_timeout_s=120,
                   figure_workers=workers)
    return out


def _outputs(path: Path) -> list:
    nb = nbformat.read(path, as_version=4)
    return [c.get("outputs") for c in nb.cells if c.cell_type == "code"]


def test_figures_drawn_by_workers_give_the_same_chapter(tmp_path):
    """Figures, executed notebook and page are the same bytes with and without workers; the
    placeholders were all replaced, in place, by their images."""
    if figure_workers.usable_workers(2) == 0:
        pytest.skip("one processor: no figure workers")
    nb = _chapter(tmp_path, THREE_FIGURES)
    alone, helped = _render(tmp_path, nb, 0), _render(tmp_path, nb, 2)
    names = sorted(p.name for p in (alone / "figs").iterdir())
    assert names == ["fig9_1_wave.png", "fig9_2_steps.png", "fig9_3_third.png"]
    for name in names:
        assert (helped / "figs" / name).read_bytes() == (alone / "figs" / name).read_bytes()
    assert _outputs(helped / "c.ipynb") == _outputs(alone / "c.ipynb")
    body = next(c for c in nbformat.read(helped / "c.ipynb", as_version=4).cells
                if "between the figures" in c.source)
    images = [o for o in body.outputs if "image/png" in o.get("data", {})]
    assert len(images) == 3 and "being drawn" not in str(body.outputs)
    assert (helped / "c.html").read_text() == (alone / "c.html").read_text()


def test_a_figure_that_cannot_be_drawn_fails_the_chapter_naming_it(tmp_path):
    """Bad mathtext pickles fine and fails only when drawn: the chapter fails with one line
    naming the figure, as it does when the kernel draws it."""
    body = ("fig, ax = plt.subplots()\nax.set_title(r'$\\frac{1}{$')\nnum.show(fig, 'wave')\n"
            "fig, ax = plt.subplots()\nnum.show(fig, 'steps')\nfig, ax = plt.subplots()\n"
            "num.show(fig, 'third')")
    nb = _chapter(tmp_path, body)
    with pytest.raises(ChapterError, match="ValueError"):
        _render(tmp_path / "alone", nb, 0)
    if figure_workers.usable_workers(2) == 0:
        return
    with pytest.raises(ChapterError) as info:
        _render(tmp_path / "helped", nb, 2)
    message = str(info.value)
    assert "Figure 9.1 ('wave') could not be drawn: ValueError" in message, message
    assert "\n" not in message


def test_a_chapter_that_never_calls_check_is_refused(tmp_path):
    """With workers, num.check() puts the images in place: a chapter without it would show
    placeholders, and is refused naming the figure and what to do."""
    if figure_workers.usable_workers(2) == 0:
        pytest.skip("one processor: no figure workers")
    nb = _chapter(tmp_path, THREE_FIGURES, check=False)
    with pytest.raises(ChapterError, match=r"figure 'wave' was never shown.*num\.check\(\)"):
        _render(tmp_path, nb, 2)


def test_a_figure_that_cannot_be_pickled_is_drawn_in_the_kernel(tmp_path):
    body = ("from matplotlib.ticker import FuncFormatter\n"
            "fig, ax = plt.subplots()\nax.plot([1, 2, 3])\n"
            "ax.xaxis.set_major_formatter(FuncFormatter(lambda v, pos: f'<{v:g}>'))\n"
            "num.show(fig, 'wave')\n"
            "fig, ax = plt.subplots()\nnum.show(fig, 'steps')\n"
            "fig, ax = plt.subplots()\nnum.show(fig, 'third')")
    nb = _chapter(tmp_path, body)
    alone, helped = _render(tmp_path, nb, 0), _render(tmp_path, nb, 2)
    for name in ("fig9_1_wave.png", "fig9_2_steps.png"):
        assert (helped / "figs" / name).read_bytes() == (alone / "figs" / name).read_bytes()


def test_figures_of_a_lost_worker_are_drawn_in_the_kernel(tmp_path):
    """A worker that dies (killed for memory, say) fails no chapter: the kernel draws what
    it did not, from the same pickle, and the files are the same."""
    if figure_workers.usable_workers(2) == 0:
        pytest.skip("one processor: no figure workers")
    body = ("from figure_worker_helpers import DiesInAWorker\n"
            "fig, ax = plt.subplots()\nax.plot([3, 1, 2])\n"
            "fig.robomill_test_payload = DiesInAWorker()\nnum.show(fig, 'wave')\n"
            "fig, ax = plt.subplots()\nax.plot([1, 2])\nnum.show(fig, 'steps')\n"
            "fig, ax = plt.subplots()\nnum.show(fig, 'third')")
    nb = _chapter(tmp_path, body)
    alone, helped = _render(tmp_path, nb, 0), _render(tmp_path, nb, 2)
    for name in ("fig9_1_wave.png", "fig9_2_steps.png", "fig9_3_third.png"):
        assert (helped / "figs" / name).read_bytes() == (alone / "figs" / name).read_bytes()


def test_the_worker_helper_really_dies_outside_a_kernel():
    """The test above proves something only if its payload kills a worker process."""
    import subprocess

    code = (f"import pickle, sys; sys.path.insert(0, {str(HERE)!r})\n"
            "from figure_worker_helpers import DiesInAWorker\n"
            "pickle.loads(pickle.dumps(DiesInAWorker())); print('alive')")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 71 and "alive" not in proc.stdout
