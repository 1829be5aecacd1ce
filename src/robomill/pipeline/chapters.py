"""Render a chapter: execute its notebook with papermill, convert it to HTML with nbconvert.

The page reads as a document (:func:`document_html`): code folded, one parameter table, no
run-specific folder; figures and tables are numbered by :mod:`robomill.pipeline.captions`.

Outputs appear only on success: the notebook runs on a staging copy, its figures go to a
staging folder, and everything is moved into place at the end. A notebook in which any cell
raised is a failure even if papermill returned normally; the failed executed notebook is kept
beside the log so the error can be read in context.
"""

from __future__ import annotations

import logging
import os
import shutil
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import nbformat

from robomill.settings import schema_default

log = logging.getLogger(__name__)

#: a kernel that never answered is started afresh this many times in all
KERNEL_START_ATTEMPTS = 2


class ChapterError(RuntimeError):
    """A chapter notebook failed; the message names the cell and the kept notebook."""


_TYPES: dict[str, tuple[type, ...]] = {
    "str": (str,),
    "int": (int,),
    "float": (int, float),
    "bool": (bool,),
    "list": (list, tuple),
    "dict": (dict,),
}


def declared_parameters(notebook: str | Path) -> dict[str, str]:
    """The chapter's declared parameters ``{name: type name}``.

    The notebook's ``parameters`` cell is the chapter's parameter schema: every parameter is
    declared with a type annotation, ``cuts: str = None`` (read with
    :func:`papermill.inspect_notebook`).
    """
    import papermill as pm

    info = pm.inspect_notebook(str(notebook))
    return {name: p["inferred_type_name"] for name, p in info.items()}


def check_parameters(notebook: str | Path, parameters: Mapping[str, Any]) -> dict[str, str]:
    """Refuse unknown, misspelt, untyped or wrongly typed parameters before execution.

    Raises
    ------
    ChapterError
        Naming the parameter and the accepted ones.
    """
    import difflib

    declared = declared_parameters(notebook)
    untyped = [n for n, t in declared.items() if t in ("None", "")]
    if untyped:
        raise ChapterError(f"chapter notebook {notebook}: parameter(s) {', '.join(untyped)} "
                           "have no type annotation in the parameters cell (write "
                           "`name: str = None`)")
    for name, value in parameters.items():
        if name not in declared:
            close = difflib.get_close_matches(name, list(declared), n=1)
            raise ChapterError(
                f"chapter notebook {notebook}: unknown parameter {name!r}"
                + (f" (did you mean {close[0]!r}?)" if close else "")
                + "; accepted: " + ", ".join(f"{n}: {t}" for n, t in declared.items()))
        types = _TYPES.get(declared[name])
        if types and value is not None and (
                not isinstance(value, types) or (bool not in types and isinstance(value, bool))):
            raise ChapterError(f"chapter notebook {notebook}: parameter {name!r} must be "
                               f"{declared[name]}, got {type(value).__name__} {value!r}")
    return declared


#: the folder holding the package (``src/`` of a checkout, ``site-packages`` of an install): a
#: chapter's templates are package data, shown relative to it (``robomill/data/templates/...``)
PACKAGE_PARENT = Path(__file__).resolve().parents[2]


def shown_value(value: Any, root: str | Path | None = None) -> str:
    """A parameter value as the chapter page shows it: an absolute path below ``root`` (the
    run's folder, the one holding ``results/``) or below the package's folder (the
    chapter's templates) becomes relative to it, so that no machine-specific folder appears on the
    page."""
    text = str(value)
    if not (isinstance(value, str | Path) and os.path.isabs(text)):
        return text
    for base in ([root] if root is not None else []) + [PACKAGE_PARENT]:
        try:
            return str(Path(text).resolve().relative_to(Path(base).resolve()))
        except ValueError:
            continue
    return text


def parameter_rows(name: str, value: Any, declared_type: str = "",
                   root: str | Path | None = None) -> list[tuple[str, str, str]]:
    """The rows ``(parameter, value, type)`` a parameter shows in the chapter's table.

    A nested setting is no Python literal on the page: a mapping gives one row per key
    (``settings.lambda_c_mm``), a list of mappings one group of rows per item
    (``sets[0].depth_mm``), and a list of plain values one row with the values joined by
    commas. A nested row's type is the type of its value.
    """
    if isinstance(value, Mapping):
        rows = [r for k, v in value.items()
                for r in parameter_rows(f"{name}.{k}", v, type(v).__name__, root)]
        return rows or [(name, "(empty)", declared_type or "dict")]
    if isinstance(value, list | tuple) and any(isinstance(v, Mapping) for v in value):
        return [r for i, v in enumerate(value)
                for r in parameter_rows(f"{name}[{i}]", v, type(v).__name__, root)]
    if isinstance(value, list | tuple):
        return [(name, ", ".join(shown_value(v, root) for v in value), declared_type or "list")]
    shown_type = "none" if value is None else (declared_type or type(value).__name__)
    return [(name, shown_value(value, root), shown_type)]


def _parameter_table(parameters: Mapping[str, Any], declared: Mapping[str, str],
                     root: str | Path | None = None) -> str:
    if not parameters:
        return ("**Parameters of this run**\n\nnone: the chapter reports the study's artefacts "
                "only")
    rows = ["| parameter | value | type |", "|---|---|---|"]
    for name, value in parameters.items():
        for key, shown, kind in parameter_rows(name, value, declared.get(name, ""), root):
            rows.append(f"| `{key}` | `{shown.replace('|', chr(92) + '|')}` | {kind} |")
    return "**Parameters of this run**\n\n" + "\n".join(rows)


#: nbconvert template of the chapter pages: code folded (robomill/data/chapter_template)
TEMPLATE_DIR = Path(__file__).parents[1] / "data" / "chapter_template"


def chapter_exporter():
    """The nbconvert exporter of the chapter pages (the chapter template, no prompts)."""
    from nbconvert import HTMLExporter

    return HTMLExporter(extra_template_basedirs=[str(TEMPLATE_DIR.parent)],
                        template_name=TEMPLATE_DIR.name, exclude_input_prompt=True,
                        exclude_output_prompt=True)


class WarmExporter:
    """A :func:`chapter_exporter` made ready in a background thread.

    The exporter's first page costs about a second on its own (importing nbconvert, loading
    and compiling the Jinja template, the markdown and highlighting machinery), and nothing
    in it depends on the chapter. :func:`render_chapter` starts this before the kernel and
    collects it after: the kernel runs the notebook in its own process meanwhile, and this
    process only waits for its messages, so the warm-up is done on the other core instead of
    after the kernel. :meth:`get` returns the warmed exporter (a failed warm-up returns a
    fresh one: the warm-up only saves time).
    """

    def __init__(self) -> None:
        import threading

        self._exporter = None
        self._thread = threading.Thread(target=self._warm, name="chapter-exporter",
                                        daemon=True)
        self._thread.start()

    def _warm(self) -> None:
        try:
            exporter = chapter_exporter()
            nb = nbformat.v4.new_notebook(cells=[
                nbformat.v4.new_markdown_cell("# warm-up\n\n| a |\n|---|\n| 1 |"),
                nbformat.v4.new_code_cell("x = 1", outputs=[nbformat.v4.new_output(
                    "display_data", data={"text/markdown": "*x*", "text/plain": "x"})])])
            exporter.from_notebook_node(nb)
            self._exporter = exporter
        except Exception as exc:  # noqa: BLE001 - the real export reports real problems
            log.debug("chapter exporter warm-up failed: %s", exc)

    def get(self):
        self._thread.join()
        return self._exporter if self._exporter is not None else chapter_exporter()


def document_html(nb: nbformat.NotebookNode, table_md: str,
                  replace: Mapping[str, str] | None = None, exporter=None) -> str:
    """The chapter page of an executed notebook, as a document.

    The ``parameters`` and papermill's ``injected-parameters`` cells are left out (the one
    parameter table ``table_md`` is inserted after the title instead), every code cell's
    input is folded in a ``<details>`` element (one click shows it; printing omits it), and
    each ``replace`` key (e.g. the staging folder) is replaced in the page. ``exporter`` is a
    :func:`chapter_exporter` (one already used, see :class:`WarmExporter`), a new one if None.
    """
    nb = nbformat.from_dict(nb)
    nb.cells = [c for c in nb.cells if not {"parameters", "injected-parameters"}
                & set(c.metadata.get("tags", []))]
    table = nbformat.v4.new_markdown_cell(table_md, id="parameters-of-this-run")  # same id each run
    nb.cells.insert(1 if nb.cells and nb.cells[0].cell_type == "markdown" else 0, table)
    body, _ = (exporter or chapter_exporter()).from_notebook_node(nb)
    for old, new in (replace or {}).items():
        body = body.replace(old, new)
    return body


def _kernel_never_ran(staged_nb: Path) -> bool:
    """True when execution failed before the kernel ran any cell (a start-up failure)."""
    if not staged_nb.exists():
        return True
    nb = nbformat.read(staged_nb, as_version=4)
    return not any(c.get("execution_count") for c in nb.cells if c.cell_type == "code")


def notebook_errors(nb: nbformat.NotebookNode) -> list[str]:
    """Error outputs of an executed notebook, as ``"cell N: EName: value"`` lines."""
    return [f"cell {i}: {out.get('ename')}: {out.get('evalue')}"
            for i, cell in enumerate(nb.cells) for out in cell.get("outputs", [])
            if out.get("output_type") == "error"]


def render_chapter(
    notebook: str | Path,
    out_ipynb: str | Path,
    out_html: str | Path,
    fig_dir: str | Path,
    parameters: Mapping[str, Any],
    *,
    kernel: str = schema_default("chapters", "kernel"),
    start_timeout_s: int = schema_default("chapters", "start_timeout_s"),
    execution_timeout_s: int = schema_default("chapters", "execution_timeout_s"),
    failed_copy: str | Path | None = None,
    cwd: str | Path | None = None,
    shown: Mapping[str, Any] | None = None,
) -> None:
    """Execute ``notebook`` with ``parameters`` (plus ``fig_dir``) and render it: papermill
    executes it (on the kernel of :func:`robomill.pipeline.kernels.start_kernel`), nbconvert
    writes the page (:func:`document_html`). The notebook draws and saves its own figures.

    The page's table "Parameters of this run" shows ``shown``: the study's parameters that
    the chapter reports (its settings, the experiment), not the artefacts it reads; None
    shows every parameter but ``fig_dir``.

    Raises
    ------
    ChapterError
        If execution fails or any cell holds an error output.
    """
    from robomill.pipeline.kernels import start_kernel, stop_kernel

    out_ipynb, out_html, fig_dir = Path(out_ipynb), Path(out_html), Path(fig_dir)
    out_ipynb.parent.mkdir(parents=True, exist_ok=True)
    fig_dir.parent.mkdir(parents=True, exist_ok=True)
    stage = Path(tempfile.mkdtemp(prefix=f".{out_ipynb.stem}.", dir=out_ipynb.parent))
    # the kernel first: it starts and imports while this job does its own start-up below
    sockets = Path(tempfile.mkdtemp(prefix="robomill-kernel-"))  # short: a socket path
    try:
        manager = start_kernel(kernel, sockets, cwd)
    except Exception:  # noqa: BLE001 - started again below, where a failure is reported
        manager = None
    try:
        import papermill as pm

        staged_nb = stage / out_ipynb.name
        staged_figs = stage / "figures"
        staged_figs.mkdir()
        params = {**parameters, "fig_dir": str(staged_figs.resolve())}
        declared = check_parameters(notebook, params)
        exporter = WarmExporter()  # readies the page's exporter while the kernel runs
        error: Exception | None = None
        for attempt in range(1, KERNEL_START_ATTEMPTS + 1):
            error = executed = None
            try:
                if manager is None:  # a kernel started again
                    shutil.rmtree(sockets, ignore_errors=True)
                    sockets = Path(tempfile.mkdtemp(prefix="robomill-kernel-"))
                    manager = start_kernel(kernel, sockets, cwd)
                executed = pm.execute_notebook(
                    str(notebook), str(staged_nb), parameters=params, kernel_name=kernel,
                    km=manager, start_timeout=start_timeout_s,
                    execution_timeout=execution_timeout_s,
                    cwd=str(cwd) if cwd else None, progress_bar=False, log_output=False,
                )
            except Exception as exc:  # papermill raises PapermillExecutionError, others
                error = exc
            finally:
                if manager is not None:
                    stop_kernel(manager)
                    manager = None
                shutil.rmtree(sockets, ignore_errors=True)
            if error is None or not _kernel_never_ran(staged_nb):
                break
            log.warning("chapter %s: kernel did not start (%s), attempt %d of %d",
                        notebook, error, attempt, KERNEL_START_ATTEMPTS)
        # the executed notebook as papermill returns it (the same as the file it wrote), or
        # what was written of it when execution failed
        nb = executed if error is None and executed is not None else (
            nbformat.read(staged_nb, as_version=4) if staged_nb.exists() else None)
        problems = notebook_errors(nb) if nb is not None else []
        if error is not None or problems:
            kept = None
            if failed_copy is not None and staged_nb.exists():
                kept = Path(failed_copy)
                kept.parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(staged_nb, kept)
            first = problems[0] if problems else f"{type(error).__name__}: {error}"
            raise ChapterError(
                f"chapter notebook {notebook} failed: {first.splitlines()[0]}"
                + (f"; executed notebook kept at {kept}" if kept else "")
            )
        if shown is None:
            shown = {k: v for k, v in params.items() if k != "fig_dir"}
        root = Path(cwd) if cwd else Path.cwd()
        body = document_html(nb, _parameter_table(shown, declared, root), replace={
            str(staged_figs.resolve()): shown_value(str(fig_dir.resolve()), root),
            str(stage.resolve()): shown_value(str(out_ipynb.parent.resolve()), root)},
            exporter=exporter.get())
        (stage / out_html.name).write_text(body)
        # move into place: figures first, the notebook and the page last
        if fig_dir.exists():
            shutil.rmtree(fig_dir)
        shutil.move(str(staged_figs), fig_dir)
        shutil.move(str(staged_nb), out_ipynb)
        shutil.move(str(stage / out_html.name), out_html)
    finally:
        if manager is not None:  # refused before execution
            stop_kernel(manager)
        shutil.rmtree(sockets, ignore_errors=True)
        shutil.rmtree(stage, ignore_errors=True)
