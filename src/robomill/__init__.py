"""robomill: a reproducible pipeline for a study of robotic milling quality.

The science library: pure functions on numpy/xarray, one module per subject. The Snakemake
workflow (``Snakefile``, ``workflow/``) and the chapter notebooks call it.

Importing the package runs nothing else: ``robomill.open_artefact``, ``write_artefact`` and
``list_artefacts`` are looked up on first use (PEP 562), so ``import robomill.spectra`` loads
neither xarray's writer nor the pipeline's tooling.
"""

from robomill.lazy import lazy_exports

__version__ = "0.1.0"

_EXPORTS = {  # module → its public names
    "robomill.io.artefacts": ("open_artefact", "write_artefact"),
    "robomill.pipeline.catalog": ("list_artefacts",),
}

__getattr__, __dir__, _LAZY = lazy_exports(__name__, _EXPORTS)
__all__ = ["__version__", *_LAZY]
