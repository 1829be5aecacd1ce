"""The raw folder's layout (``docs/data-contract.md``) and what can be inferred from it.

Used by ``robomill init`` (the skeleton), ``robomill manifest`` (kind and metadata of each
file from its folder, its name and its contents) and ``robomill check``.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from robomill.errors import RawDataError
from robomill.experiment import CUT_ID
from robomill.io.kinds import (  # noqa: F401  (the names the command line's tools import here)
    IGNORED_NAMES,
    KIND_FOLDERS,
    KIND_KEYS,
    data_files,
    ignored,
)

CUT_IN_NAME = re.compile(r"s(?P<set>\d+)_g(?P<segment>\d+)_(?P<direction>px|py|my)(?![a-z])")
TRACKER_NAME = re.compile(r"^(?:(?P<direction>px|mx|py|my)|d(?P<deg>-?\d+(?:\.\d+)?))"
                          r"_f(?P<feed>\d+(?:\.\d+)?)$")
HIT_NAME = re.compile(r"^hit(?P<direction>[XYZ])_(?P<hit>\d+)$")
LOAD_TESTS_NAME = re.compile(r"^load_tests_(?P<robot>.+)$")
NATIVE_SUFFIXES = {".uff": "uff", ".unv": "uff", ".tdms": "tdms", ".x3p": "x3p",
                   ".xml": "smats"}
"""Native exports that must be converted with ``robomill import FORMAT`` first."""


@dataclass
class Inference:
    """What was inferred about one file: its manifest entry and what could not be inferred."""

    path: str
    entry: dict[str, Any] = field(default_factory=dict)
    missing: list[str] = field(default_factory=list)
    note: str | None = None


def cut_from_name(name: str) -> str | None:
    """The cut id ``s{set}_g{segment}_{dir}`` found in a file name, if any."""
    m = CUT_IN_NAME.search(name)
    return m.group(0) if m else None


def rate_from_times(t_s: np.ndarray) -> float | None:
    """Sampling rate [Hz] of a time column: ``(n − 1) / (t[-1] − t[0])``, rounded to 6
    significant digits (the mean step, robust to time stamps printed with few digits)."""
    t = np.asarray(t_s, float)
    if t.size < 2 or not np.all(np.isfinite(t[[0, -1]])) or t[-1] <= t[0]:
        return None
    fs = (t.size - 1) / (t[-1] - t[0])
    return float(f"{fs:.6g}")


def _csv_times(path: Path) -> np.ndarray | None:
    import pandas as pd

    try:
        head = pd.read_csv(path, nrows=0)
        if "t_s" not in head.columns:
            return None
        return pd.read_csv(path, usecols=["t_s"])["t_s"].to_numpy(float)
    except (ValueError, OSError, pd.errors.ParserError):
        return None


def _h5_rate(path: Path) -> float | None:
    import h5py

    try:
        with h5py.File(path, "r") as f:
            if "fs_hz" in f.attrs:
                return float(f.attrs["fs_hz"])
            if "t_s" in f:
                return rate_from_times(np.asarray(f["t_s"][:100_000], float))
    except OSError:
        return None
    return None


def file_rate_hz(path: Path) -> float | None:
    """Sampling rate of a record from its contents: the HDF5 ``fs_hz`` attribute or time
    dataset, or a CSV's ``t_s`` column; ``None`` when it has neither."""
    if path.suffix.lower() in (".h5", ".hdf5"):
        return _h5_rate(path)
    if path.suffix.lower() == ".csv":
        t = _csv_times(path)
        return None if t is None else rate_from_times(t)
    return None


def uff_summary(path: Path) -> str | None:
    """One line describing a UFF file's datasets (type 58 function types and directions),
    from its headers; ``None`` when it cannot be read."""
    try:
        import pyuff

        uff = pyuff.UFF(str(path))
        types = [int(t) for t in uff.get_set_types()]
        if not types:
            return None
        sets = uff.read_sets(list(range(len(types)))) if len(types) > 1 else [uff.read_sets(0)]
    except Exception:  # noqa: BLE001 - any unreadable file is just "not inferred"
        return None
    kinds = {1: "time response", 4: "FRF"}
    parts = []
    for s in sets:
        if s.get("type") == 58:
            ft = kinds.get(int(s.get("func_type", 0)), f"function type {s.get('func_type')}")
            parts.append(f"{ft} rsp dir {s.get('rsp_dir')} ref dir {s.get('ref_dir')}")
    return "; ".join(parts) or None


def infer_file(raw_dir: Path, path: Path) -> Inference:
    """Kind and metadata of ``path`` (inside ``raw_dir``) from its folder, name and contents.

    Rules (``docs/data-contract.md``): the top folder gives the kind; a cut id in the name gives
    ``cut``; ``tracker/<dir>_f<feed>.csv`` gives ``direction`` (``d<deg>``: ``direction_deg``)
    and ``feed_mm_s``;
    ``impact/hit<X|Y|Z>_<k>.csv`` gives ``direction`` and ``hit``; ``ctrack/<table>.csv`` the
    table; ``stiffness/<robot>.yaml`` and ``stiffness/load_tests_<robot>.csv`` the robot; the
    sampling rate ``fs_hz`` of force and tracker records comes from the time column (or the
    HDF5 ``fs_hz`` attribute). A UFF 58 file in ``impact/`` is a contract file (kind impact,
    ``uff_content`` from its data sets, as ``robomill import uff`` writes it); other native
    exports (UFF elsewhere, TDMS, X3P, SMATS XML) are not contract files: they get a note
    naming the import command.
    """
    from robomill.io.ctrack import READERS as CTRACK_TABLES

    rel = path.relative_to(raw_dir).as_posix()
    inf = Inference(rel)
    if rel == "cell.yaml" and "cell" in KIND_KEYS:  # the cell file, where the manifest
        inf.entry = {"path": rel, "kind": "cell"}    # lists it (kind `cell`)
        inf.missing = [k for k in KIND_KEYS["cell"] if k not in inf.entry]
        return inf
    if Path(rel).parts[0] == KIND_FOLDERS["areal"] and path.suffix.lower() != ".nc":
        # an instrument's own areal export put in areal/: the import writes the .nc
        how = ("x3p FILE --areal" if path.suffix.lower() == ".x3p" else
               "sdf FILE" if path.suffix.lower() == ".sdf" else "areal FILE")
        inf.note = (f"native areal scan export: convert it with robomill import "
                    f"{how.replace('FILE', rel)} --cut CUT --feed-angle-deg A --to {raw_dir}")
        return inf
    native = NATIVE_SUFFIXES.get(path.suffix.lower())
    if native == "uff" and Path(rel).parts[0] == KIND_FOLDERS["impact"]:
        # UFF 58 in impact/ is a contract file (what `robomill import uff` writes there)
        from robomill.importers.uff import describe

        try:
            inf.entry = {"path": rel, "kind": "impact",
                         "uff_content": describe(path)["content"]}
            return inf
        except RawDataError:
            pass  # not readable as impact data: the note below names the import command
    if native in ("uff", "tdms") and Path(rel).parts[0] == KIND_FOLDERS["vibration"]:
        native = None  # accelerometer time records are read as they are (robomill.io.recordings)
    if native:
        detail = uff_summary(path) if native == "uff" else None
        inf.note = (f"native {native} export{f' ({detail})' if detail else ''}: convert it with "
                    f"robomill import {native} {rel} --to {raw_dir}")
        return inf
    parts = Path(rel).parts
    folder_kinds = [k for k, d in KIND_FOLDERS.items() if len(parts) > 1 and parts[0] == d]
    stem = path.stem
    kind = None
    if folder_kinds == ["robot", "stiffness"]:
        kind = "stiffness" if LOAD_TESTS_NAME.match(stem) else (
            "robot" if path.suffix.lower() in (".yaml", ".yml") else None)
    elif folder_kinds:
        kind = folder_kinds[0]
    if kind is None:
        inf.missing.append("kind (put the file in one of the folders "
                           + ", ".join(sorted(set(KIND_FOLDERS.values()))) + ")")
        return inf
    entry: dict[str, Any] = {"path": rel, "kind": kind}
    cut = cut_from_name(stem)
    if kind == "tracker":
        m = TRACKER_NAME.match(stem)
        if m and m["direction"]:
            entry["direction"] = m["direction"]
        elif m:
            entry["direction_deg"] = float(m["deg"])
        if m:
            entry["feed_mm_s"] = float(m["feed"])
    elif kind == "impact":
        m = HIT_NAME.match(stem)
        if m:
            entry["direction"] = m["direction"]
            entry["hit"] = int(m["hit"])
    elif kind == "ctrack" and stem in CTRACK_TABLES:
        entry["table"] = stem
    elif kind == "robot":
        entry["robot"] = stem
    elif kind == "stiffness":
        entry["robot"] = LOAD_TESTS_NAME.match(stem)["robot"]
    if cut:
        entry["cut"] = cut
        if kind in ("sound", "vibration") and stem.endswith("_air"):
            entry["pass"] = "air"  # <cut>_air: the cut's air pass (data-contract.md)
    if "fs_hz" in KIND_KEYS.get(kind, {}):
        fs = file_rate_hz(path)
        if fs is not None:
            entry["fs_hz"] = fs
    inf.entry = entry
    inf.missing = [k for k in KIND_KEYS.get(kind, {}) if k not in entry]
    return inf


def cut_stub(cut_id: str) -> dict[str, Any]:
    """A ``cuts`` entry for a cut id seen in file names: for the thesis layout
    ``s{set}_g{segment}_{dir}`` set, segment and direction from the id; for any other id the
    direction left empty; ``feed_mm_s`` and ``depth_mm`` left empty (``null``) for the user
    (or ``robomill import --cut-pattern``) to fill."""
    m = CUT_ID.match(cut_id)
    if m is None:
        return {"id": cut_id, "direction": None, "feed_mm_s": None, "depth_mm": None}
    return {"id": cut_id, "set": int(m["set"]), "segment": int(m["segment"]),
            "direction": m["direction"], "feed_mm_s": None, "depth_mm": None}


def merge_entry(old: Mapping[str, Any], new: Mapping[str, Any]) -> tuple[dict[str, Any],
                                                                            list[str]]:
    """Merge an inferred entry into what the user wrote: the user's values win (a different
    inferred value is reported, not applied); inferred keys the user did not write are added.
    Returns the merged entry and the disagreements."""
    merged = dict(old)
    disagree = []
    for k, v in new.items():
        if k not in merged or merged[k] is None:
            merged[k] = v
        elif merged[k] != v and k not in ("path",):
            disagree.append(f"{k}: manifest says {merged[k]!r}, the file suggests {v!r} "
                            "(kept the manifest's)")
    return merged, disagree
