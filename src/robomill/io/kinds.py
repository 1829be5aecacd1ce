"""The raw folder's file kinds: each kind's folder and the metadata keys its files carry,
the checks of one ``files`` entry, and the data files of a raw folder.

The manifest's parser (:mod:`robomill.io.manifest`) and the raw-folder tools of the command
line (:mod:`robomill.cli.layout`: ``robomill manifest``, ``robomill check``) read the kinds
here, so neither imports the other.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from robomill.errors import RawDataError
from robomill.experiment import DIRECTION_VECTORS, FREE_CUT_ID, TRACKER_PASSES, tracker_run


@dataclass(frozen=True)
class Kind:
    """One kind of raw data, in one record: everything the project knows about it.

    ``folder``: its folder in the raw folder (``robomill init`` makes it; ``robomill manifest``
    infers the kind of a file in it; None: a file at the top, the cell file); ``keys``: the
    metadata keys every file of the kind carries in the manifest, besides path, kind and
    sha256, with their types; ``check``: the reader ``robomill check`` calls on each file, as
    ``"module:function"`` (``function(path, entry)``; :mod:`robomill.io.kind_checks`), None for
    a kind checked for presence and sha256 only; ``stages``: the stages whose analyses read
    it (``results/<stage>/``)."""

    name: str
    folder: str | None
    keys: Mapping[str, tuple[type, ...]] = field(default_factory=dict)
    check: str | None = None
    stages: tuple[str, ...] = ()

    def checker(self) -> Callable[[Path, Mapping[str, Any]], None] | None:
        """The function :attr:`check` names, imported; None when there is none."""
        if self.check is None:
            return None
        module, _, name = self.check.partition(":")
        return getattr(importlib.import_module(module), name)


_CHECKS = "robomill.io.kind_checks"

KIND_RECORDS: tuple[Kind, ...] = (
    Kind("profile", "profiles", {"cut": (str,)}, f"{_CHECKS}:check_profile", ("surface",)),
    Kind("force", "forces", {"cut": (str,), "fs_hz": (int, float)}, f"{_CHECKS}:check_force",
         ("forces", "chatter")),
    # + direction or direction_deg (robomill.io.kinds.check_file_entry)
    Kind("tracker", "tracker", {"feed_mm_s": (int, float), "fs_hz": (int, float)},
         f"{_CHECKS}:check_tracker", ("straightness",)),
    # CSV hits need 'direction', UFF files need nothing; robomill.io.impact.entry_metadata
    # checks direction, hit, node, response_node, range_N, range_ms2
    Kind("impact", "impact", {}, f"{_CHECKS}:check_impact", ("modal", "chatter")),
    Kind("ctrack", "ctrack", {"table": (str,)}, f"{_CHECKS}:check_ctrack", ("calibration",)),
    Kind("robot", "stiffness", {"robot": (str,)}, f"{_CHECKS}:check_robot", ("stiffness",)),
    Kind("stiffness", "stiffness", {"robot": (str,)}, f"{_CHECKS}:check_stiffness",
         ("stiffness",)),
    Kind("cell", None),
    # recordings of the cut (robomill.io.recordings); optional spindle_rpm, flutes (else the
    # cut's design), fs_hz (CSV), channels (TDMS)
    Kind("sound", "sound", {"cut": (str,)}, f"{_CHECKS}:check_recording", ("chatter",)),
    Kind("vibration", "vibration", {"cut": (str,)}, f"{_CHECKS}:check_recording",
         ("chatter",)),
    Kind("areal", "areal",  # the cut's feed direction in the scan's frame (robomill.io.areal)
         {"cut": (str,), "feed_angle_deg": (int, float)}, f"{_CHECKS}:check_areal",
         ("surface",)),
)
"""Every kind of raw data, one record each (:class:`Kind`); the tables below are read from
here. Adding a kind is one record and its reader (``docs/design.md``, "Adding an instrument
kind")."""

KINDS: dict[str, Kind] = {k.name: k for k in KIND_RECORDS}

KIND_KEYS: dict[str, dict[str, tuple[type, ...]]] = {k.name: dict(k.keys) for k in KIND_RECORDS}
"""Metadata keys required per file kind (:attr:`Kind.keys`)."""

KIND_FOLDERS: dict[str, str] = {k.name: k.folder for k in KIND_RECORDS if k.folder}
"""Folder of each file kind inside the raw folder (the contract's layout; :attr:`Kind.folder`)."""

IGNORED_NAMES = ("manifest.yaml", "cell.yaml", "README.md", ".gitkeep")
"""Files of a raw folder that are not data files listed under ``files``."""


def check_keys(path: Path, where: str, obj: Any, keys: Mapping[str, tuple[type, ...]]) -> None:
    if not isinstance(obj, Mapping):
        raise RawDataError(path, f"{type(obj).__name__} found", where=where,
                           expected="a mapping with keys " + ", ".join(keys))
    for key, types in keys.items():
        if key not in obj:
            raise RawDataError(path, f"key '{key}' is missing", where=where,
                               expected="keys " + ", ".join(keys))
        value = obj[key]
        if isinstance(value, bool) or not isinstance(value, types):
            raise RawDataError(path, f"key '{key}' is {value!r}", where=where,
                               expected=" or ".join(t.__name__ for t in types))


def check_file_entry(path: Path, where: str, f: Mapping[str, Any],
                     earlier: list[dict[str, Any]]) -> None:
    """One ``files`` entry of manifest ``path`` (at ``where``; ``earlier``: the entries
    before it): a known kind, the metadata keys of its kind (:data:`KIND_KEYS`), and a
    tracker run's direction, id, pass and time base."""
    if f["kind"] not in KIND_KEYS:
        raise RawDataError(path, f"unknown kind {f['kind']!r}", where=f"{where}.kind",
                           expected="one of " + ", ".join(KIND_KEYS))
    required = KIND_KEYS[f["kind"]]
    if f["kind"] == "tracker" and f.get("time_base") == "none":  # spatial-only: no rate
        required = {k: v for k, v in required.items() if k != "fs_hz"}
    check_keys(path, f"{where} ({f['path']})", f, required)
    if f["kind"] in ("sound", "vibration"):  # an air pass of the cut: pass: air
        _check_tracker_pass(path, f"{where} ({f['path']})", f)
    if f["kind"] == "tracker":
        _check_tracker_direction(path, f"{where} ({f['path']})", f)
        _check_tracker_run(path, f"{where} ({f['path']})", f, earlier)
        _check_tracker_pass(path, f"{where} ({f['path']})", f)
        if f.get("time_base", "none") != "none":
            raise RawDataError(path, f"time_base is {f['time_base']!r}",
                               where=f"{where} ({f['path']}).time_base",
                               expected="none (a stream without a time base, imported "
                                        "with --spatial-only), or no time_base")


def _check_tracker_direction(path: Path, where: str, f: Mapping[str, Any]) -> None:
    """A tracker run's feed direction: ``direction`` (px, mx, py, my) or ``direction_deg``
    (base XY plane, 0 = +X), exactly one (the same forms as a cut)."""
    direction, deg = f.get("direction"), f.get("direction_deg")
    if (direction is None) == (deg is None):
        raise RawDataError(path, "give one of direction, direction_deg"
                           + (" (both are given)" if direction is not None else ""),
                           where=where, expected="direction (px, mx, py, my) or direction_deg")
    if direction is not None and direction not in DIRECTION_VECTORS:
        raise RawDataError(path, f"direction {direction!r} is unknown",
                           where=f"{where}.direction",
                           expected="one of " + ", ".join(DIRECTION_VECTORS))
    if deg is not None and (isinstance(deg, bool) or not isinstance(deg, int | float)):
        raise RawDataError(path, f"key 'direction_deg' is {deg!r}",
                           where=f"{where}.direction_deg", expected="a number [deg]")


def _check_tracker_run(path: Path, where: str, f: Mapping[str, Any],
                       earlier: list[dict[str, Any]]) -> None:
    """A tracker run's id (its optional ``run`` key, else ``<direction>_f<feed>``,
    :func:`robomill.experiment.tracker_run`): a name of letters, digits, ``_ . -``, and
    each run's id once (two runs of one direction at one feed need their own ``run``)."""
    run = f.get("run")
    if run is not None and (not isinstance(run, str) or not FREE_CUT_ID.match(run)):
        raise RawDataError(path, f"run id {run!r} is malformed", where=f"{where}.run",
                           expected="letters, digits, '_', '.', '-' only ([A-Za-z0-9_.-]+)")
    rid = tracker_run(f)
    for g in earlier:
        if g["kind"] == "tracker" and tracker_run(g) == rid:
            raise RawDataError(path, f"tracker run id {rid!r} also names {g['path']!r}",
                               where=f"{where}.run",
                               expected="a distinct run key for each tracker run of one "
                                        "direction and feed")


def _check_tracker_pass(path: Path, where: str, f: Mapping[str, Any]) -> None:
    """A tracker run's or a recording's ``pass`` (optional): ``loaded`` (default) or ``air``; an
    air pass names the ``cut`` whose path it follows (its loaded pass is that cut's)."""
    value = f.get("pass")
    if value is not None and value not in TRACKER_PASSES:
        raise RawDataError(path, f"pass is {value!r}", where=f"{where}.pass",
                           expected="one of " + ", ".join(TRACKER_PASSES))
    if value == "air" and f.get("cut") is None:
        raise RawDataError(path, "an air pass names no cut", where=f"{where}.cut",
                           expected="the id of the cut whose path the air pass follows")


def ignored(rel_paths: list[str], patterns: list[str]) -> set[str]:
    """The paths of ``rel_paths`` (relative, ``/``-separated) that ``patterns`` match, with
    the rules of ``.gitignore`` (``pathspec.GitIgnoreSpec``: ``*.jpg`` anywhere, ``notes/``
    a folder and all it holds, ``/x`` anchored at the raw folder, ``!keep`` re-includes)."""
    if not patterns:
        return set()
    import pathspec

    spec = pathspec.GitIgnoreSpec.from_lines(patterns)
    return {r for r in rel_paths if spec.match_file(r)}


def data_files(raw_dir: Path, ignore: list[str] | None = None) -> list[Path]:
    """Every data file of the raw folder (hidden files, the manifest and README/.gitkeep
    excluded; the cell file too unless the manifest has a kind ``cell`` to list it; files
    matching the manifest's ``ignore`` patterns, :func:`ignored`), sorted."""
    ignored_names = [n for n in IGNORED_NAMES if not (n == "cell.yaml" and "cell" in KIND_KEYS)]
    out = []
    for p in sorted(raw_dir.rglob("*")):
        rel = p.relative_to(raw_dir)
        if (p.is_file() and not any(part.startswith(".") for part in rel.parts)
                and not (len(rel.parts) == 1 and p.name in ignored_names)
                and p.name not in ("README.md", ".gitkeep")):
            out.append(p)
    skip = ignored([p.relative_to(raw_dir).as_posix() for p in out], ignore or [])
    return [p for p in out if p.relative_to(raw_dir).as_posix() not in skip]


