"""``robomill import uff``: UFF 58 exports of a modal test system into the impact contract.

A universal file holding hammer + accelerometer time histories (function type 1) or FRFs
(function type 4, with type-6 coherences when present) is itself a contract file of kind
``impact`` (``docs/data-contract.md``): the pipeline reads either. The importer reads every
source completely with the pipeline's own readers (:func:`robomill.io.impact.read_hits_uff`,
:func:`robomill.io.impact.read_frf_uff`), so a file that would fail later fails here, naming
the file, the data set and the field; it then copies the file unchanged to
``staging/impact/`` and returns its manifest entry. Sensor ranges given on the command line
go into the entries (``range_N``, ``range_ms2``).
"""

from __future__ import annotations

import argparse
import re
import shutil
from pathlib import Path

from robomill.errors import RawDataError

FORMAT = "uff"
KIND = "impact"
DESCRIPTION = "UFF 58 time histories (impact hits) or FRFs from a modal test system"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``robomill import uff``: the sensor ranges of the test."""
    parser.add_argument("--range-N", dest="range_N", type=float, default=None,
                        help="hammer force range [N]: a hit reaching it is an overload "
                             "(default: overload from flat-topping alone)")
    parser.add_argument("--range-ms2", dest="range_ms2", type=float, default=None,
                        help="accelerometer range [m/s^2] (default: flat-topping alone)")


def _target_name(src: Path) -> str:
    stem = re.sub(r"[^A-Za-z0-9_.-]+", "_", src.stem).strip("_") or "uff"
    return f"{stem}.uff"


def describe(src: Path) -> dict:
    """Read one source completely; ``{"content": "hits"|"frf"|"hits+frf", "n_hits",
    "n_frf"}``.

    Raises
    ------
    RawDataError
        Whatever the readers refuse, or a file with neither time histories nor FRFs.
    """
    from robomill.io.impact import read_frf_uff, read_hits_uff, uff_function_types

    types = uff_function_types(src)
    if not types & {1, 4}:
        raise RawDataError(src, f"UFF 58 function types {sorted(types)}",
                           where="func_type", expected="time histories (1) or FRFs (4)")
    out = {"n_hits": 0, "n_frf": 0}
    if 1 in types:
        out["n_hits"] = len(read_hits_uff(src))
    if 4 in types:
        ds = read_frf_uff(src)
        out["n_frf"] = int((abs(ds["H"]).notnull().any("frequency")).sum())
    out["content"] = "+".join(k for k, n in (("hits", out["n_hits"]), ("frf", out["n_frf"]))
                              if n)
    return out


def convert(sources: list[Path], staging: Path, args: argparse.Namespace) -> list[dict]:
    """Check every UFF source and copy it to ``staging/impact/``; return manifest entries
    ``{"path": "impact/<name>.uff", "kind": "impact", "uff_content", ["range_N"],
    ["range_ms2"]}``.

    Raises
    ------
    RawDataError
        Naming the source file (and its data set and field) on bad input; two sources with
        the same target name; a range that is not positive.
    """
    entries, seen = [], {}
    for key in ("range_N", "range_ms2"):
        v = getattr(args, key, None)
        if v is not None and not v > 0:
            raise RawDataError(f"--{key.replace('_', '-')}", f"range {v!r}",
                               expected="a positive number")
    for src in map(Path, sources):
        info = describe(src)
        name = _target_name(src)
        if name in seen:
            raise RawDataError(src, f"same target name {name!r} as {seen[name]}",
                               expected="sources with distinct file names")
        seen[name] = src
        dst = Path(staging) / "impact" / name
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(src, dst)
        entry = {"path": f"impact/{name}", "kind": KIND, "uff_content": info["content"]}
        for key in ("range_N", "range_ms2"):
            if getattr(args, key, None) is not None:
                entry[key] = float(getattr(args, key))
        entries.append(entry)
    return entries
