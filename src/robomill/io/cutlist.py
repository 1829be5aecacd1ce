"""A list of cuts to predict (``robomill predict STUDY CUTS``), read with the manifest's rules.

A cut list is a YAML list of cut mappings (or a mapping with ``cuts:``), or a CSV file whose
columns are the keys (``start_mm`` as ``[x, y, z]`` or ``x y z``; an empty cell: the key not
given). Keys: ``id``, ``spindle_rpm``, ``depth_mm``, ``feed_mm_s``, ``direction`` or
``direction_deg``, ``start_mm`` (or ``set`` and ``segment`` of the study's layout), and the
optional ``flutes``, ``tool_diameter_mm``, ``radial_immersion``, ``milling``,
``redundancy_deg``. A bad entry is one line naming the file, the cut and the key.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import yaml

from robomill.errors import RawDataError

NEEDED = ("id", "feed_mm_s", "depth_mm")


def _cell(value: Any) -> Any:
    """One CSV cell as the manifest's value (numbers, ``[x, y, z]``; empty: None)."""
    if value is None or (isinstance(value, float) and np.isnan(value)):
        return None
    if isinstance(value, str):
        text = value.strip()
        if not text:
            return None
        if " " in text and not text.startswith("["):
            text = "[" + ", ".join(text.split()) + "]"
        try:
            return yaml.safe_load(text)
        except yaml.YAMLError:
            return text
    if isinstance(value, np.generic):
        return value.item()
    return value


def read_cut_entries(path: str | Path) -> list[dict[str, Any]]:
    """The cut mappings of a CSV or YAML cut list.

    Raises
    ------
    RawDataError
        The file is missing, unreadable, or not a list of cut mappings.
    """
    path = Path(path)
    if not path.exists():
        raise RawDataError(path, "does not exist", expected="a CSV or YAML list of cuts")
    if path.suffix.lower() == ".csv":
        try:
            t = pd.read_csv(path, dtype=str, keep_default_na=False)
        except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError):
            raise RawDataError(path, "not a readable CSV table", where="file",
                               expected="a header of cut keys, one cut per row") from None
        return [{k: v for k, v in ((k, _cell(v)) for k, v in row.items()) if v is not None}
                for row in t.to_dict("records")]
    try:
        data = yaml.safe_load(path.read_text())
    except (yaml.YAMLError, UnicodeDecodeError):
        raise RawDataError(path, "not valid YAML", where="file",
                           expected="a list of cuts (or a mapping with cuts:)") from None
    if isinstance(data, dict):
        data = data.get("cuts")
    if not isinstance(data, list) or not all(isinstance(c, dict) for c in data):
        raise RawDataError(path, "not a list of cut mappings", where="cuts",
                           expected="a list of {id, spindle_rpm, depth_mm, feed_mm_s, "
                                    "direction, start_mm, ...}")
    return data


def parse_cuts(path: str | Path, entries: list[dict[str, Any]]) -> list:
    """The entries as :class:`robomill.experiment.Cut` with the manifest's rules
    (:func:`robomill.io.manifest.parse_cut`); each problem names the cut and the key."""
    from robomill.io.manifest import parse_cut

    seen: dict[str, int] = {}
    out = []
    for i, c in enumerate(entries):
        name = f"cut {c['id']}" if isinstance(c.get("id"), str) else f"cuts[{i}]"
        for key in NEEDED:
            if c.get(key) is None:
                raise RawDataError(path, f"key '{key}' missing", where=name,
                                   expected=f"the keys {', '.join(NEEDED)} on every cut")
        if not isinstance(c["id"], str):
            c = {**c, "id": str(c["id"])}
        for key in ("feed_mm_s", "depth_mm", "spindle_rpm", "direction_deg",
                    "tool_diameter_mm", "radial_immersion", "redundancy_deg"):
            v = c.get(key)
            if v is not None and (isinstance(v, bool) or not isinstance(v, int | float)):
                raise RawDataError(path, f"key '{key}' is {v!r}", where=f"{name}.{key}",
                                   expected="a number")
        out.append(parse_cut(path, name, c, seen))
        seen[out[-1].id] = i
    return out


def check_placeable(path: str | Path, cuts: list, experiment: dict) -> None:
    """Every cut has a place: ``start_mm``, or ``set``, ``segment`` and ``direction`` of the
    study's layout (one line naming the cut otherwise)."""
    for c in cuts:
        if c.start_mm is not None:
            continue
        if experiment.get("layout") is None or c.set is None or c.segment is None or \
                c.direction is None:
            raise RawDataError(path, "no place to cut", where=f"cut {c.id}.start_mm",
                               expected="start_mm [x, y, z] in the base frame (or set, "
                                        "segment, direction of the study's layout)")
        if experiment.get("cut_length_mm") is None:
            raise RawDataError(path, "the study gives no cut_length_mm", where=f"cut {c.id}",
                               expected="a study with experiment.cut_length_mm")
