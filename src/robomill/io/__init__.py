"""Readers, the manifest, and the artefact writer (the only place that touches files).

The names below are looked up on first use (PEP 562), so that a science module importing one
reader (``robomill.io.forces``) loads neither the artefact writer nor xarray through this
package. The imports stay plain statements inside :func:`__getattr__`, so that the rules'
code inputs (:mod:`robomill.pipeline.codedeps`, which follows imports inside functions)
still see what ``from robomill.io import write_artefact`` runs.
"""

from robomill.errors import ConfigError, RawDataError

__all__ = [
    "ConfigError",
    "RawDataError",
    "config_digest",
    "open_artefact",
    "sha256_file",
    "write_artefact",
    "write_table",
]


def __getattr__(name: str):
    if name in ("open_artefact", "write_artefact", "write_table"):
        from robomill.io import artefacts

        return getattr(artefacts, name)
    if name in ("config_digest", "sha256_file"):
        from robomill.io import hashing

        return getattr(hashing, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
