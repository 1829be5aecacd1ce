"""sha256 digests of files and of configuration sections (provenance, manifest checks)."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any


def sha256_file(path: str | Path, *, chunk_bytes: int = 1 << 20) -> str:
    """Hex sha256 of a file, read in chunks (works for multi-GB force records)."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        while block := fh.read(chunk_bytes):
            h.update(block)
    return h.hexdigest()


def config_digest(section: Any) -> str:
    """Short, stable digest of a (nested) configuration section.

    The section is serialised as canonical JSON (sorted keys), so the digest changes only when
    a value changes, never with key order.
    """
    blob = json.dumps(section, sort_keys=True, default=str, separators=(",", ":"))
    return hashlib.sha256(blob.encode()).hexdigest()[:16]
