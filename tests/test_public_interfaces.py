"""robomill uses other libraries through their public interfaces only: no private names of
another library (``_name`` attributes, ``_private`` modules, ``getattr(x, "_name")``) and no
assignment to another library's attributes (no monkeypatching).

The check reads the source with :mod:`ast` (nothing is imported). "Another library" is
anything that is not robomill: a name bound by ``import``/``from ... import`` of a module
outside robomill, and a variable bound, in the same function or module, to an expression
rooted at such a name (``spec = importlib.util.find_spec(...)``). A private attribute is one
whose name begins with ``_`` and that robomill itself does not define (a function, class,
module-level name, class field or ``self._x`` of robomill's own code): its own private
helpers may be called from another of its modules, a library's may not.

Dunder names (``__version__``, ``__name__``, ``__file__``, ``__doc__``) are allowed: they are
the language's data model, the same for every module and object, not a library's private
state; except those that read or rebuild an object's whole internal state
(:data:`STATE_DUNDERS`: a pickled Matplotlib figure's ``__getstate__`` is its private
attributes).

Assignments: to an attribute of another library's module or class (a name bound by an
import, or an alias of an attribute of one), item assignments into such an attribute
(``sys.modules[k] = None``), ``setattr``/``delattr`` on one, and an attribute of any other
object replaced by a function or class (``loader.exec_module = mine``: behaviour swapped).
Setting a field of an object a library returned to hold data (``ds.attrs[...]``,
``df.columns``) is that object's public use and is not listed.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
ROOTS = (REPO / "src", REPO / "workflow" / "scripts")
OWN_PACKAGE = "robomill"

#: (file relative to the repository, the offending text) → why no public interface exists.
#: Keep it short; every entry needs its reason.
ALLOWED: dict[tuple[str, str], str] = {}

#: assignment targets that the library documents as meant to be assigned, anywhere → why
DOCUMENTED_TARGETS: dict[str, str] = {
    "os.environ": "the os module documents os.environ as the mapping to change the "
                  "environment of this process and the processes it starts",
    "sys.stderr": "the sys module documents that the standard streams may be replaced by "
                  "any file object (a rule script sends its stderr to its log)",
}

#: dunders that expose or rebuild an object's whole internal state
STATE_DUNDERS = frozenset({"__getstate__", "__setstate__", "__reduce__", "__reduce_ex__",
                           "__dict__"})


def _python_files() -> list[Path]:
    return sorted(p for root in ROOTS for p in root.rglob("*.py")
                  if "__pycache__" not in p.parts and ".egg-info" not in str(p))


def _is_dunder(name: str) -> bool:
    return len(name) > 4 and name.startswith("__") and name.endswith("__")


def _is_private(name: str) -> bool:
    return name.startswith("_") and not _is_dunder(name)


def _is_own_module(module: str) -> bool:
    return module == OWN_PACKAGE or module.startswith(OWN_PACKAGE + ".")


def _own_private_names(trees: dict[Path, ast.AST]) -> set[str]:
    """Every ``_name`` robomill's own code defines (so that using one is not a library's)."""
    names: set[str] = set()
    for tree in trees.values():
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
                names.add(node.name)
            elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
                names.add(node.id)
            elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
                names.add(node.target.id)
            elif (isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store)
                  and isinstance(node.value, ast.Name) and node.value.id in ("self", "cls")):
                names.add(node.attr)
            elif isinstance(node, ast.alias) and node.asname:
                names.add(node.asname)
            elif isinstance(node, ast.arg):
                names.add(node.arg)
    return {n for n in names if _is_private(n)}


def _root_name(node: ast.AST) -> str | None:
    """``a`` of ``a.b.c``, ``a.b(...)``, ``a[0].b``; None for anything else."""
    while isinstance(node, ast.Attribute | ast.Call | ast.Subscript):
        node = node.func if isinstance(node, ast.Call) else node.value
    return node.id if isinstance(node, ast.Name) else None


@dataclass
class Finding:
    path: str
    line: int
    text: str
    what: str

    def __str__(self) -> str:
        return f"{self.path}:{self.line}: {self.what}: {self.text}"


class _Scope(ast.NodeVisitor):
    """Walks one module. ``modules`` holds the names bound to another library's module or
    class in the scope being visited (by an import, or as an alias of one of their
    attributes), ``objects`` the names bound to what a call into one returned; ``own_defs``
    the functions and classes defined in this file. Each function gets a copy of its
    enclosing scope's names."""

    def __init__(self, path: str, own_private: set[str], own_defs: set[str]) -> None:
        self.path = path
        self.own_private = own_private
        self.own_defs = own_defs
        self.modules: set[str] = set()
        self.objects: set[str] = set()
        self.found: list[Finding] = []

    def _add(self, node: ast.AST, what: str) -> None:
        self.found.append(Finding(self.path, node.lineno, ast.unparse(node), what))

    # -- names bound to other libraries
    def visit_Import(self, node: ast.Import) -> None:
        for alias in node.names:
            if not _is_own_module(alias.name):
                self.modules.add(alias.asname or alias.name.split(".")[0])
                if any(_is_private(p) for p in alias.name.split(".")):
                    self._add(node, "imports another library's private module")

    def visit_ImportFrom(self, node: ast.ImportFrom) -> None:
        module = node.module or ""
        if node.level or _is_own_module(module) or module == "__future__":
            return
        if any(_is_private(p) for p in module.split(".")):
            self._add(node, "imports from another library's private module")
        for alias in node.names:
            if _is_private(alias.name):
                self._add(node, "imports another library's private name")
            self.modules.add(alias.asname or alias.name)

    def _is_module(self, expr: ast.AST) -> bool:
        """``expr`` is another library's module or class, or an attribute of one reached
        without a call (``np``, ``np.linalg``, ``sys.modules``)."""
        while isinstance(expr, ast.Attribute):
            expr = expr.value
        return isinstance(expr, ast.Name) and expr.id in self.modules

    def _is_foreign(self, expr: ast.AST) -> bool:
        root = _root_name(expr)
        return root is not None and (root in self.modules or root in self.objects)

    def _bind(self, target: ast.AST, value: ast.AST | None) -> None:
        if not isinstance(target, ast.Name):
            return
        self.modules.discard(target.id)
        self.objects.discard(target.id)
        if value is None:
            return
        if isinstance(value, ast.Attribute) and self._is_module(value):
            self.modules.add(target.id)
        elif self._is_foreign(value):
            self.objects.add(target.id)

    def visit_Assign(self, node: ast.Assign) -> None:
        self.generic_visit(node)
        for target in node.targets:
            self._check_store(target, node.value)
            self._bind(target, node.value)

    def visit_AnnAssign(self, node: ast.AnnAssign) -> None:
        self.generic_visit(node)
        self._check_store(node.target, node.value)
        self._bind(node.target, node.value)

    def visit_AugAssign(self, node: ast.AugAssign) -> None:
        self.generic_visit(node)
        self._check_store(node.target, node.value)

    def visit_withitem(self, node: ast.withitem) -> None:
        self.generic_visit(node)
        if node.optional_vars is not None:
            self._bind(node.optional_vars, node.context_expr)

    def _replaces_behaviour(self, value: ast.AST | None) -> bool:
        return isinstance(value, ast.Lambda) or (
            isinstance(value, ast.Name) and value.id in self.own_defs)

    def _check_store(self, target: ast.AST, value: ast.AST | None) -> None:
        if isinstance(target, ast.Tuple | ast.List):
            for element in target.elts:
                self._check_store(element, None)
            return
        if isinstance(target, ast.Subscript):
            holder = target.value
            if (isinstance(holder, ast.Attribute) and self._is_module(holder)
                    and ast.unparse(holder) not in DOCUMENTED_TARGETS):
                self._add(target, "assigns into another library's attribute")
            return
        if not isinstance(target, ast.Attribute) or ast.unparse(target) in DOCUMENTED_TARGETS:
            return
        if self._is_module(target.value):
            self._add(target, "assigns to another library's attribute")
        elif _root_name(target) not in ("self", "cls") and self._replaces_behaviour(value):
            self._add(target, "replaces an object's attribute by a function of its own")

    # -- functions get their own scope (their enclosing names stay visible)
    def _visit_function(self, node: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        outer = set(self.modules), set(self.objects)
        for arg in [*node.args.posonlyargs, *node.args.args, *node.args.kwonlyargs]:
            self._bind(ast.Name(arg.arg), None)  # a parameter shadows an outer name
        self.generic_visit(node)
        self.modules, self.objects = outer

    visit_FunctionDef = _visit_function
    visit_AsyncFunctionDef = _visit_function

    # -- private names
    def visit_Attribute(self, node: ast.Attribute) -> None:
        self.generic_visit(node)
        if _is_private(node.attr) and node.attr not in self.own_private:
            self._add(node, "uses another library's private attribute")
        elif node.attr in STATE_DUNDERS and _root_name(node.value) not in ("self", "cls"):
            self._add(node, "reads or rebuilds another object's internal state")

    def visit_Call(self, node: ast.Call) -> None:
        self.generic_visit(node)
        func = node.func
        name = func.id if isinstance(func, ast.Name) else None
        if name in ("getattr", "hasattr", "setattr", "delattr") and len(node.args) >= 2:
            attr = node.args[1]
            if (isinstance(attr, ast.Constant) and isinstance(attr.value, str)
                    and _is_private(attr.value) and attr.value not in self.own_private):
                self._add(node, "uses another library's private attribute by name")
            if name in ("setattr", "delattr") and self._is_foreign(node.args[0]):
                self._add(node, "assigns to another library's attribute")


def scan(files: list[Path] | None = None) -> list[Finding]:
    """Every use of another library's private name and every assignment to another
    library's attribute in ``files`` (default: ``src/`` and ``workflow/scripts/``)."""
    files = _python_files() if files is None else files
    trees = {p: ast.parse(p.read_text(), filename=str(p)) for p in files}
    own = _own_private_names({p: t for p, t in trees.items()})
    found: list[Finding] = []
    for path, tree in trees.items():
        try:
            shown = str(path.relative_to(REPO))
        except ValueError:
            shown = str(path)
        defs = {n.name for n in ast.walk(tree)
                if isinstance(n, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef)}
        visitor = _Scope(shown, own, defs)
        visitor.visit(tree)
        found += visitor.found
    return found


@pytest.fixture(scope="module")
def the_tree_scanned() -> list[Finding]:
    """:func:`scan` of the repository's own code, once for the tests that read it."""
    return scan()


def test_no_private_interface_of_another_library_and_no_monkeypatching(the_tree_scanned):
    found = [f for f in the_tree_scanned if (f.path, f.text) not in ALLOWED]
    assert found == [], "\n".join(map(str, found))


def test_every_allowed_entry_is_still_needed_and_has_a_reason(the_tree_scanned):
    texts = {(f.path, f.text) for f in the_tree_scanned}
    for key, reason in ALLOWED.items():
        assert key in texts, f"{key} is allowed but no longer found: remove it from ALLOWED"
        assert len(reason.split()) >= 5, f"{key}: give the reason no public interface exists"


@pytest.mark.parametrize("source, what", [
    ("from jupyter_client import AsyncKernelClient\n"
     "class C(AsyncKernelClient):\n"
     "    def f(self, reply):\n"
     "        self._handle_kernel_info_reply(reply)\n",
     "uses another library's private attribute"),
    ("from multiprocessing import resource_tracker\n"
     "def stop():\n"
     "    getattr(resource_tracker._resource_tracker, '_stop')()\n",
     "uses another library's private attribute"),
    ("import importlib.util\n"
     "def hook(name):\n"
     "    def mine(module):\n"
     "        pass\n"
     "    spec = importlib.util.find_spec(name)\n"
     "    spec.loader.exec_module = mine\n",
     "replaces an object's attribute by a function of its own"),
    ("import scipy.signal\n"
     "scipy.signal.welch = None\n",
     "assigns to another library's attribute"),
    ("import sys\n"
     "sys.modules['rfc3987_syntax'] = None\n",
     "assigns into another library's attribute"),
    ("from scipy._lib._docscrape import FunctionDoc\n",
     "imports from another library's private module"),
    ("import matplotlib\n"
     "def f(state):\n"
     "    setattr(matplotlib, 'x', 1)\n",
     "assigns to another library's attribute"),
])
def test_the_scan_finds_each_kind_of_private_use(tmp_path, source, what):
    """Each pattern this check exists for is found (in a file of its own)."""
    path = tmp_path / "sample.py"
    path.write_text(source)
    found = scan([path])
    assert [f.what for f in found].count(what) >= 1, found


def test_the_scan_leaves_public_use_and_own_names_alone(tmp_path):
    path = tmp_path / "sample.py"
    path.write_text(
        "import matplotlib.pyplot as plt\n"
        "import numpy as np\n"
        "class Own:\n"
        "    def __init__(self):\n"
        "        self._items = {}\n"
        "    def f(self, other):\n"
        "        other._items.clear()\n"  # robomill's own private name, another of its objects
        "        x = np.zeros(3)\n"
        "        x[0] = 1.0\n"  # an array's element, not an attribute
        "        fig = plt.figure()\n"
        "        fig.set_dpi(100)\n"
        "        return np.__version__, plt.__name__\n")
    assert scan([path]) == []


# --- the workflow: Snakemake's documented interface only --------------------------------

#: the workflow's files: the Snakefile and every rule file
WORKFLOW_FILES = [REPO / "Snakefile", *sorted((REPO / "workflow" / "rules").glob("*.smk"))]
#: attributes of Snakemake's ``workflow`` object that its documentation gives to Snakefiles
DOCUMENTED_WORKFLOW = frozenset({"basedir", "current_basedir", "is_main_process",
                                 "snakefile", "source_path", "get_sources"})
#: Snakemake internals a workflow must not reach: rewriting a rule after it is defined,
#: expanding its inputs by hand, the command line's working directory
INTERNALS = frozenset({"set_input", "set_output", "set_params", "input_modifier",
                       "output_modifier", "modifier", "path_modifier", "expand_input",
                       "expand_output", "overwrite_workdir", "get_path_or_uri"})


def scan_workflow(files: list[Path] | None = None) -> list[Finding]:
    """Every use of an undocumented Snakemake interface in the workflow's files (``Snakefile``
    and the ``.smk`` rule files, read as Python tokens: strings and comments are skipped): an
    attribute of ``workflow`` its documentation does not give, a rule's internals (any
    :data:`INTERNALS` name), ``os.chdir``, and any private ``._name``."""
    import io
    import tokenize

    found: list[Finding] = []
    for path in WORKFLOW_FILES if files is None else files:
        try:
            shown = str(path.relative_to(REPO))
        except ValueError:
            shown = str(path)
        tokens = [t for t in tokenize.generate_tokens(io.StringIO(path.read_text()).readline)
                  if t.type in (tokenize.NAME, tokenize.OP)]
        for a, dot, b in zip(tokens, tokens[1:], tokens[2:], strict=False):
            if dot.string != "." or b.type != tokenize.NAME:
                continue
            text = f"{a.string}.{b.string}"
            what = None
            if a.string == "workflow" and b.string not in DOCUMENTED_WORKFLOW:
                what = "uses an undocumented attribute of Snakemake's workflow"
            elif b.string in INTERNALS:
                what = "reaches Snakemake's rule internals"
            elif text == "os.chdir":
                what = "changes the working directory under Snakemake"
            elif _is_private(b.string):
                what = "uses a private attribute"
            if what:
                found.append(Finding(shown, b.start[0], text, what))
    return found


def test_the_workflow_uses_snakemake_through_its_documented_interface():
    found = scan_workflow()
    assert found == [], "\n".join(map(str, found))


def test_the_workflow_scan_reads_every_rule_file_and_finds_each_kind(tmp_path):
    assert {p.name for p in WORKFLOW_FILES} >= {"Snakefile", "common.smk", "chapter.smk"}
    path = tmp_path / "bad.smk"
    path.write_text("import os\n"
                    "for r in workflow.rules:\n"
                    "    r.set_input('x')\n"
                    "    r.input_modifier = workflow.modifier.path_modifier\n"
                    "    r.expand_input({})\n"
                    "os.chdir('elsewhere')  # os.chdir in a comment is not read\n"
                    "x = rules.a._private\n"
                    "s = 'workflow.overwrite_workdir'\n")
    found = {(f.text, f.what.split()[0]) for f in scan_workflow([path])}
    assert ("workflow.rules", "uses") in found
    assert ("r.set_input", "reaches") in found and ("r.expand_input", "reaches") in found
    assert ("r.input_modifier", "reaches") in found
    assert ("workflow.modifier", "uses") in found
    assert ("os.chdir", "changes") in found and ("a._private", "uses") in found
    assert not any("overwrite_workdir" in t for t, _ in found)  # in a string
    assert sum(t == "os.chdir" for t, _ in found) == 1
