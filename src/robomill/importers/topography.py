"""Areal scans in the instruments' own formats → ``areal/<cut>.nc`` (kind ``areal``), read by
SurfaceTopography (``robomill import sdf`` and ``robomill import areal``).

SurfaceTopography (ContactEngineering, MIT licence, on PyPI with wheels for Python 3.11)
reads the exports of the instruments labs measure milled surfaces with: ISO 25178-71 SDF,
Digital Surf SUR, Sensofar PLU/PLUX, Keyence VK3/VK4/VK6/ZON, Alicona AL3D, Zygo DATX,
Bruker/Wyko OPD/OPDx, NanoSurf EZD, Mitutoyo, NMS and more (``SurfaceTopography.IO
.readers``), each through ``SurfaceTopography.open_topography`` and ``reader.topography()``.
Why this reader and not surfalize or our own: ``docs/data-contract.md``, "Areal scans: which
reader". X3P files go through ``robomill import x3p --areal`` (our reader, which reads real
exports both libraries refuse).

The heights (``Topography.heights()``, x first, masked where not measured) become
``z_um (y, x)`` with NaN; the spacing comes from ``physical_sizes / nb_grid_pts`` in the
file's unit; ``Topography.info`` (``instrument``: name, vendor, serial, parameters such as the
tip radius or the objective; ``acquisition_time``) is carried into the entry and the file.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from robomill.errors import RawDataError
from robomill.importers._common import cut_id

FORMAT = "areal"
KIND = "areal"
DESCRIPTION = ("areal scan in an instrument format SurfaceTopography reads (SDF, SUR, PLU, "
               "PLUX, VK4, ZON, AL3D, DATX, OPD, …) → areal/<cut>.nc")

UNIT_UM = {"m": 1e6, "mm": 1e3, "µm": 1.0, "μm": 1.0, "um": 1.0, "nm": 1e-3, "Å": 1e-4,
           "pm": 1e-6}
"""SurfaceTopography's length units → µm."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """``--feed-angle-deg``, ``--channel``."""
    parser.add_argument("--feed-angle-deg", type=float, default=None,
                        help="the cut's feed direction in the scan's frame (0: along the "
                             "scan's +x, 90: along +y; default 0)")
    parser.add_argument("--channel", type=int, default=0,
                        help="a file with several channels (height, intensity…): which one "
                             "(default 0, the first)")


def read_topography_file(source: Path, channel: int = 0
                         ) -> tuple[np.ndarray, float, float, dict[str, Any]]:
    """``(z_um (ny, nx), dx_mm, dy_mm, meta)`` of an instrument file, NaN where not measured.

    Raises
    ------
    RawDataError
        SurfaceTopography cannot read the file (its reason), ``channel`` out of range, a
        line scan (one row), a non-uniform grid, an unknown unit.
    """
    from SurfaceTopography import open_topography

    source = Path(source)
    if not source.is_file():
        raise RawDataError(source, "file does not exist", expected="an areal scan file")
    try:
        reader = open_topography(str(source))
    except Exception as exc:  # noqa: BLE001 - the library's refusals, one line
        reason = " ".join(str(exc).split())[:300]
        raise RawDataError(source, f"not readable as an areal scan ({type(exc).__name__}: "
                           f"{reason})", where="file", expected=DESCRIPTION) from None
    channels = reader.channels
    if not 0 <= channel < len(channels):
        raise RawDataError(source, f"--channel {channel} outside the file",
                           where="option --channel", expected=f"0 … {len(channels) - 1}")
    try:
        t = reader.topography(channel_index=channel)
    except Exception as exc:  # noqa: BLE001 - the library's refusals, one line
        raise RawDataError(source, f"channel {channel} cannot be read ({type(exc).__name__}: "
                           f"{exc})", where=f"channel {channel}", expected=DESCRIPTION) from None
    if t.dim != 2:
        raise RawDataError(source, "a line scan (one profile)", where=f"channel {channel}",
                           expected="an areal scan; import a profile with robomill import "
                                    "smats")
    if not t.is_uniform:
        raise RawDataError(source, "the grid is not uniform", where=f"channel {channel}",
                           expected="a uniform grid")
    unit = str(t.unit)
    if unit not in UNIT_UM:
        raise RawDataError(source, f"unit {unit!r} is unknown", where=f"channel {channel}",
                           expected="one of " + ", ".join(UNIT_UM))
    scale = UNIT_UM[unit]
    h = t.heights()
    z = np.ma.filled(np.ma.asarray(h, dtype=float), np.nan).T * scale
    (nx, ny), (sx, sy) = t.nb_grid_pts, t.physical_sizes
    info = t.info or {}
    inst = info.get("instrument") or {}
    meta: dict[str, Any] = {"instrument": inst.get("name") or inst.get("vendor"),
                            "serial": inst.get("serial"),
                            "date": str(info["acquisition_time"])
                            if info.get("acquisition_time") else None}
    params = inst.get("parameters") or {}
    for key in ("tip_radius", "resolution", "objective"):
        if key in params:
            val = params[key]
            meta[f"probe_{key}"] = (f"{val.get('value')} {val.get('unit', '')}".strip()
                                    if isinstance(val, dict) else str(val))
    res = params.get("resolution") if isinstance(params.get("resolution"), dict) else None
    if res and res.get("unit") in UNIT_UM:
        meta["lateral_resolution_um"] = float(res["value"]) * UNIT_UM[res["unit"]]
    return z, sx / nx * scale * 1e-3, sy / ny * scale * 1e-3, {
        k: v for k, v in meta.items() if v not in (None, "")}


def convert(sources: list[Path], staging: Path, args: argparse.Namespace) -> list[dict]:
    """Write ``staging/areal/<cut>.nc`` per source; return the manifest entries
    (:func:`robomill.importers.x3p.areal_entry`)."""
    from robomill.importers.x3p import areal_entry
    from robomill.io.areal import write_areal

    entries = []
    for src in sources:
        src = Path(src)
        z_um, dx_mm, dy_mm, meta = read_topography_file(src, getattr(args, "channel", 0))
        if not np.isfinite(z_um).any():
            raise RawDataError(src, f"the scan has only invalid points ({z_um.shape[1]} × "
                               f"{z_um.shape[0]})", where="heights",
                               expected="a scan with measured points")
        cut = cut_id(args, src, len(sources))
        fmt = src.suffix.lower().lstrip(".") or FORMAT
        entry = areal_entry(cut, getattr(args, "feed_angle_deg", None), dx_mm, dy_mm, meta,
                            src, fmt)
        write_areal(staging / entry["path"], z_um, dx_mm, dy_mm,
                    {**meta, "source_file": src.name, "source_format": fmt})
        entries.append(entry)
    return entries
