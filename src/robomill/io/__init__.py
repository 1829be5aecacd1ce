"""Readers, the manifest, and the artefact writer (the only place that touches files)."""

from robomill.errors import ConfigError, RawDataError
from robomill.io.artefacts import open_artefact, write_artefact, write_table
from robomill.io.hashing import config_digest, sha256_file

__all__ = [
    "ConfigError",
    "RawDataError",
    "config_digest",
    "open_artefact",
    "sha256_file",
    "write_artefact",
    "write_table",
]
