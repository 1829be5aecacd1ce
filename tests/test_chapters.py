"""Chapters fail honestly: a raising cell fails the render, keeps the failed notebook, and
leaves no half-written outputs; parameters are checked against the declared ones first."""

import shutil
from pathlib import Path

import nbformat
import pytest
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

from robomill.pipeline.chapters import (
    ChapterError,
    WarmExporter,
    check_parameters,
    document_html,
    render_chapter,
)


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


def test_the_parameter_table_shows_the_study_parameters_not_the_artefact_paths(tmp_path):
    """With ``shown`` (the workflow passes the chapter's settings and experiment), the table
    holds those, nested keys as rows, and none of the files the notebook reads."""
    nb = _notebook(tmp_path, "print('read', data)")
    out = tmp_path / "out"
    render_chapter(nb, out / "c.ipynb", out / "c.html", out / "figs",
                   {"data": "results/forces/findings.yaml", "n": 2},
                   failed_copy=tmp_path / "logs" / "c.failed.ipynb", start_timeout_s=120,
                   shown={"settings": {"lambda_c_mm": 0.8}, "n": 2})
    html = (out / "c.html").read_text()
    table = html[html.index("Parameters of this run"):html.index("</table>")]
    assert "settings.lambda_c_mm" in table and "0.8" in table and "<code>n</code>" in table
    assert "findings.yaml" not in table and "fig_dir" not in table
    assert "read results/forces/findings.yaml" in html  # the notebook still got its input


def test_the_page_is_the_same_from_a_warmed_exporter_and_from_run_to_run():
    """The exporter readied in the background while the kernel runs (WarmExporter) has
    already converted its warm-up notebook; the page it writes must not carry anything of
    that, and two renders of the same notebook must give the same bytes (no random ids)."""
    from nbformat.v4 import new_output

    nb = new_notebook(cells=[
        new_markdown_cell("# Chapter\n\nSome *prose*."),
        new_code_cell("x = 1", outputs=[new_output("display_data", data={
            "text/markdown": "| a | b |\n|---|---|\n| 1 | 2 |", "text/plain": "t"})]),
        new_markdown_cell("## Section\n\n$a^2$ and `code`")])
    table = "| parameter | value |\n|---|---|\n| n | 2 |"
    fresh = document_html(nb, table, replace={"Some": "Any"})
    warmed = document_html(nb, table, replace={"Some": "Any"}, exporter=WarmExporter().get())
    assert warmed == fresh
    assert document_html(nb, table, replace={"Some": "Any"}) == fresh
    assert "Any <em>prose</em>" in fresh and "warm-up" not in fresh
    assert fresh.index("parameter") < fresh.index("Section")  # the table follows the title


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


def test_a_timeout_keeps_the_cells_that_ran_and_starts_one_kernel(tmp_path, monkeypatch):
    """A cell that runs past the timeout still leaves the kept notebook with the cells before
    it, and is not mistaken for a kernel that never started (one attempt)."""
    from robomill.pipeline import kernels

    nb_path = _notebook(tmp_path, "print('first ran')")
    nb = nbformat.read(nb_path, as_version=4)
    nb.cells.append(new_code_cell("import time\ntime.sleep(60)"))
    nbformat.write(nb, nb_path)
    starts = []
    counted = kernels.start_kernel
    monkeypatch.setattr(kernels, "start_kernel",
                        lambda *a, **k: (starts.append(1), counted(*a, **k))[1])
    out = tmp_path / "slow"
    with pytest.raises(ChapterError, match="[Tt]imeout|timed out"):
        render_chapter(nb_path, out / "c.ipynb", out / "c.html", out / "figs",
                       {"data": "a.csv"}, failed_copy=tmp_path / "logs" / "slow.ipynb",
                       execution_timeout_s=3)
    kept = nbformat.read(tmp_path / "logs" / "slow.ipynb", as_version=4)
    first = next(c for c in kept.cells if c.source == "print('first ran')")
    assert "first ran" in str(first.outputs)
    assert len(starts) == 1


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
    from robomill.pipeline.chapters import declared_parameters

    notebooks = sorted((repo / "notebooks").glob("ch*.ipynb"))
    assert notebooks
    for nb in notebooks:
        declared = declared_parameters(nb)
        assert "fig_dir" in declared, nb
        assert all(t not in ("None", "") for t in declared.values()), (nb, declared)


def test_kernels_talk_over_private_unix_sockets(tmp_path):
    """Parallel chapter jobs must not race for TCP ports: each kernel gets IPC sockets in its
    own folder, and the chapter runs over them."""
    import tempfile

    from robomill.pipeline.kernels import start_kernel, stop_kernel

    folders = [Path(tempfile.mkdtemp(prefix="rmk-")) for _ in range(2)]  # short socket paths
    managers = []
    try:
        for folder in folders:
            managers.append(start_kernel("python3", folder))
        assert [m.transport for m in managers] == ["ipc", "ipc"]
        assert all(m.ip.startswith(str(f)) for m, f in zip(managers, folders, strict=True))
    finally:
        for m in managers:
            stop_kernel(m)
        for folder in folders:
            shutil.rmtree(folder, ignore_errors=True)
    nb = _notebook(tmp_path, "from ipykernel.kernelapp import IPKernelApp\n"
                   "app = IPKernelApp.instance()\nprint('transport', app.transport)")
    out = _render(tmp_path, nb, data="a.csv")
    assert "transport ipc" in (out / "c.html").read_text()


def test_no_kernel_outlives_its_chapter(tmp_path, monkeypatch):
    """The kernel, started before papermill runs the notebook, is killed after the render,
    after a failing cell, and when the parameters are refused before any cell ran; no socket
    folder is left behind (in a temporary folder of this test's own: chapters that other test
    workers run meanwhile have theirs)."""
    import glob
    import tempfile

    import psutil

    # short: the kernel's Unix socket paths must stay within the system's limit
    own = tempfile.mkdtemp(prefix="rmk-")
    monkeypatch.setattr(tempfile, "tempdir", own)

    def kernels():
        return {p.pid for p in psutil.Process().children(recursive=True)
                if "ipykernel" in " ".join(p.cmdline())}

    def folders():
        return set(glob.glob(f"{tempfile.gettempdir()}/robomill-kernel-*"))

    before, left = kernels(), folders()
    _render(tmp_path, _notebook(tmp_path, "print(1)"), data="a.csv")
    with pytest.raises(ChapterError):
        _render(tmp_path / "cell", _notebook(tmp_path, "raise ValueError('x')"), data="a.csv")
    with pytest.raises(ChapterError, match="unknown parameter .nn."):
        _render(tmp_path / "refused", _notebook(tmp_path, "print(1)"), nn=3)
    running, remaining = kernels(), folders()
    monkeypatch.undo()
    shutil.rmtree(own)  # before asserting: a failure leaves nothing behind either
    assert running <= before
    assert remaining <= left


def test_a_stopped_kernel_is_gone(tmp_path):
    """stop_kernel ends the kernel's process (reaped: no zombie left) and frees its sockets."""
    import tempfile

    import psutil

    from robomill.pipeline.kernels import start_kernel, stop_kernel

    def kernels():
        return {p.pid for p in psutil.Process().children(recursive=True)
                if "ipykernel" in " ".join(p.cmdline())}

    before = kernels()
    sockets = Path(tempfile.mkdtemp(prefix="rmk-"))  # short: Unix socket paths are limited
    try:
        manager = start_kernel("python3", sockets)
        started = kernels() - before
        assert len(started) == 1
        stop_kernel(manager)
    finally:
        left = list(sockets.iterdir())
        shutil.rmtree(sockets, ignore_errors=True)
    assert not any(psutil.pid_exists(pid) for pid in started)
    assert not manager.has_kernel
    assert left == []


def test_unknown_kernel_fails_the_chapter_in_one_line(tmp_path):
    """A kernel name with no kernelspec is a chapter failure naming it, not a traceback from
    the early kernel start."""
    out = tmp_path / "out"
    with pytest.raises(ChapterError, match="no-such-kernel"):
        render_chapter(_notebook(tmp_path, "print(1)"), out / "c.ipynb", out / "c.html",
                       out / "figs", {"data": "a.csv"}, kernel="no-such-kernel")
    assert not (out / "c.html").exists()


def test_parallel_chapters_all_render(tmp_path):
    """Four chapters started at the same moment in separate processes all render."""
    import concurrent.futures as cf
    import multiprocessing

    jobs = []
    for i in range(4):
        d = tmp_path / f"job{i}"
        d.mkdir()
        jobs.append((_notebook(d, f"print('job', {i})"), d))
    ctx = multiprocessing.get_context("spawn")
    with cf.ProcessPoolExecutor(4, mp_context=ctx) as pool:
        list(pool.map(_render_positional, [d for _, d in jobs], [nb for nb, _ in jobs]))
    for i, (_, d) in enumerate(jobs):
        assert f"job {i}" in (d / "out" / "c.html").read_text()


def _render_positional(tmp_path, nb):
    return _render(tmp_path, nb, data="a.csv")


def test_kernel_that_never_answers_is_started_again(tmp_path, monkeypatch):
    """A start-up failure (no cell ran) is retried with a fresh kernel; a cell failure is not."""
    import papermill as pm

    from robomill.pipeline import chapters

    real = pm.execute_notebook
    calls = []

    def first_start_fails(*args, **kwargs):
        calls.append(kwargs["km"].ip)
        if len(calls) == 1:
            raise RuntimeError("Kernel didn't respond in 1 seconds")
        return real(*args, **kwargs)

    monkeypatch.setattr(pm, "execute_notebook", first_start_fails)
    out = _render(tmp_path, _notebook(tmp_path, "print('value', n * 21)"), data="a.csv")
    assert "value 42" in (out / "c.html").read_text()
    assert len(calls) == 2 and calls[0] != calls[1]

    def never_starts(*args, **kwargs):
        calls.append(kwargs["km"].ip)
        raise RuntimeError("Kernel didn't respond in 1 seconds")

    calls.clear()
    monkeypatch.setattr(pm, "execute_notebook", never_starts)
    with pytest.raises(ChapterError, match="didn't respond"):
        _render(tmp_path / "again", _notebook(tmp_path, "print(1)"), data="a.csv")
    assert len(calls) == chapters.KERNEL_START_ATTEMPTS

    calls.clear()
    monkeypatch.setattr(pm, "execute_notebook", first_start_fails)
    with pytest.raises(ChapterError, match="planted"):
        _render(tmp_path / "cell", _notebook(tmp_path, "raise ValueError('planted')"),
                data="a.csv")
    assert len(calls) == 2  # the first (start) failure retried; the cell failure was not


def test_page_reads_as_a_document(tmp_path):
    """Code folded in <details>, one parameter table (no parameters / injected cells), and no
    staging folder on the page even when a cell prints fig_dir."""
    nb = _notebook(tmp_path, "print('figures in', fig_dir)\nprint('value', n * 21)")
    out = tmp_path / "out"
    render_chapter(nb, out / "c.ipynb", out / "c.html", out / "figs",
                   {"data": str(tmp_path / "results" / "a.csv"), "n": 2},
                   failed_copy=tmp_path / "logs" / "c.failed.ipynb", start_timeout_s=120,
                   cwd=tmp_path)
    html = (out / "c.html").read_text()
    assert html.count("Parameters of this run") == 1
    assert "injected-parameters" not in html and "fig_dir: str = None" not in html
    assert html.count('<details class="robomill-code">') == 1  # the one remaining code cell
    assert "<details open" not in html
    assert "`results/a.csv`" in html or "<code>results/a.csv</code>" in html
    assert str(tmp_path) not in html
    assert "figures in out/figs" in html
    executed = nbformat.read(out / "c.ipynb", as_version=4)  # the executed notebook keeps all
    assert any("injected-parameters" in c.metadata.get("tags", []) for c in executed.cells)


def test_shown_value_is_relative_to_the_run_folder(tmp_path):
    from robomill.pipeline.chapters import shown_value

    assert shown_value(str(tmp_path / "results/x.csv"), tmp_path) == "results/x.csv"
    assert shown_value("results/x.csv", tmp_path) == "results/x.csv"
    assert shown_value("/elsewhere/x.csv", tmp_path) == "/elsewhere/x.csv"
    # the chapter's templates, package data, shown relative to the package's folder
    from robomill.pipeline.prose import TEMPLATES_DIR

    templates = TEMPLATES_DIR / "ch3_modal.yaml"
    assert shown_value(str(templates), tmp_path) == "robomill/data/templates/ch3_modal.yaml"
    assert shown_value(3.5, tmp_path) == "3.5"
