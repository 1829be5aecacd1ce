"""ISO 25178-72 X3P files (profiles, or one line of a surface) → ``profiles/<cut>.csv``; a
whole surface with ``--areal`` → ``areal/<cut>.nc`` (kind ``areal``, :mod:`robomill.io.areal`).

An X3P file (ISO 25178-72, successor of ISO 5436-2 XML; openGPS) is a zip archive holding
``main.xml`` and, for binary data, ``bindata/data.bin`` (plus an optional ``valid.bin``
bit mask). ``main.xml`` has

* ``Record1/FeatureType``: ``PRF`` (profile), ``SUR`` (surface) or ``PCL`` (point cloud);
* ``Record1/Axes/CX|CY|CZ``: ``AxisType`` (``I`` incremental, ``A`` absolute), ``DataType``
  (``I`` int16, ``L`` int32, ``F`` float32, ``D`` float64), ``Increment`` and ``Offset``, in
  metres (SI);
* ``Record3/MatrixDimension/SizeX|SizeY|SizeZ`` and either ``DataLink/PointDataLink`` (the
  binary file, little endian, X fastest) with ``MD5ChecksumPointData``, or ``DataList`` with
  one ``<Datum>`` per point (empty = invalid point).

The importer needs an incremental X axis (a uniform profile); it takes the profile along X,
for a surface the row ``--row`` (default: the middle row), converts x to mm and z to µm
(``z = Offset + Increment·value`` for integer data, the value itself for float data), drops
invalid points at the ends (``--crop``, default on) and refuses invalid points inside.
The standard library reads it all (zipfile, xml.etree, numpy). This reader is kept although
SurfaceTopography and surfalize read X3P: both refuse real exports it reads — an archive with
its files under a folder (``sample-land/main.xml``, as x3ptools writes them) and an empty
``<Offset/>`` of the Z axis (``docs/data-contract.md``, "Areal scans: which reader").

``--areal`` (a ``SUR`` file) keeps the whole grid (invalid points NaN) with the instrument's
statements of ``Record2`` (manufacturer, model, serial, probing system) in the entry and the
file; ``--feed-angle-deg`` gives the cut's feed direction in the scan's frame.
"""

from __future__ import annotations

import argparse
import hashlib
import zipfile
from pathlib import Path
from typing import Any
from xml.etree import ElementTree

import numpy as np

from robomill.errors import RawDataError
from robomill.importers._common import cut_id, valid_run, write_csv

FORMAT = "x3p"
KIND = "profile"
DESCRIPTION = ("ISO 25178-72 X3P profile, one row of a surface, or with --areal the whole "
               "surface (areal/<cut>.nc)")

_DTYPES = {"I": "<i2", "L": "<i4", "F": "<f4", "D": "<f8"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """``--row``, ``--no-crop``, ``--dropouts``, ``--areal``, ``--feed-angle-deg``."""
    parser.add_argument("--row", type=int, default=None,
                        help="for a surface (SUR): the Y index of the line to take "
                             "(default the middle row)")
    parser.add_argument("--no-crop", dest="crop", action="store_false",
                        help="refuse invalid points at the ends instead of dropping them")
    parser.add_argument("--dropouts", choices=("refuse", "longest"), default="refuse",
                        help="invalid points inside the profile: refuse (default) or keep the "
                             "longest run of valid points")
    parser.add_argument("--areal", action="store_true",
                        help="a surface (SUR): import the whole scan as an areal scan "
                             "(areal/<cut>.nc, kind areal) instead of one row as a profile")
    parser.add_argument("--feed-angle-deg", type=float, default=None,
                        help="with --areal: the cut's feed direction in the scan's frame "
                             "(0: along the scan's +x, 90: along +y; default 0)")


def _strip_ns(root: ElementTree.Element) -> None:
    for el in root.iter():
        if isinstance(el.tag, str) and "}" in el.tag:
            el.tag = el.tag.split("}", 1)[1]


def _text(source: Path, root, path: str, *, required: bool = True) -> str | None:
    el = root.find(path)
    if el is None or el.text is None or not el.text.strip():
        if required:
            raise RawDataError(source, f"element {path} is missing", where=f"main.xml: {path}",
                               expected="an ISO 25178-72 main.xml")
        return None
    return el.text.strip()


def _number(source: Path, root, path: str, default: float | None = None) -> float:
    txt = _text(source, root, path, required=default is None)
    if txt is None:
        return float(default)
    try:
        return float(txt)
    except ValueError:
        raise RawDataError(source, f"{txt!r} is not a number", where=f"main.xml: {path}",
                           expected="a number") from None


def _read_x3p(source: Path) -> dict:
    """Everything :func:`read_x3p` and :func:`read_x3p_grid` share: the header checks and the
    point data as grids (first layer) ``grid`` [m] and ``vgrid`` (valid points)."""
    source = Path(source)
    if not source.is_file():
        raise RawDataError(source, "file does not exist", expected="an X3P file")
    if not zipfile.is_zipfile(source):
        raise RawDataError(source, "not a zip archive", where="file",
                           expected="an X3P file (a zip archive with main.xml)")
    try:
        zf = zipfile.ZipFile(source)
    except zipfile.BadZipFile as exc:
        raise RawDataError(source, f"damaged zip archive ({exc})", where="file",
                           expected="a complete X3P file") from None
    with zf:
        names = zf.namelist()
        main = next((n for n in names if n == "main.xml" or n.endswith("/main.xml")), None)
        if main is None:
            raise RawDataError(source, "no main.xml in the archive", where="archive",
                               expected="an X3P file (main.xml + bindata/)")
        prefix = main[: -len("main.xml")]
        try:
            root = ElementTree.fromstring(zf.read(main))
        except (ElementTree.ParseError, zipfile.BadZipFile, OSError) as exc:
            raise RawDataError(source, f"main.xml cannot be parsed ({exc})", where="main.xml",
                               expected="well-formed XML") from None
        _strip_ns(root)
        feature = _text(source, root, "Record1/FeatureType").upper()
        if feature not in ("PRF", "SUR"):
            raise RawDataError(source, f"feature type is {feature}",
                               where="main.xml: Record1/FeatureType",
                               expected="PRF (profile) or SUR (surface); a point cloud has "
                                        "no uniform x axis")
        ax = "Record1/Axes/CX"
        if (_text(source, root, f"{ax}/AxisType") or "").upper() != "I":
            raise RawDataError(source, "the X axis is absolute (points at arbitrary x)",
                               where=f"main.xml: {ax}/AxisType",
                               expected="an incremental (uniform) X axis, AxisType I")
        dx_m = _number(source, root, f"{ax}/Increment")
        if not dx_m > 0:
            raise RawDataError(source, f"X increment is {dx_m}", where=f"main.xml: {ax}/Increment",
                               expected="a positive spacing in metres")
        x0_m = _number(source, root, f"{ax}/Offset", 0.0)
        cz = "Record1/Axes/CZ"
        ztype = (_text(source, root, f"{cz}/DataType") or "").upper()
        if ztype not in _DTYPES:
            raise RawDataError(source, f"data type {ztype!r}", where=f"main.xml: {cz}/DataType",
                               expected="I, L, F or D")
        zinc = _number(source, root, f"{cz}/Increment", 1.0)
        zoff = _number(source, root, f"{cz}/Offset", 0.0)
        md = "Record3/MatrixDimension"
        nx = int(_number(source, root, f"{md}/SizeX"))
        ny = int(_number(source, root, f"{md}/SizeY"))
        nz = int(_number(source, root, f"{md}/SizeZ", 1.0))
        npts = nx * ny * nz
        link = _text(source, root, "Record3/DataLink/PointDataLink", required=False)
        valid = np.ones(npts, dtype=bool)
        if link is not None:
            member = link if link in names else prefix + link
            if member not in names:
                raise RawDataError(source, f"point data {link!r} is not in the archive",
                                   where="main.xml: Record3/DataLink/PointDataLink",
                                   expected="the binary file the link names")
            raw = zf.read(member)
            want_md5 = _text(source, root, "Record3/DataLink/MD5ChecksumPointData",
                             required=False)
            size = np.dtype(_DTYPES[ztype]).itemsize
            if len(raw) != npts * size:
                raise RawDataError(source, f"{link} has {len(raw)} bytes, "
                                   f"{nx}×{ny}×{nz} points of type {ztype} need {npts * size}"
                                   " (truncated?)", where=f"archive member {link}",
                                   expected=f"{npts * size} bytes")
            if want_md5 and hashlib.md5(raw).hexdigest().lower() != want_md5.lower():
                raise RawDataError(source, f"{link} MD5 is {hashlib.md5(raw).hexdigest()}, "
                                   f"main.xml says {want_md5}",
                                   where="main.xml: Record3/DataLink/MD5ChecksumPointData",
                                   expected="an undamaged point data file")
            values = np.frombuffer(raw, dtype=_DTYPES[ztype]).astype(float)
            # ISO 5436-2 puts the link in DataLink; older writers beside it
            vlink = (_text(source, root, "Record3/DataLink/ValidPointsLink", required=False)
                     or _text(source, root, "Record3/ValidPointsLink", required=False))
            vmember = None if vlink is None else (vlink if vlink in names else prefix + vlink)
            if vmember in names:
                vraw = zf.read(vmember)
                want = _text(source, root, "Record3/DataLink/MD5ChecksumValidPoints",
                             required=False)
                if want and hashlib.md5(vraw).hexdigest().lower() != want.lower():
                    raise RawDataError(source, f"{vlink} MD5 is {hashlib.md5(vraw).hexdigest()}"
                                       f", main.xml says {want}",
                                       where="main.xml: Record3/DataLink/MD5ChecksumValidPoints",
                                       expected="an undamaged valid-points file")
                bits = np.unpackbits(np.frombuffer(vraw, dtype=np.uint8), bitorder="little")
                if bits.size >= npts:
                    valid = bits[:npts].astype(bool)
        else:
            datalist = root.find("Record3/DataList")
            if datalist is None:
                raise RawDataError(source, "neither DataLink nor DataList",
                                   where="main.xml: Record3",
                                   expected="Record3/DataLink/PointDataLink or Record3/DataList")
            data = datalist.findall("Datum")
            if len(data) != npts:
                raise RawDataError(source, f"{len(data)} Datum elements, {nx}×{ny}×{nz} "
                                   f"= {npts} expected (truncated?)",
                                   where="main.xml: Record3/DataList",
                                   expected=f"{npts} Datum elements")
            values = np.empty(npts)
            for i, el in enumerate(data):
                txt = (el.text or "").strip()
                if not txt:
                    valid[i] = False
                    values[i] = np.nan
                    continue
                try:
                    values[i] = float(txt.split(";")[-1])
                except ValueError:
                    raise RawDataError(source, f"{txt!r} is not a number",
                                       where=f"main.xml: Record3/DataList/Datum[{i + 1}]",
                                       expected="a number") from None
    if ztype in ("I", "L"):
        z_m = zoff + zinc * values
    else:
        z_m = values + (zoff if zoff else 0.0)
    valid &= np.isfinite(z_m)
    grid = z_m.reshape(nz, ny, nx)[0]
    vgrid = valid.reshape(nz, ny, nx)[0]
    cy = "Record1/Axes/CY"
    dy_m = (_number(source, root, f"{cy}/Increment", dx_m)
            if (_text(source, root, f"{cy}/AxisType", required=False) or "I").upper() == "I"
            else float("nan"))
    meta = {k: v for k, v in (
        ("manufacturer", _text(source, root, "Record2/Instrument/Manufacturer", required=False)),
        ("model", _text(source, root, "Record2/Instrument/Model", required=False)),
        ("serial", _text(source, root, "Record2/Instrument/Serial", required=False)),
        ("probe", _text(source, root, "Record2/ProbingSystem/Identification",
                        required=False)),
        ("probe_type", _text(source, root, "Record2/ProbingSystem/Type", required=False)),
        ("date", _text(source, root, "Record2/Date", required=False)),
        ("creator", _text(source, root, "Record2/Creator", required=False)),
    ) if v}
    return {"feature": feature, "grid": grid, "vgrid": vgrid, "dx_m": dx_m, "dy_m": dy_m,
            "x0_m": x0_m, "nx": nx, "ny": ny, "meta": meta}


def read_x3p(source: Path, *, row: int | None = None, crop: bool = True,
             dropouts: str = "refuse") -> tuple[np.ndarray, np.ndarray, dict]:
    """Read one profile: ``(x_mm (n,), z_um (n,), info)``.

    ``info`` has ``feature`` (PRF/SUR), ``row``, ``size`` (x, y), ``cropped`` (points dropped
    at the start and end) and ``dx_mm``. ``dropouts="longest"`` keeps the longest run of
    valid points of the row instead of refusing interior invalid points.

    Raises
    ------
    RawDataError
        Not a zip / no ``main.xml`` (wrong format), unparsable XML, a missing element, a
        point cloud or absolute X axis (not uniform), an unknown data type, a binary file of
        the wrong size (truncated) or with a wrong MD5, a ``--row`` outside the surface, an
        invalid point inside the profile, fewer than 2 valid points.
    """
    d = _read_x3p(Path(source))
    source = Path(source)
    feature, grid, vgrid = d["feature"], d["grid"], d["vgrid"]
    nx, ny, dx_m, x0_m = d["nx"], d["ny"], d["dx_m"], d["x0_m"]
    if feature == "SUR":
        r = ny // 2 if row is None else row
        if not 0 <= r < ny:
            raise RawDataError(source, f"--row {r} is outside the surface",
                               where="option --row", expected=f"0 … {ny - 1}")
    else:
        r = 0
    z = grid[r]
    keep = valid_run(source, vgrid[r], where=f"row {r}", bad="invalid", option="--row",
                     crop=crop, dropouts=dropouts, empty_where=f"main.xml: Record3, row {r}")
    i0, i1 = keep.start, keep.stop
    x_mm = (x0_m + dx_m * np.arange(i0, i1)) * 1e3
    z_um = z[i0:i1] * 1e6
    info = {"feature": feature, "row": r, "size": (nx, ny), "cropped": (i0, nx - i1),
            "dx_mm": dx_m * 1e3}
    return x_mm - x_mm[0], z_um, info


def read_x3p_grid(source: Path) -> tuple[np.ndarray, float, float, dict[str, Any]]:
    """Read a surface (``FeatureType SUR``): ``(z_um (ny, nx), dx_mm, dy_mm, meta)``, NaN at
    invalid points (``valid.bin``, empty ``Datum``, non-finite values).

    ``meta``: ``feature`` and what ``Record2`` states (``manufacturer``, ``model``,
    ``serial``, ``probe`` (the probing system's identification: the objective), ``probe_type``,
    ``date``, ``creator``), for the manifest entry.

    Raises
    ------
    RawDataError
        As :func:`read_x3p`; a profile (``PRF``) or a Y axis that is not incremental.
    """
    source = Path(source)
    d = _read_x3p(source)
    if d["feature"] != "SUR":
        raise RawDataError(source, f"feature type is {d['feature']} (a profile)",
                           where="main.xml: Record1/FeatureType",
                           expected="SUR (a surface) for an areal scan; import a profile "
                                    "without --areal")
    if not d["dy_m"] > 0:
        raise RawDataError(source, "the Y axis is not incremental with a positive spacing",
                           where="main.xml: Record1/Axes/CY",
                           expected="AxisType I and a positive Increment")
    z = np.where(d["vgrid"], d["grid"] * 1e6, np.nan)
    return z, d["dx_m"] * 1e3, d["dy_m"] * 1e3, {"feature": "SUR", **d["meta"]}


def areal_entry(cut: str, feed_angle_deg: float | None, dx_mm: float, dy_mm: float,
                meta: dict[str, Any], source: Path, fmt: str) -> dict[str, Any]:
    """The manifest entry of an imported areal scan: ``cut``, ``feed_angle_deg`` and the
    instrument's own statements (``instrument``, ``probe``, ``lateral_spacing_um``…)."""
    instrument = " ".join(v for v in (meta.get("manufacturer"), meta.get("model")) if v)
    entry = {"path": f"areal/{cut}.nc", "kind": "areal", "cut": cut,
             "feed_angle_deg": 0.0 if feed_angle_deg is None else float(feed_angle_deg),
             "instrument": meta.get("instrument") or instrument or None,
             "probe": meta.get("probe"),
             "lateral_spacing_um": [round(dx_mm * 1e3, 9), round(dy_mm * 1e3, 9)],
             "lateral_resolution_um": meta.get("lateral_resolution_um"),
             "source_file": source.name, "source_format": fmt}
    return {k: v for k, v in entry.items() if v not in (None, "")}


def convert(sources: list[Path], staging: Path, args: argparse.Namespace) -> list[dict]:
    """Write ``staging/profiles/<cut>.csv`` per source (or with ``--areal``
    ``staging/areal/<cut>.nc``, :func:`robomill.io.areal.write_areal`); return the manifest
    entries."""
    entries = []
    if getattr(args, "feed_angle_deg", None) is not None and not getattr(args, "areal", False):
        raise RawDataError(Path(sources[0]), "--feed-angle-deg without --areal",
                           where="option --feed-angle-deg",
                           expected="--areal (the angle is the feed direction in a scan)")
    for src in sources:
        src = Path(src)
        cut = cut_id(args, src, len(sources))
        if getattr(args, "areal", False):
            from robomill.io.areal import write_areal

            z_um, dx_mm, dy_mm, meta = read_x3p_grid(src)
            if not np.isfinite(z_um).any():
                raise RawDataError(src, f"the scan has only invalid points ({z_um.shape[1]} "
                                   f"× {z_um.shape[0]})", where="main.xml: Record3",
                                   expected="a scan with measured points")
            entry = areal_entry(cut, getattr(args, "feed_angle_deg", None), dx_mm, dy_mm,
                                meta, src, FORMAT)
            write_areal(staging / entry["path"], z_um, dx_mm, dy_mm,
                        {**meta, "source_file": src.name, "source_format": "x3p"})
            entries.append(entry)
            continue
        x_mm, z_um, _info = read_x3p(src, row=getattr(args, "row", None),
                                     crop=getattr(args, "crop", True),
                                     dropouts=getattr(args, "dropouts", "refuse"))
        rel = f"profiles/{cut}.csv"
        write_csv(staging / rel, ("x_mm", "z_um"), (x_mm, z_um), ("%.9g", "%.6g"))
        entries.append({"path": rel, "kind": KIND, "cut": cut})
    return entries
