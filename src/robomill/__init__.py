"""robomill: a reproducible pipeline for a study of robotic milling quality.

The science library: pure functions on numpy/xarray, one module per subject. The Snakemake
workflow (``Snakefile``, ``workflow/``) and the chapter notebooks call it.

Importing the package runs nothing else: ``robomill.open_artefact``, ``write_artefact`` and
``list_artefacts`` are looked up on first use (PEP 562), so ``import robomill.spectra`` loads
neither xarray's writer nor the pipeline's tooling. The start-up patches of
:mod:`robomill._imports` are applied by the pipeline's entry points (the Snakefile, the
``robomill`` command, the rule scripts and the chapter kernels), not here.
"""

import importlib

__version__ = "0.1.0"

_LAZY = {  # name: the module that defines it
    "open_artefact": "robomill.io.artefacts",
    "write_artefact": "robomill.io.artefacts",
    "list_artefacts": "robomill.pipeline.catalog",
}

__all__ = ["__version__", "list_artefacts", "open_artefact", "write_artefact"]


def __getattr__(name: str):
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
