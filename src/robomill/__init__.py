"""robomill: a reproducible pipeline for a study of robotic milling quality.

The science library: pure functions on numpy/xarray, one module per subject. The Snakemake
workflow (``Snakefile``, ``workflow/``) and the chapter notebooks call it.
"""

__version__ = "0.1.0"

from robomill._imports import skip_iri_format_checks, skip_scipy_capability_notes  # noqa: E402

skip_iri_format_checks()  # before anything imports jsonschema (see robomill._imports)
skip_scipy_capability_notes()  # before anything imports scipy.signal/stats (same module)

from robomill.io.artefacts import open_artefact, write_artefact  # noqa: E402
from robomill.pipeline.catalog import list_artefacts  # noqa: E402

__all__ = ["__version__", "list_artefacts", "open_artefact", "write_artefact"]
