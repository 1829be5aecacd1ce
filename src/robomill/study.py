"""The study as one artefact: ``results/ingest/study.yaml``.

The raw folder's ``manifest.yaml`` (synthetic mode: the manifest the simulators wrote) is
read and validated once, by the ingestion rule, and written here with every cut's design
resolved: its own keys, and under ``process`` the values it is cut with (its own, else the
experiment's, else the defaults: :func:`robomill.experiment.cut_process`). Every analysis
rule reads the study from this file (:func:`load_study`), never the manifest: the design
reaches the analyses by one channel. The files are still verified against their sha256
where they are read (:meth:`robomill.io.manifest.Manifest.verify_file`), so a raw file
changed after ingestion stops the job that reads it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

from robomill.errors import RawDataError
from robomill.experiment import Cut, cut_process, tracker_run
from robomill.io.manifest import SAFE_LOADER, Manifest, parse_manifest

HEADER = ("# The study as the analyses read it (robomill.study): written by the ingestion rule\n"
          "# from the manifest named below; do not edit (edit the manifest).\n")


def resolved_process(cut: Cut, experiment: dict[str, Any]) -> dict[str, Any] | None:
    """The cut's process (:func:`robomill.experiment.cut_process`), or ``None`` where the
    study does not give what it needs (a folder whose chapters need no spindle speed)."""
    try:
        return cut_process(cut, experiment)
    except (KeyError, TypeError, ValueError):
        return None


def study_dict(manifest: Manifest) -> dict[str, Any]:
    """The mapping written to ``study.yaml``: where the manifest is, the experiment, every
    cut with its resolved ``process``, the files with their metadata and sha256 (a tracker
    run with its ``run`` id, :func:`robomill.experiment.tracker_run`), the cell
    file, and the manifest's other top-level keys (``extra``)."""
    cuts = []
    for c in manifest.cuts:
        entry = c.as_dict()
        entry["process"] = resolved_process(c, manifest.experiment)
        cuts.append(entry)
    return {
        "manifest": manifest.path.as_posix(),
        "raw_dir": manifest.raw_dir.as_posix(),
        "cell": manifest.cell_file,
        "experiment": dict(manifest.experiment),
        "cuts": cuts,
        "files": [({**f, "run": tracker_run(f)} if f["kind"] == "tracker" else dict(f))
                  for f in manifest.files],
        "extra": dict(manifest.extra),
    }


def write_study(manifest: Manifest, path: str | Path) -> Path:
    """Write ``study.yaml`` (atomically) from a validated manifest."""
    from robomill.io.atomic import atomic_path

    with atomic_path(path) as tmp:
        tmp.write_text(HEADER + yaml.safe_dump(study_dict(manifest), sort_keys=False,
                                               width=100))
    return Path(path)


def load_study(path: str | Path) -> Manifest:
    """The study written by :func:`write_study`, as the validated
    :class:`~robomill.io.manifest.Manifest` it was written from (same cuts, files and
    experiment; files verified against the raw folder where they are read).

    Raises
    ------
    RawDataError
        The file is missing or is not a study written by :func:`write_study`.
    """
    path = Path(path)
    try:
        data = yaml.load(path.read_text(), Loader=SAFE_LOADER)
    except (OSError, yaml.YAMLError) as exc:
        raise RawDataError(path, f"cannot read the study ({' '.join(str(exc).split())})",
                           expected="results/ingest/study.yaml as the ingestion rule wrote "
                                    "it (rerun snakemake)") from None
    if not isinstance(data, dict) or not {"manifest", "experiment", "cuts", "files"} <= set(
            data):
        raise RawDataError(path, "not a study file", expected="keys manifest, experiment, "
                           "cuts, files (written by the ingestion rule)")
    own = [{k: v for k, v in c.items() if k != "process"} for c in data["cuts"]]
    return parse_manifest({"experiment": data["experiment"], "cuts": own,
                           "files": data["files"], **(data.get("extra") or {})},
                          data["manifest"])

