"""ISO 25178-72 X3P files (profiles, or one line of a surface) → ``profiles/<cut>.csv``.

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
The standard library reads it all (zipfile, xml.etree, numpy); no X3P package is needed.
"""

from __future__ import annotations

import argparse
import hashlib
import zipfile
from pathlib import Path
from xml.etree import ElementTree

import numpy as np

from robomill.errors import RawDataError
from robomill.importers._common import cut_id, valid_run, write_csv

FORMAT = "x3p"
KIND = "profile"
DESCRIPTION = "ISO 25178-72 X3P profile (or one row of a surface)"

_DTYPES = {"I": "<i2", "L": "<i4", "F": "<f4", "D": "<f8"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """``--row``, ``--no-crop``."""
    parser.add_argument("--row", type=int, default=None,
                        help="for a surface (SUR): the Y index of the line to take "
                             "(default the middle row)")
    parser.add_argument("--no-crop", dest="crop", action="store_false",
                        help="refuse invalid points at the ends instead of dropping them")
    parser.add_argument("--dropouts", choices=("refuse", "longest"), default="refuse",
                        help="invalid points inside the profile: refuse (default) or keep the "
                             "longest run of valid points")


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
            vlink = _text(source, root, "Record3/ValidPointsLink", required=False)
            vmember = None if vlink is None else (vlink if vlink in names else prefix + vlink)
            if vmember in names:
                bits = np.unpackbits(np.frombuffer(zf.read(vmember), dtype=np.uint8),
                                     bitorder="little")
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


def convert(sources: list[Path], staging: Path, args: argparse.Namespace) -> list[dict]:
    """Write ``staging/profiles/<cut>.csv`` per source; return the manifest entries."""
    entries = []
    for src in sources:
        src = Path(src)
        x_mm, z_um, _info = read_x3p(src, row=getattr(args, "row", None),
                                     crop=getattr(args, "crop", True),
                                     dropouts=getattr(args, "dropouts", "refuse"))
        cut = cut_id(args, src, len(sources))
        rel = f"profiles/{cut}.csv"
        write_csv(staging / rel, ("x_mm", "z_um"), (x_mm, z_um), ("%.9g", "%.6g"))
        entries.append({"path": rel, "kind": KIND, "cut": cut})
    return entries
