"""NIST SMATS XML profiles: the profile and the file's own reference parameters, for the SMATS
importer (:mod:`robomill.importers.smats`, whose docstring describes the layout: a root
``<DATA>`` with one ``<DATAFILE>`` per profile, ``UNITS``, ``SPACING``, ``KCAL``,
``DATA_POINT_VALUES``, and the ``*_SURFACE_PARAMETERS`` sections).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np

from robomill.errors import RawDataError

XML_UNITS_UM = {"um": 1.0, "µm": 1.0, "μm": 1.0, "micron": 1.0, "microns": 1.0,
                "micrometer": 1.0, "micrometre": 1.0, "micrometers": 1.0,
                "micrometres": 1.0, "nm": 1e-3, "nanometer": 1e-3, "nanometers": 1e-3,
                "nanometre": 1e-3, "nanometres": 1e-3, "mm": 1e3, "millimeter": 1e3,
                "millimeters": 1e3, "millimetre": 1e3, "millimetres": 1e3, "m": 1e6,
                "meter": 1e6, "meters": 1e6, "metre": 1e6, "metres": 1e6, "in": 25.4e3,
                "inch": 25.4e3, "inches": 25.4e3, "uin": 25.4e-3, "µin": 25.4e-3,
                "microinch": 25.4e-3, "microinches": 25.4e-3}
"""SMATS XML ``<UNITS>`` (of the spacing and the heights) → µm per unit."""
COUNT_UNITS = ("count", "counts", "cnt", "cnts", "lsb", "bit", "bits", "digit", "digits")
"""Denominators of a ``KCAL`` that converts instrument counts into a length."""
VOLTAGE_UNITS = ("v", "mv", "uv", "µv", "volt", "volts")
"""Denominators of a ``KCAL`` that is the transducer's sensitivity (``1um/mv``, as the NPL
profiles exported by SMATS write it): the heights are already in ``UNITS``."""
_NUMBER_UNIT = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")
PARAMETER_SECTIONS = {"ROUGHNESS_SURFACE_PARAMETERS": "roughness",
                      "WAVINESS_SURFACE_PARAMETERS": "waviness",
                      "PRIMARY_SURFACE_PARAMETERS": "primary",
                      "SHORT_CUTOFF_PROFILE_SURFACE_PARAMETERS": "primary",
                      "RAW_PROFILE_SURFACE_PARAMETERS": "raw"}
"""The file's reference parameter sections and the profile each describes."""
_PARAMETER = re.compile(r"^[PRW](A|Q|Z|T|P|V|C|SK|KU)$", re.IGNORECASE)
_DIMENSIONLESS = ("SK", "KU")
_CUTOFF_TAGS = ("CUTOFF", "LAMBDA_C", "LAMBDAC", "LC", "CUT_OFF", "LONG_CUTOFF",
                "ROUGHNESS_CUTOFF", "WAVINESS_CUTOFF")
_XML_WHAT = ("a SMATS XML profile: <DATA> with <DATAFILE> holding FILENAME, UNITS, NUMPOINTS, "
             "SPACING, KCAL, DATA_TYPE 2D, DATA_POINT_VALUES")
_XML_META = (("PART", "part"), ("PROCESS", "process"), ("MEASUREMENT", "measurement"))


def _xml_root(source: Path, text: str):
    try:
        from defusedxml.ElementTree import fromstring
    except ImportError:  # defusedxml is in environment.lock; the stdlib parser otherwise
        from xml.etree.ElementTree import fromstring
    from xml.etree.ElementTree import ParseError

    try:
        root = fromstring(text.encode("utf-8"))
    except ParseError as exc:
        raise RawDataError(source, f"XML cannot be parsed ({exc})", where="file",
                           expected=_XML_WHAT) from None
    except Exception as exc:  # noqa: BLE001 - defusedxml's refusals (entities, DTDs)
        raise RawDataError(source, f"XML refused ({type(exc).__name__}: {exc})",
                           where="file", expected=_XML_WHAT) from None
    for el in root.iter():
        if isinstance(el.tag, str):
            el.tag = el.tag.split("}", 1)[-1].upper()  # namespaces off; tags in any case
    return root


def _xml_label(el) -> str | None:
    """The text of ``<PART>`` (or of its first child with text: ``<PART><NAME>…``)."""
    if el is None:
        return None
    if el.text and el.text.strip():
        return " ".join(el.text.split())
    for child in el.iter():
        if child is not el and child.text and child.text.strip():
            return " ".join(child.text.split())
    return None


def _xml_field(source: Path, datafile, where: str, tag: str) -> str:
    el = datafile.find(tag)
    if el is None or el.text is None or not el.text.strip():
        raise RawDataError(source, f"element {tag} is missing", where=f"{where}/{tag}",
                           expected=_XML_WHAT)
    return el.text.strip()


def number_unit(text: str) -> tuple[float, str] | None:
    """``"0.25 um"`` → ``(0.25, "um")``, ``"4000"`` → ``(4000.0, "")``; ``None`` when the
    text does not start with a number."""
    m = _NUMBER_UNIT.match(text or "")
    return None if m is None else (float(m[1]), m[2])


def _unit_um(unit: str) -> float | None:
    return XML_UNITS_UM.get(unit.strip().lower())


def _attr_unit(el) -> str:
    """The unit an element states as an attribute (``unit``/``units``, any case), or ``""``."""
    if el is None:
        return ""
    for key, value in el.attrib.items():
        if key.lower() in ("unit", "units") and value.strip():
            return value.strip()
    return ""


def _xml_number(source: Path, datafile, where: str, tag: str) -> float:
    text = _xml_field(source, datafile, where, tag)
    got = number_unit(text)
    if got is None or got[1]:
        raise RawDataError(source, f"{tag} {text!r} is not a number", where=f"{where}/{tag}",
                           expected="a number") from None
    return got[0]


def _xml_length_um(source: Path, datafile, where: str, tag: str, um_per_unit: float,
                   unit: str) -> float:
    """A length field in µm: a bare number in ``UNITS``, or a number with its own unit."""
    text = _xml_field(source, datafile, where, tag)
    got = number_unit(text)
    if got is not None and not got[1]:  # a unit given as an attribute: <SPACING unit="um">
        got = (got[0], _attr_unit(datafile.find(tag)))
    if got is None or (got[1] and _unit_um(got[1]) is None):
        raise RawDataError(source, f"{tag} {text!r} is not a length", where=f"{where}/{tag}",
                           expected=f"a number (in {unit}) or a number and a unit of "
                                    + ", ".join(dict.fromkeys(XML_UNITS_UM)))
    return got[0] * (_unit_um(got[1]) if got[1] else um_per_unit)


def kcal_factor(source: Path, text: str, where: str) -> tuple[float, bool]:
    """``KCAL`` as NIST writes it → ``(factor, stated)``.

    A bare number ``k`` → ``(k, False)``; a ratio of two lengths ``k A/B`` → ``(k·A/B,
    False)`` (dimensionless: whether the heights are to be scaled by it is not stated);
    a length per count ``k A/count`` → ``(k·A in the heights' unit, True)``: the values are
    counts and the unit says how to convert them. ``False`` means: a factor other than 1
    needs ``--kcal apply`` or ``--kcal ignore``.

    Raises
    ------
    RawDataError
        Not a number, or a unit that is neither a length ratio nor a length per count.
    """
    got = number_unit(text)
    expected = ("a number, a number and a ratio of lengths (1.0 um/um), a length per count "
                "(0.1 nm/count) or a length per volt (1um/mv)")
    if got is None:
        raise RawDataError(source, f"KCAL {text!r} is not a number", where=where,
                           expected=expected)
    k, unit = got
    if not unit:
        return k, False
    num, slash, den = (u.strip().lower() for u in unit.partition("/"))
    if slash and _unit_um(num) is not None and _unit_um(den) is not None:
        return k * _unit_um(num) / _unit_um(den), False
    if slash and _unit_um(num) is not None and den in COUNT_UNITS:
        return k * _unit_um(num), True
    if slash and _unit_um(num) is not None and den in VOLTAGE_UNITS:
        return 1.0, False  # the transducer's sensitivity: the heights are in UNITS already
    raise RawDataError(source, f"KCAL {text!r}: unit {unit!r} is not understood", where=where,
                       expected=expected)


def _analysis_settings(root) -> dict[str, Any]:
    """What the NPL/SMATS ``<ANALYSIS>`` block states about the parameters it lists: the
    short-wavelength (λs) Gaussian filter of the ``SHORT_CUTOFF_PROFILE``
    (``<FILTER>``: ``FILTER_TYPE``, ``SHORT_CUTOFF`` in ``UNITS``, default mm) →
    ``lambda_s_mm``, and the form removed before them (``<CURVATURE_REMOVAL>``
    ``<LSQ_COEFF>``: the order of the least-squares polynomial removed, 0 = the mean only)
    → ``form_order``."""
    out: dict[str, Any] = {}
    lsq = root.find(".//ANALYSIS/CURVATURE_REMOVAL/LSQ_COEFF")
    if lsq is not None and (got := number_unit(lsq.text or "")) is not None and not got[1]:
        out["form_order"] = int(round(got[0]))
    flt = root.find(".//ANALYSIS/FILTER")
    if flt is not None:
        ftype = " ".join((flt.findtext("FILTER_TYPE") or "").split())
        short = number_unit(flt.findtext("SHORT_CUTOFF") or "")
        unit = (flt.findtext("UNITS") or "mm").strip()
        um = _unit_um(short[1] or unit) if short is not None else None
        if ftype and ftype.upper() != "N/A" and short is not None and um and short[0] > 0:
            out["lambda_s_mm"] = short[0] * um * 1e-3
            out["lambda_s_filter"] = ftype
    return out


def reference_parameters(source: Path, root, datafile, heights_um_per_unit: float
                         ) -> dict[str, dict[str, Any]]:
    """The file's own parameter sections (:data:`PARAMETER_SECTIONS`) → ``{profile:
    {"Pq_um": …, "Psk": …, "filter": {"CUTOFF": "0.8 mm", …}, "lambda_c_mm": 0.8}}``.

    Sections inside the chosen ``<DATAFILE>`` come first; those elsewhere in the document
    are read when the data file has none. Parameter names keep their letter (P, R or W) and
    type (a, q, z, t, p, v, c, sk, ku); amplitudes are converted to µm (their own unit, the
    section's ``<UNITS>``, or the heights' ``UNITS``), sk and ku are dimensionless; an empty
    element (``<PA/>``: not computed by the exporter) is skipped. Other children are the
    section's settings, kept as text under ``filter``; a cut-off among them (``CUTOFF``,
    ``LAMBDA_C``…) with a length unit (mm when none) also gives ``lambda_c_mm``. The NPL
    exports' ``RAW_PROFILE`` (profile ``raw``: the heights as measured) and
    ``SHORT_CUTOFF_PROFILE`` (profile ``primary``: after the λs filter) also carry what the
    ``<ANALYSIS>`` block states (:func:`_analysis_settings`: ``lambda_s_mm`` for the
    primary profile, ``form_order`` for both).

    Raises
    ------
    RawDataError
        A parameter whose value is not a number, or has an unknown unit.
    """
    out: dict[str, dict[str, Any]] = {}
    analysis = _analysis_settings(root)
    for tag, profile in PARAMETER_SECTIONS.items():
        sec = datafile.find(f".//{tag}")
        if sec is None:
            sec = root.find(f".//{tag}")
        if sec is None:
            continue
        where = f"{tag}"
        values: dict[str, Any] = {}
        settings: dict[str, str] = {}
        sec_unit = " ".join((sec.findtext("UNITS") or "").split())
        sec_um = _unit_um(sec_unit) if sec_unit else None
        for child in sec:
            if not isinstance(child.tag, str):
                continue
            text = " ".join((child.text or "").split())
            m = _PARAMETER.match(child.tag)
            if m is None:
                if text:
                    settings[child.tag] = text
                continue
            if not text:
                continue
            got = number_unit(text)
            if got is not None and not got[1]:
                got = (got[0], _attr_unit(child))
            name = child.tag[0] + child.tag[1:].lower()
            if got is None or (got[1] and _unit_um(got[1]) is None):
                raise RawDataError(source, f"{child.tag} {text!r} is not a number with a "
                                   "length unit", where=f"{where}/{child.tag}",
                                   expected="a number, optionally followed by a unit such as "
                                            "um")
            if m[1].upper() in _DIMENSIONLESS:
                values[name] = got[0]
            else:
                scale = (_unit_um(got[1]) if got[1] else sec_um or heights_um_per_unit)
                values[f"{name}_um"] = got[0] * scale
        if not values:
            continue
        if tag in ("SHORT_CUTOFF_PROFILE_SURFACE_PARAMETERS", "RAW_PROFILE_SURFACE_PARAMETERS"):
            if "form_order" in analysis:
                values["form_order"] = analysis["form_order"]
            if profile == "primary" and "lambda_s_mm" in analysis:
                values["lambda_s_mm"] = analysis["lambda_s_mm"]
                settings = {"FILTER_TYPE": analysis["lambda_s_filter"],
                            "SHORT_CUTOFF": f"{analysis['lambda_s_mm']:g} mm", **settings}
        if settings:
            values["filter"] = settings
        for key in _CUTOFF_TAGS:
            if key in settings and (got := number_unit(settings[key])) is not None:
                um = _unit_um(got[1]) if got[1] else 1e3
                if um is not None and got[0] > 0:
                    values["lambda_c_mm"] = got[0] * um * 1e-3
                    break
        if profile in out:  # PRIMARY_SURFACE_PARAMETERS and a SHORT_CUTOFF_PROFILE: the first
            continue
        out[profile] = values
    return out


def read_smats_xml(source: Path, text: str, *, profile: int = 0, kcal: str = "refuse"
                   ) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
    """Read one profile of a SMATS XML file: ``(x_mm (n,), z_um (n,), metadata)``.

    ``metadata`` has ``part`` and, when present, ``process``, ``measurement``,
    ``source_filename`` (the ``<FILENAME>``) and ``reference`` (the file's own parameters,
    :func:`reference_parameters`). x = k·SPACING, z = value (× KCAL with ``kcal="apply"``,
    or × the length per count of a KCAL such as ``0.1 nm/count``), both converted from
    ``<UNITS>`` (or the value's own unit) to mm and µm.

    Raises
    ------
    RawDataError
        Unparsable XML; a root other than ``<DATA>`` or no ``<DATAFILE>``; ``profile`` out
        of range; a missing element; an unknown unit; a DATA_TYPE other than 2D; NUMPOINTS
        not a positive integer or different from the number of values; a spacing ≤ 0; a value
        that is not a number; a KCAL other than 1 with ``kcal="refuse"``, or with a unit that is
        neither a length ratio nor a length per count; a reference parameter that is not a
        number.
    """
    root = _xml_root(source, text)
    if root.tag != "DATA" or root.find("DATAFILE") is None:
        raise RawDataError(source, f"XML root <{root.tag}> "
                           + ("has no <DATAFILE>" if root.tag == "DATA" else "is not <DATA>"),
                           where="line 1", expected=_XML_WHAT + "; or " + _supported())
    files = root.findall("DATAFILE")
    if not 0 <= profile < len(files):
        raise RawDataError(source, f"--profile {profile} outside the file",
                           where="option --profile", expected=f"0 … {len(files) - 1} "
                           f"(the file has {len(files)} DATAFILE elements)")
    df = files[profile]
    where = "DATA/DATAFILE" + (f"[{profile}]" if len(files) > 1 else "")
    unit = _xml_field(source, df, where, "UNITS")
    if unit.lower() not in XML_UNITS_UM:
        raise RawDataError(source, f"unit {unit!r} is unknown", where=f"{where}/UNITS",
                           expected="one of " + ", ".join(dict.fromkeys(XML_UNITS_UM)))
    um = XML_UNITS_UM[unit.lower()]
    dtype = _xml_field(source, df, where, "DATA_TYPE")
    if dtype.upper() != "2D":
        raise RawDataError(source, f"DATA_TYPE is {dtype!r} (not a profile)",
                           where=f"{where}/DATA_TYPE",
                           expected="2D (a profile; export one profile of a 3D surface)")
    npts_text = _xml_field(source, df, where, "NUMPOINTS")
    if not npts_text.isdigit() or int(npts_text) < 2:
        raise RawDataError(source, f"NUMPOINTS {npts_text!r}", where=f"{where}/NUMPOINTS",
                           expected="an integer ≥ 2")
    npts = int(npts_text)
    spacing_um = _xml_length_um(source, df, where, "SPACING", um, unit)
    if not spacing_um > 0:
        raise RawDataError(source, f"SPACING {spacing_um:g} µm", where=f"{where}/SPACING",
                           expected="a positive x spacing")
    k_text = _xml_field(source, df, where, "KCAL")
    k, stated = kcal_factor(source, k_text, f"{where}/KCAL")
    if stated:  # a length per count: the values are counts, KCAL says how long one is
        um, kcal = k, "stated"
    elif abs(k - 1.0) < 1e-12:
        k = 1.0
    elif kcal == "refuse":
        raise RawDataError(source, f"KCAL is {k_text}: whether the heights are to be scaled "
                           "by it is not stated in the file", where=f"{where}/KCAL",
                           expected="KCAL 1, or --kcal apply (heights × KCAL) or --kcal ignore "
                                    "(heights already calibrated)")
    values = _xml_field(source, df, where, "DATA_POINT_VALUES").split()
    z = np.empty(len(values))
    for i, tok in enumerate(values):
        try:
            z[i] = float(tok)
        except ValueError:
            raise RawDataError(source, f"value {tok!r} is not a number",
                               where=f"{where}/DATA_POINT_VALUES, value {i}",
                               expected="one height per line") from None
    if z.size != npts:
        raise RawDataError(source, f"{z.size} values in DATA_POINT_VALUES, NUMPOINTS says "
                           f"{npts}" + (" (truncated?)" if z.size < npts else ""),
                           where=f"{where}/NUMPOINTS",
                           expected=f"{npts} heights, one per line")
    z = z * um * (k if kcal == "apply" else 1.0)
    x = np.arange(npts) * spacing_um * 1e-3
    meta = {key: label for tag, key in _XML_META
            if (label := _xml_label(root.find(tag))) is not None}
    if "part" not in meta:
        raise RawDataError(source, "element PART is missing", where="DATA/PART",
                           expected=_XML_WHAT + " (the part's name)")
    name = df.find("FILENAME")
    if name is not None and name.text and name.text.strip():
        meta["source_filename"] = name.text.strip()
    reference = reference_parameters(source, root, df, um)
    if reference:
        meta["reference"] = reference
    return x, z, meta


def _supported() -> str:
    """The formats the SMATS importer reads (:data:`robomill.importers.smats.SUPPORTED`),
    imported when a file is refused (that module imports this one)."""
    from robomill.importers.smats import SUPPORTED

    return SUPPORTED
