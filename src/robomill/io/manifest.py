"""The raw-data manifest (``manifest.yaml``): what each file is, and its sha256.

Layout (``docs/data-contract.md`` has the full contract)::

    experiment: {spindle_rpm: 28000, flutes: 2, tool_diameter_mm: 6.0, cut_length_mm: 40.0}
    cuts:
      - {id: s1_g1_px, set: 1, segment: 1, direction: px, feed_mm_s: 1.0, depth_mm: 0.25}
    files:
      - {path: profiles/s1_g1_px.csv, kind: profile, cut: s1_g1_px, sha256: "<hex>"}

Ingestion checks each file against its sha256 and never writes into the raw directory.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from robomill.errors import RawDataError
from robomill.experiment import (
    CUT_ID,
    DIRECTION_VECTORS,
    FREE_CUT_ID,
    MILLING,
    Cut,
)
from robomill.io.hashing import sha256_file
from robomill.io.kinds import KIND_FOLDERS, check_file_entry, check_keys, data_files
from robomill.io.needs import (
    chapter_list,
    file_kinds,
    required_cut_keys,
    required_experiment_keys,
)

# the same safe constructor over the C parser when PyYAML was built with libyaml
SAFE_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)

EXPERIMENT_KEYS = {
    "spindle_rpm": (int, float),
    "flutes": (int,),
    "tool_diameter_mm": (int, float),
    "cut_length_mm": (int, float),
}
"""The experiment's process keys and their types; each is required only where a chapter the
folder's kinds feed reads it (:data:`robomill.io.needs.CHAPTER_NEEDS`)."""
CUT_KEYS = {
    "id": (str,),
    "feed_mm_s": (int, float),
    "depth_mm": (int, float),
}
"""Keys a cut carries: ``id`` always, the others where a chapter needs them (every folder
that lists cuts feeds chapter 0, which tables both)."""

CUT_OPTIONAL_KEYS: dict[str, tuple[type, ...]] = {
    "set": (int,),
    "segment": (int,),
    "direction": (str,),
    "direction_deg": (int, float),
    "spindle_rpm": (int, float),
    "flutes": (int,),
    "tool_diameter_mm": (int, float),
    "radial_immersion": (int, float),
    "milling": (str,),
    "start_mm": (list,),
    "redundancy_deg": (int, float),
}
"""Optional cut keys: grouping (``set``, ``segment``), the feed direction (``direction`` or
``direction_deg``, one of them required), the process keys overriding ``experiment`` and the
tool's rotation about its axis ``redundancy_deg`` (default 0: the cell's tool orientation)."""

REDUNDANCY_LIMIT_DEG = 360.0
"""The largest |redundancy_deg| a cut may give (one turn either way)."""

@dataclass
class Manifest:
    """A validated manifest."""

    path: Path
    experiment: dict[str, Any]
    cuts: list[Cut]
    files: list[dict[str, Any]]
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def raw_dir(self) -> Path:
        return self.path.parent

    @property
    def cell_file(self) -> str | None:
        """Path (relative to the raw folder) of the cell file (kind ``cell``), if listed."""
        cells = self.files_of("cell")
        return cells[0]["path"] if cells else None

    def cut(self, cut_id: str) -> Cut:
        for c in self.cuts:
            if c.id == cut_id:
                return c
        raise RawDataError(self.path, f"cut '{cut_id}' is not listed", where="cuts",
                           expected="one of " + ", ".join(c.id for c in self.cuts))

    def files_of(self, kind: str, **meta: Any) -> list[dict[str, Any]]:
        """Files of ``kind`` whose metadata match every ``meta`` item."""
        return [f for f in self.files if f["kind"] == kind
                and all(f.get(k) == v for k, v in meta.items())]

    def entry(self, relpath: str) -> dict[str, Any]:
        for f in self.files:
            if f["path"] == relpath:
                return f
        raise RawDataError(self.path, f"file '{relpath}' is not listed", where="files",
                           expected="every raw file listed with its sha256")

    def verify_file(self, relpath: str) -> Path:
        """Check that listed file ``relpath`` exists and matches its sha256; return its path."""
        entry = self.entry(relpath)
        full = self.raw_dir / relpath
        if not full.exists():
            raise RawDataError(full, "file listed in the manifest does not exist",
                               where=f"{self.path.name}: files[path={relpath}]",
                               expected="the file to be present")
        actual = sha256_file(full)
        if actual != entry["sha256"]:
            raise RawDataError(full, f"sha256 is {actual}, the manifest says {entry['sha256']}",
                               where=f"{self.path.name}: files[path={relpath}].sha256",
                               expected="the file unchanged since the manifest was written "
                                        "(restore it, or update the manifest on purpose)")
        return full

    def ignore_patterns(self) -> list[str]:
        """The manifest's ``ignore:`` patterns (gitignore syntax), ``[]`` when it has none."""
        return list(self.extra.get("ignore") or [])

    def verify_all(self) -> list[str]:
        """Verify every listed file and look for files the manifest does not list.

        A raw folder holds more than data (notes, photos, an instrument's project files).
        Files matching the manifest's ``ignore:`` patterns (gitignore syntax,
        :func:`robomill.io.kinds.ignored`) are skipped. An unlisted file inside a kind's
        folder (``profiles/``, ``forces/``, ``areal/`` …: the folders of
        :data:`robomill.io.kinds.KIND_FOLDERS` and the top folders of the listed files; the
        cell file ``cell.yaml``) stops ingestion, naming every such file: it is data that would
        silently be left out. Unlisted files elsewhere are returned, one line in all, for the
        caller to warn with.

        Returns
        -------
        list[str]
            ``[]``, or one warning line naming the unlisted files outside the kind folders.

        Raises
        ------
        RawDataError
            A listed file is missing or changed (sha256); unlisted files in a kind folder.
        """
        for f in self.files:
            self.verify_file(f["path"])
        listed = {f["path"] for f in self.files}
        folders = set(KIND_FOLDERS.values()) | {
            Path(f["path"]).parts[0] for f in self.files if len(Path(f["path"]).parts) > 1}
        unlisted = [p.relative_to(self.raw_dir).as_posix()
                    for p in data_files(self.raw_dir, self.ignore_patterns())]
        unlisted = [r for r in unlisted if r not in listed and r != self.path.name]
        inside = [r for r in unlisted if r == "cell.yaml"
                  or (len(Path(r).parts) > 1 and Path(r).parts[0] in folders)]
        if inside:
            raise RawDataError(self.raw_dir / inside[0],
                               f"{len(inside)} file(s) in a data folder are present but not "
                               f"listed in the manifest: {_names(inside)}",
                               where=f"{self.path.name}: files",
                               expected="every raw data file listed with kind and sha256 "
                                        "(robomill manifest lists them), removed from the raw "
                                        "folder, or matched by an ignore: pattern")
        outside = [r for r in unlisted if r not in inside]
        if not outside:
            return []
        return [f"{self.raw_dir}: {len(outside)} file(s) not listed in {self.path.name} "
                f"left out of the study: {_names(outside)} (list them under ignore: to "
                "silence this)"]

    def to_dict(self) -> dict[str, Any]:
        return {
            "experiment": dict(self.experiment),
            "cuts": [c.as_dict() for c in self.cuts],
            "files": [dict(f) for f in self.files],
            **self.extra,
        }


def _names(paths: list[str], most: int = 8) -> str:
    """``a, b, c`` (and ``… and N more`` past ``most``)."""
    shown = ", ".join(paths[:most])
    return shown + (f" and {len(paths) - most} more" if len(paths) > most else "")


def _check_ignore(path: Path, patterns: Any) -> None:
    """``ignore:`` is a list of gitignore patterns (strings)."""
    if patterns is None:
        return
    if not isinstance(patterns, list) or not all(isinstance(p, str) for p in patterns):
        raise RawDataError(path, f"ignore is {patterns!r}", where="ignore",
                           expected="a list of patterns as in .gitignore, e.g. "
                                    "['notes/', '*.jpg']")


def _check_needed(path: Path, where: str, obj: Mapping[str, Any],
                  keys: Mapping[str, tuple[type, ...]], needed: Mapping[str, list[str]],
                  kinds: str) -> None:
    """The ``keys`` of ``obj`` (experiment or one cut): a key some chapter needs
    (``needed``: key → chapter labels) is present and not null; every present, non-null key
    has its type. The message names the chapters that need a missing key."""
    for key, types in keys.items():
        value = obj.get(key)
        if value is None:
            if key in needed:
                state = "null" if key in obj else "missing"
                raise RawDataError(path, f"key '{key}' is {state}", where=where,
                                   expected=f"{key} ({' or '.join(t.__name__ for t in types)}):"
                                            f" {chapter_list(needed[key])} of this folder "
                                            f"({kinds}) need(s) it")
            continue
        if isinstance(value, bool) or not isinstance(value, types):
            raise RawDataError(path, f"key '{key}' is {value!r}", where=where,
                               expected=" or ".join(t.__name__ for t in types))


def _kinds_text(kinds: set[str], has_cuts: bool) -> str:
    names = [f"{k} files" for k in sorted(kinds)] + (["cuts"] if has_cuts else [])
    return ", ".join(names) or "no files"


def _check_modal_band(path: Path, band: Any) -> None:
    """The optional ``experiment.modal_band_hz``: the modal band of interest of the design
    (``[f_lo_hz, f_hi_hz]``, 0 <= f_lo_hz < f_hi_hz), or absent/null."""
    if band is None:
        return
    ok = (isinstance(band, list) and len(band) == 2
          and all(isinstance(b, (int, float)) and not isinstance(b, bool) for b in band)
          and 0 <= band[0] < band[1])
    if not ok:
        raise RawDataError(path, f"modal_band_hz is {band!r}", where="experiment.modal_band_hz",
                           expected="[f_lo_hz, f_hi_hz] with 0 <= f_lo_hz < f_hi_hz, or null")


def _parse_cut(path: Path, where: str, c: Mapping[str, Any], seen: Mapping[str, int]) -> Cut:
    """One ``cuts`` entry: required keys, optional grouping/direction/process keys."""
    unknown = sorted(set(c) - set(CUT_KEYS) - set(CUT_OPTIONAL_KEYS))
    if unknown:
        raise RawDataError(path, f"unknown key(s) {', '.join(map(str, unknown))}", where=where,
                           expected="keys " + ", ".join([*CUT_KEYS, *CUT_OPTIONAL_KEYS]))
    for key, types in CUT_OPTIONAL_KEYS.items():
        value = c.get(key)
        if value is not None and (isinstance(value, bool) or not isinstance(value, types)):
            raise RawDataError(path, f"key '{key}' is {value!r}", where=f"{where}.{key}",
                               expected=" or ".join(t.__name__ for t in types))
    cid = c["id"]
    if not FREE_CUT_ID.match(cid):
        raise RawDataError(path, f"cut id {cid!r} is malformed", where=f"{where}.id",
                           expected="letters, digits, '_', '.', '-' only ([A-Za-z0-9_.-]+)")
    m = CUT_ID.match(cid)
    if m and all(k in c for k in ("set", "segment", "direction")) and (
            int(m["set"]), int(m["segment"]), m["direction"]) != (
            c["set"], c["segment"], c["direction"]):
        raise RawDataError(path, f"cut id {cid!r} disagrees with set={c['set']}, "
                           f"segment={c['segment']}, direction={c['direction']}",
                           where=where, expected="id built from set, segment, direction")
    if cid in seen:
        raise RawDataError(path, f"duplicate cut id {cid!r} (also cuts[{seen[cid]}])",
                           where=f"{where}.id", expected="unique cut ids")
    if any(c.get(k) is not None and c[k] <= 0 for k in ("feed_mm_s", "depth_mm")):
        raise RawDataError(path, "feed_mm_s and depth_mm must be positive", where=where,
                           expected="positive numbers")
    direction, deg = c.get("direction"), c.get("direction_deg")
    if direction is None and deg is None:
        raise RawDataError(path, "neither direction nor direction_deg is given", where=where,
                           expected="direction (px, mx, py, my) or direction_deg (feed "
                                    "direction in the base XY plane, 0 = +X)")
    if direction is not None and deg is not None:
        raise RawDataError(path, "both direction and direction_deg are given", where=where,
                           expected="one of direction, direction_deg")
    if direction is not None and direction not in DIRECTION_VECTORS:
        raise RawDataError(path, f"direction {direction!r} is unknown",
                           where=f"{where}.direction",
                           expected="one of " + ", ".join(DIRECTION_VECTORS))
    for key in ("spindle_rpm", "tool_diameter_mm"):
        if c.get(key) is not None and c[key] <= 0:
            raise RawDataError(path, f"{key} is {c[key]!r}", where=f"{where}.{key}",
                               expected="a positive number")
    if c.get("flutes") is not None and c["flutes"] < 1:
        raise RawDataError(path, f"flutes is {c['flutes']!r}", where=f"{where}.flutes",
                           expected="a positive integer")
    ae = c.get("radial_immersion")
    if ae is not None and not 0 < ae <= 1:
        raise RawDataError(path, f"radial_immersion is {ae!r}",
                           where=f"{where}.radial_immersion",
                           expected="a_e / D in (0, 1] (1 = slot)")
    mode = c.get("milling")
    if mode is not None and mode not in MILLING:
        raise RawDataError(path, f"milling {mode!r} is unknown", where=f"{where}.milling",
                           expected="one of " + ", ".join(MILLING))
    if mode == "slot" and ae is not None and ae < 1:
        raise RawDataError(path, f"milling slot with radial_immersion {ae!r}", where=where,
                           expected="radial_immersion 1 for a slot (or milling up/down)")
    start = c.get("start_mm")
    if start is not None and (len(start) != 3 or any(
            isinstance(v, bool) or not isinstance(v, int | float) for v in start)):
        raise RawDataError(path, f"start_mm is {start!r}", where=f"{where}.start_mm",
                           expected="[x, y, z] of the path start in the base frame [mm]")
    theta = c.get("redundancy_deg")
    if theta is not None and not (math.isfinite(theta) and abs(theta) <= REDUNDANCY_LIMIT_DEG):
        raise RawDataError(path, f"redundancy_deg is {theta!r}", where=f"{where}.redundancy_deg",
                           expected="the tool's rotation about its axis from the cell's tool "
                                    f"orientation, within ±{REDUNDANCY_LIMIT_DEG:g} deg")
    return Cut(cid, c.get("set"), c.get("segment"), direction,
               None if c.get("feed_mm_s") is None else float(c["feed_mm_s"]),
               None if c.get("depth_mm") is None else float(c["depth_mm"]),
               spindle_rpm=None if c.get("spindle_rpm") is None else float(c["spindle_rpm"]),
               flutes=c.get("flutes"),
               tool_diameter_mm=(None if c.get("tool_diameter_mm") is None
                                 else float(c["tool_diameter_mm"])),
               radial_immersion=None if ae is None else float(ae), milling=mode,
               direction_deg=None if deg is None else float(deg),
               start_mm=None if start is None else tuple(float(v) for v in start),
               redundancy_deg=None if theta is None else float(theta))


def parse_cut(path: str | Path, where: str, entry: Mapping[str, Any],
              seen: Mapping[str, int]) -> Cut:
    """One cut mapping with the manifest's rules (keys, types, direction, process keys),
    ``where`` naming it in a problem's one line; ``seen`` the ids taken before it.

    Raises
    ------
    RawDataError
        The entry breaks a rule (file, cut, key and what was expected)."""
    return _parse_cut(Path(path), where, entry, seen)


def _in_own_folder(raw_dir: Path, f: Mapping[str, Any]) -> bool:
    """Whether a file of a study merged from several raw folders (its entry carries the
    ``folder`` it was listed in; :mod:`robomill.io.rawdirs`) lies inside that folder."""
    folder = f.get("folder")
    if not isinstance(folder, str):
        return False
    full, own = os.path.realpath(raw_dir / f["path"]), os.path.realpath(folder)
    return os.path.commonpath([full, own]) == own


def parse_manifest(data: Any, path: str | Path, *, require_sha256: bool = True,
                   kinds: Iterable[str] | None = None) -> Manifest:
    """Validate a manifest mapping (as loaded from YAML) and return a :class:`Manifest`.

    ``require_sha256=False`` validates a *plan*: the synthetic study's manifest before its
    files exist (:func:`robomill.io.synthetic_layout.synthetic_manifest`), through the same checks.
    The experiment and cut keys required are those of the chapters the folder's file kinds
    feed (:mod:`robomill.io.needs`); ``kinds`` gives the folder's kinds when ``data`` is a
    part of its manifest (``robomill check`` validates entry by entry)."""
    path = Path(path)
    if not isinstance(data, Mapping):
        raise RawDataError(path, "not a YAML mapping",
                           expected="top-level keys experiment, cuts, files")
    for key in ("experiment", "cuts", "files"):
        if key not in data:
            raise RawDataError(path, f"top-level key '{key}' is missing",
                               expected="top-level keys experiment, cuts, files")
    exp = data["experiment"]
    if not isinstance(exp, Mapping):
        raise RawDataError(path, f"{type(exp).__name__} found", where="experiment",
                           expected="a mapping with keys " + ", ".join(EXPERIMENT_KEYS))
    if not isinstance(data["cuts"], list):
        raise RawDataError(path, "cuts is not a list", where="cuts", expected="a list of cuts")
    # the keys the chapters this folder feeds read (robomill.io.needs.CHAPTER_NEEDS)
    if kinds is None:
        kinds = file_kinds(data["files"]) if isinstance(data["files"], list) else set()
    kinds = set(kinds)
    has_cuts = bool(data["cuts"])
    what = _kinds_text(kinds, has_cuts)
    _check_needed(path, "experiment", exp, EXPERIMENT_KEYS,
                  required_experiment_keys(kinds, has_cuts), what)
    _check_modal_band(path, exp.get("modal_band_hz"))
    cut_needed = required_cut_keys(kinds)
    cuts: list[Cut] = []
    seen: dict[str, int] = {}
    for i, c in enumerate(data["cuts"]):
        where = f"cuts[{i}]"
        check_keys(path, where, c, {"id": CUT_KEYS["id"]})
        _check_needed(path, where, c, {k: t for k, t in CUT_KEYS.items() if k != "id"},
                      cut_needed, what)
        cuts.append(_parse_cut(path, where, c, seen))
        seen[c["id"]] = i
    if not isinstance(data["files"], list):
        raise RawDataError(path, "files is not a list", where="files",
                           expected="a list of files")
    files = []
    paths: dict[str, int] = {}
    for i, f in enumerate(data["files"]):
        where = f"files[{i}]"
        check_keys(path, where, f, {"path": (str,), "kind": (str,),
                                     **({"sha256": (str,)} if require_sha256 else {})})
        check_file_entry(path, where, f, files)
        if f["path"] in paths:
            first = paths[f["path"]]
            raise RawDataError(path, f"duplicate path {f['path']!r} (also files[{first}])",
                               where=f"{where}.path", expected="each file listed once")
        if ((Path(f["path"]).is_absolute() or ".." in Path(f["path"]).parts)
                and not _in_own_folder(path.parent, f)):
            raise RawDataError(path, f"path {f['path']!r} leaves the raw folder",
                               where=f"{where}.path", expected="a path relative to the manifest")
        if "cut" in f and f["cut"] not in seen:
            raise RawDataError(path, f"file refers to unknown cut {f['cut']!r}",
                               where=f"{where}.cut", expected="a cut listed under cuts")
        if f["kind"] == "cell" and any(g["kind"] == "cell" for g in files):
            first = next(j for j, g in enumerate(files) if g["kind"] == "cell")
            raise RawDataError(path, f"second cell file {f['path']!r} (also files[{first}])",
                               where=f"{where}.kind",
                               expected="at most one file of kind cell (cell.yaml)")
        paths[f["path"]] = i
        files.append(dict(f))
    _check_ignore(path, data.get("ignore"))
    extra = {k: v for k, v in data.items() if k not in ("experiment", "cuts", "files")}
    # a key written null (robomill manifest writes what it could not infer) is absent
    return Manifest(path, {k: v for k, v in exp.items() if v is not None}, cuts, files, extra)


def load_manifest(path: str | Path) -> Manifest:
    """Read and validate ``manifest.yaml`` (safe YAML loader; libyaml's when PyYAML has it:
    every analysis job reads the manifest, and the pure-Python parser took 0.2–0.4 s of
    each on the thesis-scale manifest)."""
    path = Path(path)
    if not path.exists():
        raise RawDataError(path, "manifest does not exist",
                           expected="manifest.yaml in the raw data folder (docs/data-contract.md)")
    try:
        data = yaml.load(path.read_text(), Loader=SAFE_LOADER)
    except yaml.YAMLError as exc:
        raise RawDataError(path, f"not valid YAML: {exc}") from None
    return parse_manifest(data, path)


def build_manifest(experiment: Mapping[str, Any], cuts: Iterable[Cut],
                   files: Iterable[Mapping[str, Any]], raw_dir: str | Path) -> dict[str, Any]:
    """A manifest mapping for ``files`` under ``raw_dir``, with each file's sha256 computed."""
    raw_dir = Path(raw_dir)
    entries = []
    for f in files:
        entry = dict(f)
        entry["sha256"] = sha256_file(raw_dir / entry["path"])
        entries.append(entry)
    return {
        "experiment": dict(experiment),
        "cuts": [c.as_dict() for c in cuts],
        "files": entries,
    }


def write_manifest(manifest: Mapping[str, Any], path: str | Path) -> Path:
    """Write a manifest mapping as YAML (atomically)."""
    from robomill.io.atomic import atomic_path

    with atomic_path(path) as tmp:
        tmp.write_text(yaml.safe_dump(dict(manifest), sort_keys=False, width=100))
    return Path(path)
