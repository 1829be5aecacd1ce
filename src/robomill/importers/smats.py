"""NIST SMATS profile files → ``profiles/<cut>.csv``.

NIST's Surface Metrology Algorithm Testing System (SMATS, the internet-based reference
software of the NIST Precision Engineering Division) reads two profile formats, both
documented on its "Data Format" page:

* **ASCII**: whitespace- or line-separated numbers; the *first* value is the sampling
  spacing in x and the remaining values are the heights z, all in micrometres.
* **SDF** (Surface Data File, ISO 25178-71 / EUNA 15178, ASCII variants ``aISO-1.0``,
  ``aISO-2.0``, ``aBCR-1.0``, ``aNIST-1.0``, and the ``aBC-1.0``/``aNPL-V1.0`` spellings of
  the NIST and NPL pages): a header of ``Key = value`` lines (``NumPoints``,
  ``NumProfiles``, ``Xscale``, ``Yscale``, ``Zscale`` in metres per unit, ``Zresolution``,
  ``Compression``, ``DataType``, ``CheckType``) closed by a line ``*``, then the heights
  (z = value·Zscale) in file order, any number per line, closed by ``*`` (an optional
  trailer follows). A non-measured point is the word ``BAD`` (ISO 25178-71; real exports of
  Digital Surf MountainsMap write it, ``tests/data/real/smats/``): invalid points at the ends
  of the chosen profile are dropped, inside it they are refused unless ``--dropouts
  longest`` keeps the longest valid run (as the X3P importer does).

* **SMATS XML** (the layout of the profiles NIST distributes with its surface metrology
  services): a root ``<DATA>`` holding ``<PART>`` (the part's name), ``<PROCESS>``,
  ``<MEASUREMENT>`` and one ``<DATAFILE>`` per profile with ``<FILENAME>``, ``<UNITS>`` (the
  unit of the spacing and of the heights: ``um``, ``nm``, ``mm``, ``m``, ``in``, ``uin``),
  ``<NUMPOINTS>``, ``<SPACING>`` (in that unit), ``<KCAL>``, ``<DATA_TYPE>`` (``2D``: a
  profile; ``3D`` surfaces are refused) and ``<DATA_POINT_VALUES>`` (one height per line).
  The point count must equal ``NUMPOINTS``; the part name (and the process, measurement and
  file names when given) are kept in the manifest entry (``part``, ``process``,
  ``measurement``, ``source_filename``). Tags are read in any letter case, and values as
  NIST writes them: a number may carry its unit (``<SPACING>0.25 um</SPACING>``: that unit,
  not ``UNITS``, applies), and ``KCAL`` may be a number followed by a unit ratio
  (``1.0000 um/um``, ``0.1 nm/count``). ``KCAL`` (:func:`kcal_factor`): a ratio of two
  lengths is a dimensionless factor, accepted as it is when it equals 1 and otherwise, as
  for a bare number other than 1, applied only when ``--kcal apply`` (heights × KCAL) or
  ignored with ``--kcal ignore``; a length per count (``count``, ``counts``, ``cnt``,
  ``lsb``, ``bit``, ``digit``) states that the values are instrument counts, and is applied.
* The file's own reference parameters, where present: ``<ROUGHNESS_SURFACE_PARAMETERS>``,
  ``<WAVINESS_SURFACE_PARAMETERS>`` (and ``<PRIMARY_SURFACE_PARAMETERS>``), in the data file
  or anywhere in the document, each holding parameters (``<PA>``, ``<PQ>``, ``<PZ>``,
  ``<PSK>``, ``<PKU>``…, or R/W spellings), a number with an optional unit, and the filter
  settings (``<CUTOFF>``/``<LAMBDA_C>`` with a unit, ``<FILTER>``…: every other child is
  kept as text). They go into the manifest entry as ``reference``
  (:func:`reference_parameters`), so that chapter 2 states ours beside them
  (:func:`robomill.surface.reference.reference_comparison`).

For an SDF with several profiles ``--profile`` picks one (default 0, the first in the file);
for an SMATS XML file with several ``<DATAFILE>`` the same option picks the data file.
x is written from 0 in mm, z in µm. Read with the standard library (``xml.etree``; the file
is parsed without entity expansion by ``defusedxml`` where installed).

Not supported, and refused with a message that says so: binary SDF (``bISO-…``,
``bBCR-…``: export ASCII), and an XML file of another layout (an X3P ``main.xml`` handed
over alone is told to be passed as its ``.x3p`` archive).
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path
from typing import Any

import numpy as np

from robomill.errors import RawDataError
from robomill.importers._common import cut_id, read_text, valid_run, write_csv
from robomill.importers.smats_xml import (  # noqa: F401  (the SMATS XML reader, public here)
    kcal_factor,
    number_unit,
    read_smats_xml,
    reference_parameters,
)

FORMAT = "smats"
KIND = "profile"
DESCRIPTION = ("NIST SMATS profile (ASCII: spacing then heights in µm; ASCII SDF, aISO/aBCR; "
               "or SMATS XML, <DATA>/<DATAFILE>)")

WHAT = ("a NIST SMATS profile: ASCII (first value the x spacing, then heights, all in µm), "
        "ASCII SDF (aISO-1.0/aBCR-1.0 header, '*', heights, '*') or SMATS XML (<DATA> with "
        "<DATAFILE>)")
SUPPORTED = ("SMATS ASCII (the x spacing, then the heights, in µm), ASCII SDF (aISO-1.0, "
             "aISO-2.0, aBCR-1.0, aNIST-1.0; BAD points), SMATS XML (<DATA> with <DATAFILE>, "
             "DATA_TYPE 2D), or an X3P file (robomill import x3p); binary SDF is not read")
_SDF_MAGIC = re.compile(r"^([ab])([A-Za-z]+)-V?\d")
_SDF_KEYS = ("NumPoints", "NumProfiles", "Xscale", "Zscale")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """``--profile``, ``--dropouts``, ``--no-crop``, ``--kcal``."""
    parser.add_argument("--profile", type=int, default=0,
                        help="SDF with several profiles: which one (default 0, the first in "
                             "the file)")
    parser.add_argument("--dropouts", choices=("refuse", "longest"), default="refuse",
                        help="SDF 'BAD' points inside the profile: refuse (default) or keep "
                             "the longest run of valid points")
    parser.add_argument("--no-crop", dest="crop", action="store_false",
                        help="refuse 'BAD' points at the ends instead of dropping them")
    parser.add_argument("--kcal", choices=("refuse", "apply", "ignore"), default="refuse",
                        help="SMATS XML with a KCAL other than 1: refuse (default), apply "
                             "(heights × KCAL) or ignore (the heights are calibrated already)")


def _read_sdf(source: Path, lines: list[str], profile: int, *, crop: bool = True,
              dropouts: str = "refuse") -> tuple[np.ndarray, np.ndarray]:
    header: dict[str, str] = {}
    end = None
    for i, line in enumerate(lines[1:], start=1):
        if line.strip() == "*":
            end = i
            break
        key, eq, value = line.partition("=")
        if eq:
            header[key.strip()] = value.strip()
    if end is None:
        raise RawDataError(source, "SDF header is not closed by a '*' line", where="header",
                           expected=WHAT)
    for key in _SDF_KEYS:
        if key not in header:
            raise RawDataError(source, f"SDF header key {key} is missing", where="header",
                               expected="keys " + ", ".join(_SDF_KEYS))
    try:
        npts = int(header["NumPoints"])
        nprof = int(header["NumProfiles"])
        xscale = float(header["Xscale"])
        zscale = float(header["Zscale"])
    except ValueError as exc:
        raise RawDataError(source, f"SDF header value is not a number ({exc})", where="header",
                           expected="NumPoints, NumProfiles integers; Xscale, Zscale numbers"
                           ) from None
    if npts < 2 or nprof < 1 or not xscale > 0 or not zscale > 0:
        raise RawDataError(source, f"NumPoints {npts}, NumProfiles {nprof}, Xscale {xscale:g}, "
                           f"Zscale {zscale:g}", where="header",
                           expected="NumPoints ≥ 2, NumProfiles ≥ 1, positive scales")
    if not 0 <= profile < nprof:
        raise RawDataError(source, f"--profile {profile} outside the file",
                           where="option --profile", expected=f"0 … {nprof - 1}")
    body = []
    closed = False
    for i, line in enumerate(lines[end + 1:], start=end + 2):
        if line.strip() == "*":
            closed = True
            break
        for tok in line.split():
            if tok.upper() == "BAD":
                body.append(np.nan)
                continue
            try:
                body.append(float(tok))
            except ValueError:
                raise RawDataError(source, f"value {tok!r} is not a number", where=f"line {i}",
                                   expected="height values (or BAD)") from None
    want = npts * nprof
    if len(body) != want:
        raise RawDataError(source, f"{len(body)} height values, the header announces "
                           f"{npts}×{nprof} = {want}" + ("" if closed else " (truncated?)"),
                           where="data section", expected=f"{want} values closed by '*'")
    z = np.asarray(body).reshape(nprof, npts)[profile] * zscale * 1e6
    keep = valid_run(source, np.isfinite(z), where=f"profile {profile}", bad="'BAD'",
                     option="--profile", crop=crop, dropouts=dropouts,
                     empty_where=f"data section, profile {profile}")
    x = np.arange(npts)[keep] * xscale * 1e3
    return x - x[0], z[keep]


def read_smats(source: Path, *, profile: int = 0, crop: bool = True,
               dropouts: str = "refuse", kcal: str = "refuse") -> tuple[np.ndarray, np.ndarray]:
    """Read one profile: ``(x_mm (n,), z_um (n,))``, x from 0 (see :func:`read_smats_file`)."""
    x, z, _ = read_smats_file(source, profile=profile, crop=crop, dropouts=dropouts, kcal=kcal)
    return x, z


def read_smats_file(source: Path, *, profile: int = 0, crop: bool = True,
                    dropouts: str = "refuse", kcal: str = "refuse"
                    ) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
    """Read one profile: ``(x_mm (n,), z_um (n,), metadata)``, x from 0; ``metadata`` is
    empty except for SMATS XML (:func:`read_smats_xml`).

    Raises
    ------
    RawDataError
        Missing/empty/binary file; an XML file that is not SMATS XML (an X3P ``main.xml``
        is named as such) or a bad SMATS XML (:func:`read_smats_xml`); a binary SDF; text in
        the data; a spacing ≤ 0; fewer than 2 heights; for SDF, a missing header key, an
        unclosed header, a value count different from ``NumPoints × NumProfiles``
        (truncated), ``--profile`` out of range, 'BAD' points inside the profile (unless
        ``dropouts="longest"``) or at its ends with ``crop=False``.
    """
    source = Path(source)
    text = read_text(source, WHAT)
    lines = text.splitlines()
    first = lines[0].strip() if lines else ""
    meta: dict[str, Any] = {}
    if first.startswith("<"):
        if "ISO5436_2" in text[:4096]:
            raise RawDataError(source, "the main.xml of an X3P (ISO 25178-72) file",
                               where="line 1",
                               expected="the .x3p archive itself: robomill import x3p FILE.x3p")
        x, z, meta = read_smats_xml(source, text, profile=profile, kcal=kcal)
    elif magic := _SDF_MAGIC.match(first):
        if magic[1] == "b":
            raise RawDataError(source, f"binary SDF ({first[:9]})", where="line 1",
                               expected="an ASCII SDF (aISO-1.0, aBCR-1.0, …): " + SUPPORTED)
        x, z = _read_sdf(source, lines, profile, crop=crop, dropouts=dropouts)
    else:
        values = []
        for i, line in enumerate(lines, start=1):
            for tok in line.replace(",", " ").split():
                try:
                    values.append(float(tok))
                except ValueError:
                    raise RawDataError(source, f"value {tok!r} is not a number",
                                       where=f"line {i}", expected=WHAT) from None
        if len(values) < 3:
            raise RawDataError(source, f"{len(values)} values", where="file",
                               expected="the spacing and at least 2 heights")
        dx_um = values[0]
        if not dx_um > 0:
            raise RawDataError(source, f"spacing {dx_um:g} µm", where="line 1 (first value)",
                               expected="a positive x spacing in µm")
        z = np.asarray(values[1:])
        x = np.arange(z.size) * dx_um * 1e-3
    if not np.all(np.isfinite(z)):
        raise RawDataError(source, "height is not finite",
                           where=f"height {int(np.argmax(~np.isfinite(z)))}",
                           expected="finite heights")
    return x, z, meta


def convert(sources: list[Path], staging: Path, args: argparse.Namespace) -> list[dict]:
    """Write ``staging/profiles/<cut>.csv`` per source; return the manifest entries (for
    SMATS XML with the part name and the other labels of :func:`read_smats_xml`)."""
    entries = []
    for src in sources:
        src = Path(src)
        x_mm, z_um, meta = read_smats_file(src, profile=getattr(args, "profile", 0),
                                           crop=getattr(args, "crop", True),
                                           dropouts=getattr(args, "dropouts", "refuse"),
                                           kcal=getattr(args, "kcal", "refuse"))
        cut = cut_id(args, src, len(sources))
        rel = f"profiles/{cut}.csv"
        write_csv(staging / rel, ("x_mm", "z_um"), (x_mm, z_um), ("%.9g", "%.6g"))
        entries.append({"path": rel, "kind": KIND, "cut": cut, **meta})
    return entries
