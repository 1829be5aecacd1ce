"""Provenance of a whole run, shown on the book's title page."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from robomill.io.artefacts import git_commit, package_version
from robomill.io.hashing import config_digest, sha256_file
from robomill.io.rawdirs import raw_folders


def run_provenance(config: Mapping[str, Any], manifest: str | Path | None) -> dict[str, str]:
    """Package version, git commit, config digest, data source (and the manifest's digest)."""
    source = config["data"]["source"]
    where = (", ".join(raw_folders(config["data"])) if source == "raw"
             else "results/synthetic/raw (virtual cell)")
    out = {
        "robomill version": package_version(),
        "git commit": git_commit(),
        "config digest": config_digest(dict(config)),
        "data source": f"{source}: {where}",
    }
    if manifest and Path(manifest).exists():
        out["manifest sha256"] = sha256_file(manifest)
    return out
