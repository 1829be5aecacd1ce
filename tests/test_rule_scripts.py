"""Every rule script is one call into the library with the rule's inputs and outputs.

A script of ``workflow/scripts/`` holds, besides its docstring and imports, exactly one
statement: a call of a library function whose arguments are the rule's own objects
(``snakemake.input``, ``snakemake.output``, ``snakemake.params``, ``snakemake.log[0]`` and the
like), constants, and the log set-up :func:`robomill.pipeline.runlog.setup`. Files are read,
frames built and artefacts written in the library (``robomill.pipeline.jobs``,
``robomill.synth.jobs``), where they can be tested and imported. Read with :mod:`ast`.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SCRIPTS = sorted((REPO / "workflow" / "scripts").glob("*.py"))
#: the one call a script may make inside its call's arguments: its log (robomill.pipeline.runlog)
LOG_SETUP = "setup"


def _plain_argument(node: ast.AST) -> bool:
    """A constant, or ``snakemake`` and attributes/items of it (``snakemake.log[0]``), or the
    log set-up called on such arguments."""
    if isinstance(node, ast.Constant):
        return True
    if isinstance(node, ast.Name):
        return node.id == "snakemake"
    if isinstance(node, ast.Attribute):
        return _plain_argument(node.value)
    if isinstance(node, ast.Subscript):
        return _plain_argument(node.value) and _plain_argument(node.slice)
    if isinstance(node, ast.Call):
        return (isinstance(node.func, ast.Name) and node.func.id == LOG_SETUP
                and all(_plain_argument(a) for a in node.args)
                and all(_plain_argument(k.value) for k in node.keywords))
    return False


def problems(source: str) -> list[str]:
    """Why ``source`` is not a thin rule script (empty when it is)."""
    body = ast.parse(source).body
    found = []
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
            and isinstance(body[0].value.value, str):
        body = body[1:]
    else:
        found.append("no docstring")
    rest = [n for n in body if not isinstance(n, ast.Import | ast.ImportFrom)]
    if len(rest) != 1:
        found.append(f"{len(rest)} statements besides the docstring and imports (expected 1)")
    for node in rest:
        if not (isinstance(node, ast.Expr) and isinstance(node.value, ast.Call)):
            found.append(f"line {node.lineno}: a {type(node).__name__}, not a call")
            continue
        call = node.value
        if not isinstance(call.func, ast.Name | ast.Attribute) or \
                isinstance(call.func, ast.Attribute) and not isinstance(call.func.value, ast.Name):
            found.append(f"line {node.lineno}: the function called is not an imported name")
        for arg in [*call.args, *(k.value for k in call.keywords)]:
            if not _plain_argument(arg):
                found.append(f"line {arg.lineno}: argument {ast.unparse(arg)!r} is not the "
                             "rule's own object, a constant or the log set-up")
    return found


@pytest.mark.parametrize("script", SCRIPTS, ids=[p.name for p in SCRIPTS])
def test_every_rule_script_is_one_library_call(script):
    assert problems(script.read_text()) == []


def test_the_check_finds_thick_scripts():
    assert len(SCRIPTS) > 50
    thin = ('"""Doc."""\nfrom robomill.pipeline.jobs import x\n'
            'from robomill.pipeline.runlog import setup\n\n'
            'x.run(snakemake.input, snakemake.output, snakemake.params,\n'
            '      log=setup(snakemake.log[0], "x"), rule=snakemake.rule)\n')
    assert problems(thin) == []
    two = thin + 'setup(snakemake.log[0], "x").info("done")\n'
    assert "2 statements" in problems(two)[0]
    assigned = thin.replace("x.run(", "log = x.run(")
    assert "a Assign, not a call" in problems(assigned)[0]
    composed = thin.replace("snakemake.input,", "load_study(snakemake.input.study),")
    assert "load_study" in problems(composed)[0]
    looped = thin.replace("snakemake.params,", "{k: snakemake.output[k] for k in OUTPUTS},")
    assert "OUTPUTS" in problems(looped)[0]
    assert problems("from x import y\ny()\n") == ["no docstring"]


# --- the jobs are library functions: callable without Snakemake, with plain objects ---

def test_a_job_runs_without_snakemake(tmp_path):
    """The job behind cell_write.py, called with plain objects in place of Snakemake's named
    lists, writes the cell file the cell reader reads back."""
    import logging
    from types import SimpleNamespace

    from robomill.io.cell import read_cell
    from robomill.pipeline.config import load_config
    from robomill.pipeline.jobs import cell_write

    section = load_config(REPO / "config.yaml")["cell"]
    out = tmp_path / "cell.yaml"
    cell_write.run(SimpleNamespace(), [str(out)], SimpleNamespace(cell=section),
                   log=logging.getLogger("test"))
    assert read_cell(out).robot.name == section["robot"]["name"]


def test_a_job_reports_bad_input_in_one_line_naming_the_file(tmp_path):
    """Bad input raised inside the job, as it was in the script: one line naming the file and
    what is missing (the workflow's failure summary shows that line)."""
    import logging
    from types import SimpleNamespace

    from robomill.pipeline.jobs import chatter_thesis

    modes = tmp_path / "modes.csv"
    modes.write_text("f_n_hz,zeta\n40.0,0.03\n")
    empty = tmp_path / "empty.csv"
    empty.write_text("cut\n")
    inputs = SimpleNamespace(modes=str(modes), coefficients=str(empty), peaks=str(empty),
                             study=str(tmp_path / "study.yaml"))
    with pytest.raises(ValueError) as err:
        chatter_thesis.run(inputs, SimpleNamespace(), SimpleNamespace(),
                           log=logging.getLogger("test"))
    message = str(err.value)
    assert "\n" not in message and str(modes) in message and "k_modal_N_m" in message


def test_the_code_inputs_of_every_script_hold_the_job_it_calls_and_what_that_imports():
    """A rule's ``code`` inputs are the library files its script imports, followed through the
    import graph (``code_inputs`` in common.smk): the job module is among them, and so is every
    library module the job imports, so that editing the moved logic reruns the rule."""
    from robomill.pipeline.codedeps import code_files, file_imports, module_file

    src = REPO / "src"
    for script in SCRIPTS:
        called = ast.parse(script.read_text()).body[-1].value.func
        name = called.value.id if isinstance(called, ast.Attribute) else called.id
        module = next(f"{n.module}.{a.name}" if n.module.endswith(".jobs") else n.module
                      for n in ast.parse(script.read_text()).body
                      if isinstance(n, ast.ImportFrom) for a in n.names if a.name == name)
        job = module_file(module, src)
        assert job is not None, (script.name, module)
        code = set(code_files([script], src))
        assert str(job) in code, script.name
        own = {module_file(m, src) for m in file_imports(job, src)} - {None}
        assert {str(f) for f in own} <= code, script.name
