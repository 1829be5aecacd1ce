"""Keep the start-up of every Snakemake run, Slurm job and chapter short.

jsonschema (Snakemake's config validation, nbformat in papermill) imports the optional
``rfc3987_syntax`` whenever it is installed (here it is, through jupyter-events'
``jsonschema[format-nongpl]``), and that module compiles 38 lark grammars at import: measured
on the 2-core development machine, ``import jsonschema`` takes 3.4 s with it and 0.35 s
without. It only adds the ``iri``/``iri-reference`` format checks, which no robomill schema
uses. :func:`skip_iri_format_checks` keeps it out of this process when jsonschema has not been
imported yet; the schemas are still validated by jsonschema in full.

SciPy 1.17's ``@xp_capabilities`` decorator re-parses the docstring of every function it
decorates with its numpydoc scraper (``FunctionDoc``) at import time, only to append an
"Array API Standard Support" note: about 800 docstrings when ``scipy.signal`` is imported,
0.4–0.7 s of every job that uses it (``python -c "import scipy.signal, scipy.stats"``
1.84/2.17 s → 1.43/1.52 s here). :func:`skip_scipy_capability_notes` installs a one-shot
import hook that, once ``scipy._lib._array_api`` has been executed, gives the decorator a
stand-in that leaves each docstring as it was. Nothing else changes: the decorator still
records the capabilities table, and the functions are the same objects. It costs nothing in a
process that never imports SciPy.

At exit, CPython's finalization runs the cyclic garbage collector over every object the
process still holds before it frees them: with Snakemake, or with xarray, SciPy and
matplotlib loaded, that pass alone took 0.25–0.45 s of every process here (``snakemake -j2
all`` with nothing to do: 2.0 s, of which 0.36 s after the last ``atexit`` handler; a rule
script's imports: 1.58 s against 1.31 s with the pass skipped). The memory goes back to the
operating system at exit anyway. :func:`skip_final_collection` registers ``gc.freeze`` as an
``atexit`` handler: objects alive then are moved to the permanent generation, which the
final passes skip; everything is still released by reference counting, files are closed
and flushed as before (HDF5 and the standard streams are closed by their own exit hooks),
and only the finalizers of objects left in reference cycles at exit do not run.

:func:`apply_startup_patches` applies all three. The pipeline's entry points call it, not
``import robomill`` (which stays inert): :mod:`robomill.pipeline` on import (the Snakefile,
``workflow/rules/common.smk`` and every rule script's first line, ``from
robomill.pipeline.runlog import setup``), the ``robomill`` command (:func:`robomill.cli.main`)
and each chapter's kernel (:data:`KERNEL_STARTUP_ARGUMENT`, given to the kernel by
:func:`robomill.pipeline.kernels.private_kernel_manager`).
"""

from __future__ import annotations

import atexit
import gc
import importlib.abc
import importlib.util
import sys

SCIPY_CAPABILITIES_MODULE = "scipy._lib._array_api"


def skip_iri_format_checks() -> bool:
    """Block ``rfc3987_syntax`` for this process; True if it took effect."""
    if "jsonschema" in sys.modules or "rfc3987_syntax" in sys.modules:
        return False
    sys.modules["rfc3987_syntax"] = None  # makes `import rfc3987_syntax` raise ImportError
    return True


class _UnchangedDoc:
    """Stands in for SciPy's ``FunctionDoc`` in ``@xp_capabilities``: the decorator appends
    to ``doc["Notes"]`` and then uses ``str(doc)`` minus its first (signature) line as the new
    docstring, so a leading newline plus the original docstring leaves it unchanged."""

    def __init__(self, func, *args, **kwargs):
        self._doc = getattr(func, "__doc__", None) or ""
        self._sections: dict[str, list] = {}

    def __getitem__(self, section: str) -> list:
        return self._sections.setdefault(section, [])

    def __str__(self) -> str:
        return "\n" + self._doc


class _CapabilityNotesHook(importlib.abc.MetaPathFinder):
    """Finds ``scipy._lib._array_api`` once, runs it, then swaps its ``FunctionDoc``."""

    def find_spec(self, name, path, target=None):
        if name != SCIPY_CAPABILITIES_MODULE:
            return None
        sys.meta_path.remove(self)  # one-shot, and lets the real finders answer below
        spec = importlib.util.find_spec(name)
        if spec is None or spec.loader is None or not hasattr(spec.loader, "exec_module"):
            return spec
        run_module = spec.loader.exec_module

        def exec_module(module):
            run_module(module)
            if isinstance(getattr(module, "FunctionDoc", None), type):
                module.FunctionDoc = _UnchangedDoc

        spec.loader.exec_module = exec_module
        return spec


def skip_scipy_capability_notes() -> bool:
    """Keep SciPy from re-parsing docstrings at import; True if the hook was installed."""
    if SCIPY_CAPABILITIES_MODULE in sys.modules:
        return False
    if not any(isinstance(f, _CapabilityNotesHook) for f in sys.meta_path):
        sys.meta_path.insert(0, _CapabilityNotesHook())
    return True


_FINAL_COLLECTION_SKIPPED = False


def skip_final_collection() -> bool:
    """Skip the garbage collector's passes over this process's objects at exit (``atexit``
    handler ``gc.freeze``); True the first time, False once registered."""
    global _FINAL_COLLECTION_SKIPPED
    if _FINAL_COLLECTION_SKIPPED:
        return False
    atexit.register(gc.freeze)
    _FINAL_COLLECTION_SKIPPED = True
    return True


def apply_startup_patches() -> None:
    """The three patches, for a process that is about to use jsonschema or SciPy and that
    ends with many objects alive (a workflow, a rule script, a chapter kernel)."""
    skip_iri_format_checks()  # before anything imports jsonschema
    skip_scipy_capability_notes()  # before anything imports scipy.signal/stats
    skip_final_collection()


KERNEL_STARTUP_ARGUMENT = ("--IPKernelApp.exec_lines=__import__('robomill._imports')"
                           "._imports.apply_startup_patches()")
"""The kernel command-line option that applies the patches before a notebook's first cell
(IPython runs ``exec_lines`` at start-up without counting them as executed cells)."""
