"""The study as one artefact: ``results/ingest/study.yaml``.

The raw folder's ``manifest.yaml`` (synthetic mode: the manifest the simulators wrote) is
read and validated once, by the ingestion rule, and written here with every cut's design
resolved: its own keys, and under ``process`` the values it is cut with (its own, else the
experiment's, else the defaults: :func:`robomill.experiment.cut_process`). Every analysis
rule reads the study from this file (:func:`load_study`), never the manifest: the design
reaches the analyses by one channel. The files are still verified against their sha256
where they are read (:meth:`robomill.io.manifest.Manifest.verify_file`), so a raw file
changed after ingestion stops the job that reads it.

:func:`read_study` returns the typed study (:class:`Study`): every cut as a
:class:`StudyCut` with its own resolved speed, flutes, depth, feed direction and tool, as the
ingestion rule resolved them; a chapter groups the cuts by what they share, never by their
ids. The experiment's block layout (where the thesis' U segments sit, for cuts without
``start_mm``) is the manifest's, else the one the ingestion rule was handed (the virtual
cell's configuration), resolved into the study once.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from robomill.errors import RawDataError
from robomill.experiment import Cut, cut_process, feed_direction, tracker_run
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


def study_dict(manifest: Manifest, layout: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The mapping written to ``study.yaml``: where the manifest is, the experiment (with
    ``layout``, the block layout, where the manifest gives none and one is handed over), every
    cut with its resolved ``process``, the files with their metadata and sha256 (a tracker
    run with its ``run`` id, :func:`robomill.experiment.tracker_run`), the cell
    file, and the manifest's other top-level keys (``extra``)."""
    experiment = dict(manifest.experiment)
    if experiment.get("layout") is None and layout is not None:
        experiment["layout"] = dict(layout)
    cuts = []
    for c in manifest.cuts:
        entry = c.as_dict()
        entry["process"] = resolved_process(c, manifest.experiment)
        cuts.append(entry)
    return {
        "manifest": manifest.path.as_posix(),
        "raw_dir": manifest.raw_dir.as_posix(),
        "cell": manifest.cell_file,
        "experiment": experiment,
        "cuts": cuts,
        "files": [({**f, "run": tracker_run(f)} if f["kind"] == "tracker" else dict(f))
                  for f in manifest.files],
        "extra": dict(manifest.extra),
    }


def write_study(manifest: Manifest, path: str | Path,
                layout: Mapping[str, Any] | None = None) -> Path:
    """Write ``study.yaml`` (atomically) from a validated manifest (``layout``: the block
    layout where the manifest gives none, :func:`study_dict`)."""
    from robomill.io.atomic import atomic_path

    with atomic_path(path) as tmp:
        tmp.write_text(HEADER + yaml.safe_dump(study_dict(manifest, layout), sort_keys=False,
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
    return read_study(path).manifest


@dataclass(frozen=True)
class StudyCut:
    """One cut of the study as the analyses read it: its own keys and the process the
    ingestion rule resolved for it (its own value, else the experiment's, else the default:
    :func:`robomill.experiment.cut_process`). ``direction`` names the feed direction
    (``px``, ``mx``, ``py``, ``my``, or ``d<deg>`` for a cut given by ``direction_deg``);
    ``feed_xy`` is its unit vector in the base XY plane. Process values are None where the
    study does not give them (a folder whose chapters need no spindle speed)."""

    id: str
    direction: str
    direction_deg: float
    feed_xy: tuple[float, float]
    feed_mm_s: float | None
    depth_mm: float | None
    spindle_rpm: float | None
    flutes: int | None
    tool_diameter_mm: float | None
    radial_immersion: float | None
    milling: str | None
    cut: Cut

    @property
    def tool(self) -> tuple[int | None, float | None, float | None, str | None]:
        """What the cut was made with: ``(flutes, tool_diameter_mm, radial_immersion,
        milling)``."""
        return (self.flutes, self.tool_diameter_mm, self.radial_immersion, self.milling)


def direction_name(cut: Cut, deg: float) -> str:
    """The name of a cut's feed direction: its ``direction`` (``px`` …), else ``d<deg>``
    (``d45``, ``d-12.5``: the form of a tracker run given by ``direction_deg``)."""
    return cut.direction if cut.direction else f"d{deg:g}"


def study_cut(cut: Cut, experiment: Mapping[str, Any]) -> StudyCut:
    """The :class:`StudyCut` of a cut that no ingestion resolved (a cut list handed to
    ``robomill predict``), its process resolved as the ingestion rule resolves a study's
    cuts (:func:`resolved_process`, the same routine). A study's own cuts come resolved
    from ``study.yaml`` (:func:`read_study`): never resolve them again."""
    return _study_cut(cut, resolved_process(cut, dict(experiment)))


def _study_cut(cut: Cut, process: Mapping[str, Any] | None) -> StudyCut:
    proc = dict(process or {})
    deg = proc.get("direction_deg")
    if deg is None:
        deg = float(np.degrees(np.arctan2(*feed_direction(cut)[1::-1])))
    u = feed_direction(cut)
    return StudyCut(
        id=cut.id, direction=direction_name(cut, float(deg)), direction_deg=float(deg),
        feed_xy=(float(u[0]), float(u[1])), feed_mm_s=cut.feed_mm_s, depth_mm=cut.depth_mm,
        spindle_rpm=proc.get("spindle_rpm"), flutes=proc.get("flutes"),
        tool_diameter_mm=proc.get("tool_diameter_mm"),
        radial_immersion=proc.get("radial_immersion"), milling=proc.get("milling"), cut=cut)


@dataclass(frozen=True)
class Study:
    """The study (``results/ingest/study.yaml``): the validated manifest it was written from
    (files verified against their sha256 where they are read), the experiment and every cut
    with its resolved process (:class:`StudyCut`), in the manifest's order."""

    path: Path
    manifest: Manifest
    cuts: tuple[StudyCut, ...]

    @property
    def experiment(self) -> dict[str, Any]:
        return dict(self.manifest.experiment)

    @property
    def files(self) -> list[dict[str, Any]]:
        return self.manifest.files

    def cut(self, cut_id: str) -> StudyCut:
        """The cut ``cut_id``; ``KeyError`` naming the study when it has none."""
        for c in self.cuts:
            if c.id == cut_id:
                return c
        raise KeyError(f"{self.path}: no cut {cut_id!r}")

    def kinds(self) -> set[str]:
        """The raw-data kinds the study's files are of."""
        return {f["kind"] for f in self.manifest.files}


def read_study(path: str | Path) -> Study:
    """The study written by :func:`write_study`, typed (:class:`Study`): the one loader of
    the study for the rule scripts and chapters.

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
    manifest = parse_manifest({"experiment": data["experiment"], "cuts": own,
                               "files": data["files"], **(data.get("extra") or {})},
                              data["manifest"])
    cuts = tuple(_study_cut(c, raw.get("process"))
                 for c, raw in zip(manifest.cuts, data["cuts"], strict=True))
    return Study(path, manifest, cuts)

