"""One study from several raw folders (config ``data.raw_dirs``, in order).

A study may name the original experiment's folder and, after it, each run of planned cuts
(the next run of a plan writes its raw files under
``results/plan/next/run/results/synthetic/raw``). The analyses read one manifest: the
folders' manifests merged here into one :class:`~robomill.io.manifest.Manifest` whose folder
is the first one. The merge rule (docs/data-contract.md, "Several raw folders"):

- **Cuts** are the cuts of every folder, in folder order. A cut id must name one cut: a later
  folder that lists an id already taken with other files (their sha256) or another design is
  refused in one line; the same cut with the same files (a folder named twice, a copied run)
  is taken once.
- **Per-cut files** (entries with a ``cut`` key: force, profile, tracker runs of a cut,
  recordings) come with their cut. Their ``path`` is rewritten relative to the first folder
  (``os.path.relpath``, so that every rule keeps reading ``<first folder>/<path>``) and the
  entry carries ``folder``: the raw folder it was listed in.
- **Files that are not per-cut** (impact hits, load tests, robot files, ctrack tables,
  tracker runs without a cut): each kind is taken from the first folder that has files of it;
  a later folder's files of a kind already given are left out (the study's modal test, load
  tests and calibration are those of the first folder that made them).
- **cell.yaml** is the first folder's (else the first that has one); every other folder's
  cell file must agree with it (same sha256, or the same YAML mapping), else one line.
- A cut of a later folder keeps its own folder's experiment: each process key the cut leaves
  to the experiment (:data:`robomill.experiment.CUT_PROCESS_KEYS`) and whose value there
  differs from the first folder's is written on the cut.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import yaml

from robomill.errors import RawDataError
from robomill.experiment import CUT_PROCESS_KEYS, Cut
from robomill.io.manifest import SAFE_LOADER, Manifest, load_manifest

SYNTHETIC_RAW_DIR = "results/synthetic/raw"
"""The virtual cell's raw folder (synthetic mode's first folder)."""


def raw_folders(data: dict[str, Any]) -> list[str]:
    """The study's raw folders in order, from the configuration's ``data`` section.

    ``raw_dirs`` names them; empty (the default) means ``[raw_dir]``. With
    ``source: synthetic`` the virtual cell's folder (:data:`SYNTHETIC_RAW_DIR`) is always the
    first, followed by the ``raw_dirs`` entries other than it.
    """
    named = [str(d) for d in data.get("raw_dirs") or []]
    if data.get("source") == "synthetic":
        own = os.path.abspath(SYNTHETIC_RAW_DIR)  # also as a run's folder names it (workdir)
        return [SYNTHETIC_RAW_DIR] + [d for d in named if os.path.abspath(d) != own]
    return named or [str(data["raw_dir"])]


def _cut_files(m: Manifest, cut_id: str) -> set[tuple[str, str]]:
    """What identifies a cut's files across folders: (kind, sha256) of each."""
    return {(f["kind"], f.get("sha256", "")) for f in m.files if f.get("cut") == cut_id}


def _own_experiment(cut: Cut, own: dict[str, Any], first: dict[str, Any]) -> Cut:
    """``cut`` with each process key it takes from its folder's experiment ``own`` written on
    it where ``own`` differs from the study's (first folder's) experiment ``first``."""
    keep = {}
    for k in CUT_PROCESS_KEYS:
        if getattr(cut, k) is None and k in own and own[k] != first.get(k):
            keep[k] = tuple(own[k]) if k == "start_mm" else own[k]
    return replace(cut, **keep) if keep else cut


def _same_cell(a: Path, b: Path) -> bool:
    """Whether two cell files agree (same bytes or the same YAML mapping). A file not yet
    written (the virtual cell's, while the workflow is planned) is compared when the
    ingestion rule merges the folders again."""
    if not (a.exists() and b.exists()) or a.read_bytes() == b.read_bytes():
        return True
    try:
        return yaml.load(a.read_text(), Loader=SAFE_LOADER) == yaml.load(
            b.read_text(), Loader=SAFE_LOADER)
    except yaml.YAMLError:
        return False


def merge_manifests(manifests: Sequence[Manifest]) -> Manifest:
    """One study from the manifests of several raw folders, merged by the rule of this module
    (the first manifest's path, experiment and extra keys; the cuts and files of all).

    Raises
    ------
    RawDataError
        One line: a folder named twice, a cut id given other files or another design by a
        later folder, or a cell file that disagrees with the first.
    """
    first, *later = manifests
    if not later:
        return first
    root = first.raw_dir
    cuts = list(first.cuts)
    files = [dict(f) for f in first.files]
    where_cut = {c.id: first for c in first.cuts}
    kinds = {f["kind"] for f in first.files if "cut" not in f}
    cell_of = first if first.cell_file else None
    seen_dirs = {os.path.abspath(root)}
    for m in later:
        if os.path.abspath(m.raw_dir) in seen_dirs:
            raise RawDataError(m.path, "raw folder named twice", where="data.raw_dirs",
                               expected="each raw folder once")
        seen_dirs.add(os.path.abspath(m.raw_dir))
        taken = set()
        for i, c in enumerate(m.cuts):
            if c.id in where_cut:
                other = where_cut[c.id]
                if _cut_files(m, c.id) != _cut_files(other, c.id) or c != other.cut(c.id):
                    raise RawDataError(m.path, f"cut {c.id!r} is also a cut of "
                                       f"{other.raw_dir} with other files or design",
                                       where=f"cuts[{i}]", expected="each cut id once across "
                                       "data.raw_dirs (rename the cut in one folder)")
                taken.add(c.id)
                continue
            cuts.append(_own_experiment(c, m.experiment, first.experiment))
            where_cut[c.id] = m
        new_kinds = set()
        for f in m.files:
            per_cut = "cut" in f
            if per_cut and f["cut"] in taken:
                continue
            if f["kind"] == "cell":
                if cell_of is None:
                    cell_of = m
                elif not _same_cell(cell_of.raw_dir / cell_of.cell_file, m.raw_dir / f["path"]):
                    raise RawDataError(m.raw_dir / f["path"], "cell file differs from "
                                       f"{cell_of.raw_dir / cell_of.cell_file}",
                                       where="data.raw_dirs", expected="one cell for the "
                                       "study: the same cell.yaml in every raw folder")
                else:
                    continue
            elif not per_cut:
                if f["kind"] in kinds:
                    continue  # the first folder that has this kind gives it
                new_kinds.add(f["kind"])
            # physical paths: <first folder>/<rel> is opened as the OS resolves it, through
            # any link in the first folder's path
            rel = Path(os.path.relpath(os.path.realpath(m.raw_dir / f["path"]),
                                       os.path.realpath(root))).as_posix()
            files.append({**f, "path": rel, "folder": m.raw_dir.as_posix()})
        kinds |= new_kinds
    return Manifest(first.path, dict(first.experiment), cuts, files, dict(first.extra))


def load_study_manifest(paths: str | Path | Sequence[str | Path]) -> Manifest:
    """The study's manifest from the ``manifest.yaml`` of each raw folder, in order
    (:func:`merge_manifests`; one path: that manifest)."""
    if isinstance(paths, str | Path):
        paths = [paths]
    return merge_manifests([load_manifest(p) for p in paths])


def synthetic_plan(config: dict[str, Any]) -> Manifest:
    """The manifest the virtual cell's simulators will write (``data.source: synthetic``),
    planned from the configuration without importing a simulator
    (:func:`robomill.io.synthetic_layout.synthetic_manifest`) and validated as a plan (no
    sha256 yet)."""
    from robomill.io.manifest import parse_manifest
    from robomill.io.synthetic_layout import synthetic_manifest

    path = f"{raw_folders(config['data'])[0]}/manifest.yaml"
    return parse_manifest(synthetic_manifest(config), path, require_sha256=False)


def first_plan(config: dict[str, Any]) -> Manifest:
    """The first raw folder's manifest (``data.raw_dirs[0]``), or for synthetic data the
    virtual cell's (:func:`synthetic_plan`)."""
    if config["data"]["source"] == "synthetic":
        return synthetic_plan(config)
    return load_manifest(f"{raw_folders(config['data'])[0]}/manifest.yaml")


def study_plan(config: dict[str, Any], first: Manifest | None = None) -> Manifest:
    """The study as the workflow's DAG takes its shape from it (cut ids, kinds, files), one
    parser in both modes: the ``manifest.yaml`` of each raw folder (``data.raw_dirs`` in order,
    merged by :func:`merge_manifests`), or for synthetic data (``data.source: synthetic``) the
    manifest the virtual cell's simulators will write (:func:`synthetic_plan`), merged with
    any later raw folder's; ``first``: the first folder's (:func:`first_plan`) when the caller
    has it.

    Raises
    ------
    RawDataError
        A manifest that cannot be read or validated (one line: file, where, what).
    """
    manifests = [f"{d}/manifest.yaml" for d in raw_folders(config["data"])]
    if first is None:
        first = first_plan(config)
    return merge_manifests([first] + [load_manifest(m) for m in manifests[1:]])
