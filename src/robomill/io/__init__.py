"""Readers, the manifest, and the artefact writer (the only place that touches files).

The names below are looked up on first use (PEP 562, :mod:`robomill.lazy`), so that a science
module importing one reader (``robomill.io.forces``) loads neither the artefact writer nor
xarray through this package; the rules' code inputs (:mod:`robomill.pipeline.codedeps`) read
the table, and see what ``from robomill.io import write_artefact`` runs.
"""

from robomill.errors import ConfigError, RawDataError
from robomill.lazy import lazy_exports

_EXPORTS = {  # submodule → its public names
    "artefacts": ("open_artefact", "write_artefact", "write_table"),
    "hashing": ("config_digest", "sha256_file"),
}

__getattr__, __dir__, _LAZY = lazy_exports(__name__, _EXPORTS)
__all__ = ["ConfigError", "RawDataError", *_LAZY]
