"""Which library files a rule's script and notebook import: the rule's ``code`` inputs.

Snakemake reruns a job when its script changes, but not when a library module the script
imports changes. The workflow therefore declares, as inputs of every rule, the files of the
``robomill`` modules its script and notebook import — followed through the import graph
(a module's own ``robomill`` imports, lazy ones inside functions included, and the
``__init__.py`` of every package on the way, which Python runs on import; a name a package
exports lazily, :mod:`robomill.lazy`, leads to the module its table names). Editing any of
them makes ``make why`` list the rule ("input changed").

Only :mod:`ast` and the standard library are used (no module is imported), and every
file's imports are cached by path, size and modification time — in memory and, with
:func:`load_cache` / :func:`save_cache`, in a JSON file between Snakemake runs (the workflow
keeps it in ``.snakemake/robomill-codedeps.json``) — so planning the DAG stays fast.
"""

from __future__ import annotations

import ast
import json
import os
from collections.abc import Iterable
from pathlib import Path

PACKAGE = "robomill"

_CACHE: dict[tuple[str, int, int], frozenset[str]] = {}
_DIRTY = False


def load_cache(path: str | Path) -> int:
    """Read cached imports from ``path`` (missing or unreadable: ignored); entries read."""
    try:
        entries = json.loads(Path(path).read_text())
    except (OSError, ValueError):
        return 0
    for e in entries if isinstance(entries, list) else []:
        try:
            _CACHE[(e["path"], int(e["size"]), int(e["mtime_ns"]))] = frozenset(e["imports"])
        except (KeyError, TypeError, ValueError):
            continue
    return len(_CACHE)


def save_cache(path: str | Path) -> bool:
    """Write the cache to ``path`` when new files were parsed since :func:`load_cache`
    (atomically; an unwritable place is ignored). True when written."""
    global _DIRTY
    if not _DIRTY:
        return False
    entries = [{"path": p, "size": size, "mtime_ns": m, "imports": sorted(names)}
               for (p, size, m), names in _CACHE.items()]
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f"{path.name}.{os.getpid()}.tmp")
        tmp.write_text(json.dumps(entries))
        tmp.replace(path)
    except OSError:
        return False
    _DIRTY = False
    return True


def _stat_key(path: Path) -> tuple[str, int, int]:
    st = path.stat()
    return str(path), st.st_size, st.st_mtime_ns


def _imports_in_source(source: str, module: str | None, is_package: bool) -> set[str]:
    """Dotted names a source imports (``from a.b import c`` gives ``a.b`` and ``a.b.c``;
    relative imports resolved against ``module``)."""
    try:
        tree = ast.parse(source)
    except SyntaxError:
        return set()
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                if module is None:
                    continue
                parts = module.split(".")
                if not is_package:
                    parts = parts[:-1]
                parts = parts[: len(parts) - (node.level - 1)] if node.level > 1 else parts
                base = ".".join(parts + ([base] if base else []))
            found.add(base)
            found.update(f"{base}.{alias.name}" for alias in node.names if alias.name != "*")
    return {n for n in found if n == PACKAGE or n.startswith(PACKAGE + ".")}


def _notebook_source(path: Path) -> str:
    """The code cells of an .ipynb, IPython magics and shell lines blanked."""
    nb = json.loads(path.read_text())
    lines = []
    for cell in nb.get("cells", []):
        if cell.get("cell_type") != "code":
            continue
        src = cell.get("source", "")
        src = "".join(src) if isinstance(src, list) else src
        for line in src.splitlines():
            lines.append("" if line.lstrip().startswith(("%", "!")) else line)
    return "\n".join(lines)


def file_imports(path: str | Path, src_root: str | Path | None = None) -> frozenset[str]:
    """``robomill`` names imported by a script, a module or a notebook (cached)."""
    path = Path(path)
    key = _stat_key(path)
    if key in _CACHE:
        return _CACHE[key]
    module, is_package = None, False
    if src_root is not None and path.suffix == ".py":
        try:
            rel = path.resolve().relative_to(Path(src_root).resolve()).with_suffix("")
            parts = list(rel.parts)
            is_package = parts[-1] == "__init__"
            module = ".".join(parts[:-1] if is_package else parts)
        except ValueError:
            module = None
    source = _notebook_source(path) if path.suffix == ".ipynb" else path.read_text()
    names = frozenset(_imports_in_source(source, module, is_package))
    global _DIRTY
    _CACHE[key] = names
    _DIRTY = True
    return names


def module_file(name: str, src_root: str | Path) -> Path | None:
    """The file of a dotted module name (``robomill.io.manifest`` →
    ``<src_root>/robomill/io/manifest.py`` or ``…/manifest/__init__.py``); None when the
    name is not a module (an attribute imported from a package)."""
    base = Path(src_root).joinpath(*name.split("."))
    for candidate in (base.with_suffix(".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def lazy_table(init: Path, package: str) -> dict[str, str]:
    """``{public name: full module name}`` of the ``lazy_exports(__name__, TABLE)`` call in
    ``init``, the ``__init__.py`` of ``package`` (``TABLE`` a dict literal, inline or bound
    at module level); empty for a package without one. Read with :mod:`ast`, not imported."""
    try:
        tree = ast.parse(init.read_text())
    except (OSError, SyntaxError):
        return {}
    bound = {t.id: node.value for node in tree.body if isinstance(node, ast.Assign)
             for t in node.targets if isinstance(t, ast.Name)}
    found: dict[str, str] = {}
    for node in ast.walk(tree):
        if not (isinstance(node, ast.Call) and getattr(node.func, "id", None) == "lazy_exports"
                and len(node.args) == 2):
            continue
        table = node.args[1]
        table = bound.get(table.id, table) if isinstance(table, ast.Name) else table
        try:
            literal = ast.literal_eval(table)
        except ValueError:
            continue
        for module, names in literal.items():
            full = module if "." in module else f"{package}.{module}"
            found.update({name: full for name in names if isinstance(names, list | tuple)})
    return found


_DEPS: dict[tuple[str, Path], tuple[Path | None, frozenset[str]]] = {}
_lazy_tables: dict[Path, dict[str, str]] = {}


def _direct(name: str, src_root: Path) -> tuple[Path | None, frozenset[str]]:
    """(file of ``name`` or None, names importing it runs directly: its parent packages and
    the library modules its file imports); memoised for the process."""
    key = (name, src_root)
    if key not in _DEPS:
        parts = name.split(".")
        deps = {".".join(parts[:i]) for i in range(1, len(parts))}
        f = module_file(name, src_root)
        if f is not None:
            deps |= set(file_imports(f, src_root))
        elif len(parts) > 1:  # an attribute of a package: lazily exported from its module?
            init = module_file(".".join(parts[:-1]), src_root)
            if init is not None and init.name == "__init__.py":
                lazy = _lazy_tables.setdefault(init, lazy_table(init, ".".join(parts[:-1])))
                if parts[-1] in lazy:
                    deps.add(lazy[parts[-1]])
        _DEPS[key] = (f, frozenset(deps - {name}))
    return _DEPS[key]


def code_files(sources: Iterable[str | Path], src_root: str | Path) -> list[str]:
    """Every library file the ``sources`` (scripts, notebooks) import, directly or through
    other library modules, with the ``__init__.py`` of each package on the way; sorted
    paths. (The import graph is memoised for the process: files are not expected to change
    while one Snakemake run plans its DAG.)"""
    src_root = Path(src_root)
    todo: set[str] = set()
    for s in sources:
        if s and os.path.exists(s):
            todo |= set(file_imports(s, src_root))
    seen: set[str] = set()
    files: set[Path] = set()
    while todo:
        name = todo.pop()
        seen.add(name)
        f, deps = _direct(name, src_root)
        if f is not None:
            files.add(f)
        todo |= deps - seen
    return sorted(str(f) for f in files)
