"""Recognise native instrument exports from their first bytes (no heavy imports).

The contract readers (:mod:`robomill.io.tables`, :mod:`robomill.io.forces`, …) call
:func:`hint` on their header/format error path, so that a DynoWare, TDMS, X3P, SMATS/SDF,
SpatialAnalyzer, FARO, UFF, LabVIEW or MATLAB file handed to them directly is named and the
import command given, instead of a bare "column 't_s' is missing". Only the first
:data:`HEAD_BYTES` bytes are read; nothing here imports numpy, pandas or the importers.
"""

from __future__ import annotations

import re
from pathlib import Path

HEAD_BYTES = 8192

NAMES = {
    "dynoware": "a Kistler DynoWare export",
    "tdms": "an NI TDMS file",
    "x3p": "an ISO 25178-72 X3P file",
    "smats": "a NIST SMATS / SDF profile",
    "spatialanalyzer": "a SpatialAnalyzer point export",
    "faro": "a FARO tracker export",
    "uff": "a UFF (universal file format) file",
    "lvm": "a LabVIEW measurement file",
    "mat": "a MATLAB .mat file",
}

EXAMPLE_OPTIONS = {
    "dynoware": "--cut CUT",
    "tdms": "--cut CUT --fx CH --fy CH --fz CH",
    "x3p": "--cut CUT",
    "smats": "--cut CUT",
    "spatialanalyzer": "--direction DIR --feed-mm-s FEED --fs-hz RATE",
    "faro": "--direction DIR --feed-mm-s FEED --fs-hz RATE",
    "uff": "",
    "lvm": "--hammer CH[:unit] --response CH:DIR[:unit] --direction DIR",
    "mat": "--hammer VAR[:unit] --response VAR:DIR[:unit] --direction DIR",
}


def _head(path: Path) -> bytes:
    try:
        with open(path, "rb") as fh:
            return fh.read(HEAD_BYTES)
    except OSError:
        return b""


def sniff(path: str | Path) -> str | None:
    """The importer format a file looks like (``"dynoware"``, ``"tdms"``, …), or None.

    Evidence, in order: the TDMS lead-in tag ``TDSm``; a zip archive holding ``main.xml``
    (X3P); an SDF first line (``aISO-1.0``, ``aBCR-1.0``, … with ``NumPoints``) or an XML file
    naming SMATS or holding a ``<DATAFILE>`` (SMATS XML); the
    words Kistler/DynoWare; SpatialAnalyzer/``::`` point names with ``//`` comments; FARO; a
    UFF data set (``-1`` delimiter line then a set number such as 58); a MATLAB v5/v7.3 header;
    an LVM first line ``LabVIEW Measurement``.
    """
    head = _head(Path(path))
    if not head:
        return None
    if head.startswith(b"TDSm"):
        return "tdms"
    if head.startswith(b"MATLAB 5.0 MAT-file") or head.startswith(b"MATLAB 7.3 MAT-file"):
        return "mat"
    if head.lstrip(b"\xef\xbb\xbf").startswith(b"LabVIEW Measurement"):
        return "lvm"
    if head.startswith(b"PK\x03\x04"):
        return "x3p" if b"main.xml" in head else None
    text = head.decode("utf-8", errors="replace")
    lower = text.lower()
    if re.match(r"^\s*[ab][A-Za-z]+-V?\d", text) and "numpoints" in lower:
        return "smats"
    if text.lstrip().startswith("<") and ("smats" in lower or "<datafile>" in lower):
        return "smats"
    if "dynoware" in lower or "kistler" in lower:
        return "dynoware"
    if "spatialanalyzer" in lower or "spatial analyzer" in lower or (
            text.lstrip().startswith("//") and "::" in text):
        return "spatialanalyzer"
    if re.search(r"\bfaro\b", lower):
        return "faro"
    if re.match(r"^\s*-1\s*\n\s*(15|55|58|82|151|164|2411|2412)\s*(\n|b)", text):
        return "uff"
    return None


def hint(path: str | Path) -> str | None:
    """A sentence naming the format and the import command, or None if not recognised.

    Example: ``looks like a Kistler DynoWare export: run robomill import dynoware FILE --to
    RAW_DIR --cut CUT``.
    """
    fmt = sniff(path)
    if fmt is None:
        return None
    opts = EXAMPLE_OPTIONS[fmt]
    cmd = f"robomill import {fmt} {Path(path).name} --to RAW_DIR" + (f" {opts}" if opts else "")
    return f"looks like {NAMES[fmt]}: run {cmd}"
