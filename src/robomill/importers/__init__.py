"""Importers: native instrument exports converted into the data contract (``robomill import``).

Each format lives in its own module, imported only when it is used (some need optional,
heavy libraries such as npTDMS). A module exposes

- ``FORMAT`` (its name on the command line) and ``DESCRIPTION`` (one line for ``--help``);
- ``add_arguments(parser)``: its own command-line options (``argparse``);
- ``convert(sources, staging, args) -> list[dict]``: writes contract files under
  ``staging/<kind folder>/`` and returns their manifest entries ``{"path": rel, "kind": ...,
  **metadata}`` (no sha256: the caller adds it). Bad input raises
  :class:`robomill.errors.RawDataError` naming the source file and field.

``args`` always carries ``cut`` (``--cut ID`` or ``None``). The command
(:mod:`robomill.cli.importing`) gives each run a fresh staging folder and moves the files into
the raw folder only when every source converted.
"""

from __future__ import annotations

import importlib
from types import ModuleType

FORMATS: dict[str, str] = {
    "dynoware": "robomill.importers.dynoware",
    "tdms": "robomill.importers.tdms",
    "uff": "robomill.importers.uff",
    "spatialanalyzer": "robomill.importers.spatialanalyzer",
    "faro": "robomill.importers.faro",
    "smats": "robomill.importers.smats",
    "x3p": "robomill.importers.x3p",
    "sdf": "robomill.importers.sdf",
    "areal": "robomill.importers.topography",
    "lvm": "robomill.importers.lvm",
    "mat": "robomill.importers.mat",
    "text": "robomill.importers.text",
    "recording": "robomill.importers.recording",
}
"""Registered formats and the module implementing each (imported lazily)."""

INTERFACE = ("FORMAT", "DESCRIPTION", "add_arguments", "convert")
"""What every importer module must define."""


class ImporterError(LookupError):
    """An unknown format, or a registered one whose module is missing or incomplete."""


def load_importer(fmt: str, formats: dict[str, str] | None = None) -> ModuleType:
    """The importer module of format ``fmt``, checked for :data:`INTERFACE`.

    Parameters
    ----------
    fmt
        Format name as typed after ``robomill import``.
    formats
        Registry to use (default :data:`FORMATS`; tests pass their own).

    Raises
    ------
    ImporterError
        ``fmt`` is not registered (the message lists the formats), its module cannot be
        imported, or it lacks part of :data:`INTERFACE`.
    """
    formats = FORMATS if formats is None else formats
    if fmt not in formats:
        raise ImporterError(f"unknown format {fmt!r} (expected one of {', '.join(formats)})")
    name = formats[fmt]
    try:
        module = importlib.import_module(name)
    except ModuleNotFoundError as exc:
        if exc.name and (name == exc.name or name.startswith(exc.name + ".")):
            raise ImporterError(f"format {fmt!r} is registered but its module {name} is not "
                                "part of this robomill installation") from None
        raise ImporterError(f"format {fmt!r} needs the Python package {exc.name!r}, which is "
                            "not installed (pip install it, or make venv)") from None
    missing = [a for a in INTERFACE if not hasattr(module, a)]
    if missing:
        raise ImporterError(f"importer module {name} lacks {', '.join(missing)} "
                            f"(expected {', '.join(INTERFACE)})")
    return module


def describe(formats: dict[str, str] | None = None) -> list[tuple[str, str]]:
    """``(format, description)`` for ``--help``; a format that cannot be loaded is described
    by the reason."""
    out = []
    for fmt in FORMATS if formats is None else formats:
        try:
            out.append((fmt, str(load_importer(fmt, formats).DESCRIPTION)))
        except ImporterError as exc:
            out.append((fmt, f"(unavailable: {exc})"))
    return out
