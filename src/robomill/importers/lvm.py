"""LabVIEW measurement files (``.lvm``, the text files of LabVIEW's "Write to Measurement
File") of an impact test → ``impact/<stem>_h<k>.csv``.

Read with ``lvm-read`` (:func:`lvm_read.read`): a file header (``LabVIEW Measurement``), then
one or more segments, each with its own header (``Channels``, ``Samples``, ``Y_Unit_Label``,
``Delta_X``) and a column row (``X_Value``, the channel names, ``Comment``); the ``X_Value``
columns (``X_Columns`` ``One`` or ``Multi``) are the time and are not channels. A decimal
comma (``Decimal_Separator ,``) is read as written. The rate is ``1/Delta_X`` of the hammer
channel; every chosen channel must share it. The channels' units are their ``Y_Unit_Label``
unless the command line states one (:func:`robomill.importers._impact.scale_to_si`); the
hits of every segment are found and split (:func:`robomill.importers._impact.find_hits`),
numbered across the file.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from robomill.errors import RawDataError
from robomill.importers._common import nice_rate
from robomill.importers._impact import (
    add_hit_arguments,
    append_hits,
    finish_hits,
    parse_hammer,
    parse_response,
    pick_channel,
    safe_stem,
    scale_to_si,
    write_hits,
)

FORMAT = "lvm"
KIND = "impact"
DESCRIPTION = ("LabVIEW measurement file (.lvm) of an impact test: hammer and accelerometer "
               "channels by name or index, hits found and split → impact/<stem>_h<k>.csv")
WHAT = "a LabVIEW measurement file (.lvm, first line 'LabVIEW Measurement')"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The impact options (:func:`robomill.importers._impact.add_hit_arguments`)."""
    add_hit_arguments(parser)


def read_lvm(source: Path) -> list[dict]:
    """The segments of an LVM file: ``[{"names", "units", "dt", "data"}]`` (channels only,
    the ``X_Value`` columns left out).

    Raises
    ------
    RawDataError
        Not an LVM file, unreadable, or a segment without channels.
    """
    import lvm_read

    source = Path(source)
    if not source.is_file():
        raise RawDataError(source, "file does not exist", expected=WHAT)
    with open(source, "rb") as fh:
        head = fh.read(64)
    if not head.lstrip(b"\xef\xbb\xbf").startswith(b"LabVIEW Measurement"):
        raise RawDataError(source, f"first line is {head.splitlines()[0][:40]!r}"
                           if head.strip() else "file is empty", where="line 1", expected=WHAT)
    try:
        lvm = lvm_read.read(str(source), read_from_pickle=False, dump_file=False)
    except Exception as exc:  # noqa: BLE001 - lvm_read raises what its parsing meets
        raise RawDataError(source, f"cannot be read ({type(exc).__name__}: {exc})",
                           where="file", expected=WHAT + " (truncated copy?)") from None
    segments = []
    for k in range(int(lvm.get("Segments", 0) or 0)):
        seg = lvm[k]
        data = np.asarray(seg.get("data"), float)
        names = list(seg.get("Channel names") or [])
        if data.ndim != 2 or data.shape[0] < 2:
            raise RawDataError(source, f"segment {k + 1} holds {data.shape[0] if data.ndim else 0}"
                               " rows", where=f"segment {k + 1}", expected="samples")
        units = list(seg.get("Y_Unit_Label") or [])
        dts = list(seg.get("Delta_X") or [])
        cols = [i for i in range(data.shape[1])
                if i < len(names) and names[i] != "X_Value"]

        segments.append({"names": [names[i] for i in cols],
                         "units": [str(_field(units, names, i, "") or "") for i in cols],
                         "dt": [float(_field(dts, names, i, np.nan)) for i in cols],
                         "data": data[:, cols]})
    if not segments or not any(s["names"] for s in segments):
        raise RawDataError(source, "no channel columns", where="header", expected=WHAT)
    return segments


def _field(values: list, names: list[str], i: int, empty):
    """Header field of data column ``i``; with ``X_Columns Multi`` a channel's fields sit
    under its own time column (lvm-read aligns them with the ``X_Value`` column)."""
    v = values[i] if i < len(values) else empty
    blank = v in ("", None) or (isinstance(v, float) and np.isnan(v))
    if blank and i > 0 and names[i - 1] == "X_Value" and i - 1 < len(values):
        v = values[i - 1]
    return v


def convert(sources: list[Path], staging: Path, args: argparse.Namespace) -> list[dict]:
    """Write the hit CSVs of every source; return their manifest entries."""
    entries: list[dict] = []
    for src in map(Path, sources):
        segments = read_lvm(src)
        hammer = parse_hammer(getattr(args, "hammer", None), src)
        responses = [parse_response(r, src) for r in getattr(args, "response", []) or []]
        if not responses:
            raise RawDataError(src, "no response channel given", where="option --response",
                               expected="--response CHANNEL:DIRECTION[:unit] (repeatable)")
        stem = safe_stem(src)
        own: list[dict] = []
        for j, seg in enumerate(segments):
            i_f = pick_channel(src, seg["names"], hammer)
            f_scale, f_origin = scale_to_si(src, hammer, seg["units"][i_f], force=True)
            dt = seg["dt"][i_f]
            fs = getattr(args, "fs_hz", None) or (nice_rate(1.0 / dt) if dt > 0 else None)
            if not fs:
                raise RawDataError(src, f"segment {j + 1}: no Delta_X for channel "
                                   f"{seg['names'][i_f]!r}", where="header Delta_X",
                                   expected="a sampling step, or --fs-hz")
            resp, units = [], {seg["names"][i_f]: f_origin}
            for spec in responses:
                i = pick_channel(src, seg["names"], spec)
                scale, origin = scale_to_si(src, spec, seg["units"][i], force=False)
                if np.isfinite(seg["dt"][i]) and abs(seg["dt"][i] - dt) > 1e-9 * dt:
                    raise RawDataError(src, f"channel {seg['names'][i]!r} is sampled every "
                                       f"{seg['dt'][i]:g} s, the hammer every {dt:g} s",
                                       where=f"segment {j + 1}, header Delta_X",
                                       expected="channels sampled together")
                resp.append((spec, seg["data"][:, i] * scale))
                units[seg["names"][i]] = origin
            bad = ~np.isfinite(seg["data"][:, [i_f]])
            if bad.any():
                raise RawDataError(src, "value is not finite",
                                   where=f"segment {j + 1}, row {int(np.argmax(bad))}",
                                   expected="numbers")
            name = stem if len(segments) == 1 else f"{stem}_s{j + 1}"
            got = write_hits(src, staging, name, fs, seg["data"][:, i_f] * f_scale, resp, args,
                             {"source_file": src.name, "source_format": "lvm",
                              "units": units})
            append_hits(own, got)  # hit numbers go on through the file's records
        entries.extend(own)
    return finish_hits(staging, entries)
