"""NI TDMS records (LabVIEW, NI DAQ) → ``forces/<cut>.csv`` or ``impact/hit<D>_<k>.csv``.

A TDMS file holds groups of channels; each waveform channel carries its sampling step in the
property ``wf_increment`` (s) and its start in ``wf_start_offset`` (npTDMS,
``TdmsFile.read``). Channels are chosen by name, ``GROUP/CHANNEL`` or just ``CHANNEL`` when the
name is unique in the file; all chosen channels must have the same length and step.

* ``--record force`` (default): ``--fx``, ``--fy``, ``--fz`` name the dynamometer's x, y, z
  channels; ``--n-per-unit`` converts their unit (e.g. volts at the charge amplifier's
  output) to newtons; ``--axes`` maps them to the force on the tool in R0 as for DynoWare
  (default ``-x,-y,-z``: reading with its sign inverted).
* ``--record impact``: ``--force``, ``--ax``, ``--ay``, ``--az`` name the hammer and the three
  accelerometer channels, ``--force-n-per-unit`` and ``--accel-ms2-per-unit`` their
  sensitivities, ``--direction`` (X, Y, Z) and ``--hit`` the manifest keys.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from robomill.errors import RawDataError
from robomill.importers._common import cut_id, map_axes, nice_rate, parse_axes, write_csv

FORMAT = "tdms"
KIND = "force"
DESCRIPTION = "NI TDMS (LabVIEW/DAQmx) force or impact-hammer channels, chosen by name"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Channel names, sensitivities, axis mapping, impact keys."""
    parser.add_argument("--record", choices=("force", "impact"), default="force",
                        help="what the channels are (default force)")
    for ax in ("fx", "fy", "fz"):
        parser.add_argument(f"--{ax}", default=None,
                            help=f"dynamometer {ax[1]} channel, GROUP/CHANNEL or CHANNEL")
    parser.add_argument("--n-per-unit", type=float, default=1.0,
                        help="newtons per unit of the force channels (default 1: already N)")
    parser.add_argument("--axes", default="-x,-y,-z",
                        help="dynamometer axis and sign for each tool-force axis X,Y,Z "
                             "(default -x,-y,-z)")
    parser.add_argument("--force", default=None, help="hammer force channel (impact)")
    for ax in ("ax", "ay", "az"):
        parser.add_argument(f"--{ax}", default=None,
                            help=f"accelerometer channel along base {ax[1].upper()} (impact)")
    parser.add_argument("--force-n-per-unit", type=float, default=1.0,
                        help="newtons per unit of the hammer channel (impact, default 1)")
    parser.add_argument("--accel-ms2-per-unit", type=float, default=1.0,
                        help="m/s² per unit of the accelerometer channels (impact, default 1)")
    parser.add_argument("--direction", choices=("X", "Y", "Z"), default=None,
                        help="hammer direction in base axes (impact)")
    parser.add_argument("--hit", type=int, default=None,
                        help="hit number k (impact; default: 1, 2, … per source)")


def _open(source: Path):
    from nptdms import TdmsFile

    if not source.is_file():
        raise RawDataError(source, "file does not exist", expected="an NI TDMS file")
    with open(source, "rb") as fh:
        magic = fh.read(4)
    if magic != b"TDSm":
        raise RawDataError(source, f"lead-in tag is {magic!r}", where="bytes 0-3",
                           expected="an NI TDMS file (tag b'TDSm'); .tdms_index files are "
                                    "not the data")
    import logging

    class _Collect(logging.Handler):
        def __init__(self):
            super().__init__(logging.WARNING)
            self.messages: list[str] = []

        def emit(self, record):
            self.messages.append(record.getMessage())

    collect = _Collect()
    log = logging.getLogger("nptdms")
    log.addHandler(collect)
    try:
        tdms = TdmsFile.read(source)
    except Exception as exc:  # npTDMS raises ValueError/IndexError/struct.error on damage
        raise RawDataError(source, f"cannot be read ({type(exc).__name__}: {exc})",
                           where="file structure",
                           expected="a complete TDMS file (truncated copy?)") from None
    finally:
        log.removeHandler(collect)
    short = [m for m in collect.messages if "less data than expected" in m
             or "incomplete" in m or "Cropping data" in m]
    if short:
        raise RawDataError(source, f"the last segment is incomplete ({short[0]})",
                           where="last data segment",
                           expected="a complete TDMS file (truncated copy?)")
    return tdms


def list_channels(tdms) -> list[str]:
    """``GROUP/CHANNEL`` names of every channel."""
    return [f"{g.name}/{c.name}" for g in tdms.groups() for c in g.channels()]


def _channel(source: Path, tdms, name: str | None, option: str):
    names = list_channels(tdms)
    if not names:
        raise RawDataError(source, "the file holds no channels", where="file structure",
                           expected="a TDMS file with channels (truncated copy?)")
    if not name:
        raise RawDataError(source, f"no channel given for {option}", where=f"option {option}",
                           expected="one of " + ", ".join(repr(n) for n in names[:20]))
    if "/" in name and name in names:
        g, c = name.split("/", 1)
        return name, tdms[g][c]
    hits = [n for n in names if n.split("/", 1)[1] == name]
    if len(hits) == 1:
        g, c = hits[0].split("/", 1)
        return hits[0], tdms[g][c]
    if len(hits) > 1:
        raise RawDataError(source, f"channel {name!r} is in several groups",
                           where=f"option {option}", expected="GROUP/CHANNEL, one of "
                           + ", ".join(repr(h) for h in hits))
    raise RawDataError(source, f"channel {name!r} is missing", where=f"option {option}",
                       expected="one of " + ", ".join(repr(n) for n in names[:20]))


def read_channels(source: Path, spec: dict[str, str | None]) -> tuple[dict, float, float]:
    """Read the named channels: ``({option: values}, fs_hz, t0_s)``.

    Raises
    ------
    RawDataError
        Not a TDMS file, unreadable/truncated, a missing or ambiguous channel (the message
        lists the channels), no ``wf_increment``, different lengths or steps, too few or
        non-finite samples.
    """
    tdms = _open(Path(source))
    out: dict[str, np.ndarray] = {}
    step = None
    t0 = 0.0
    n = None
    for option, name in spec.items():
        full, ch = _channel(source, tdms, name, option)
        inc = ch.properties.get("wf_increment")
        if inc is None or not float(inc) > 0:
            raise RawDataError(source, f"channel {full!r} has no sampling step",
                               where=f"{full}: property wf_increment",
                               expected="a waveform channel with wf_increment > 0")
        inc = float(inc)
        if step is None:
            step, t0 = inc, float(ch.properties.get("wf_start_offset", 0.0) or 0.0)
        elif abs(inc - step) > 1e-6 * step:
            raise RawDataError(source, f"channel {full!r} is sampled every {inc:g} s, the "
                               f"first every {step:g} s", where=f"{full}: wf_increment",
                               expected="channels sampled together")
        data = np.asarray(ch[:], dtype=float)
        if n is None:
            n = data.size
        elif data.size != n:
            raise RawDataError(source, f"channel {full!r} has {data.size} samples, the first "
                               f"has {n} (truncated acquisition?)", where=f"{full}",
                               expected="channels of equal length")
        bad = ~np.isfinite(data)
        if bad.any():
            raise RawDataError(source, "value is not finite",
                               where=f"{full}, sample {int(np.argmax(bad))}",
                               expected="finite numbers")
        out[option] = data
    if n is None or n < 2:
        raise RawDataError(source, f"only {n or 0} samples", where="channels",
                           expected="at least 2 samples")
    return out, nice_rate(1.0 / step), t0


def convert(sources: list[Path], staging: Path, args: argparse.Namespace) -> list[dict]:
    """Write one contract file per source; return its manifest entries."""
    entries = []
    record = getattr(args, "record", "force")
    for i, src in enumerate(sources):
        src = Path(src)
        if record == "impact":
            direction = getattr(args, "direction", None)
            if direction not in ("X", "Y", "Z"):
                raise RawDataError(src, "no hammer direction", where="option --direction",
                                   expected="--direction X, Y or Z")
            spec = {f"--{k}": getattr(args, k, None) for k in ("force", "ax", "ay", "az")}
            ch, fs, _t0 = read_channels(src, spec)
            hit = (getattr(args, "hit", None) or 1) + i
            n = ch["--force"].size
            rel = f"impact/hit{direction}_{hit}.csv"
            a = float(getattr(args, "accel_ms2_per_unit", 1.0))
            write_csv(staging / rel, ("t_s", "force_N", "ax_ms2", "ay_ms2", "az_ms2"),
                      (np.arange(n) / fs, ch["--force"] * float(args.force_n_per_unit),
                       ch["--ax"] * a, ch["--ay"] * a, ch["--az"] * a),
                      ("%.9f", "%.6g", "%.6g", "%.6g", "%.6g"))
            entries.append({"path": rel, "kind": "impact", "direction": direction,
                            "hit": hit})
            continue
        mapping = parse_axes(getattr(args, "axes", "-x,-y,-z"), src)
        spec = {f"--{k}": getattr(args, k, None) for k in ("fx", "fy", "fz")}
        ch, fs, _t0 = read_channels(src, spec)
        reading = np.column_stack([ch["--fx"], ch["--fy"], ch["--fz"]])
        reading = reading * float(getattr(args, "n_per_unit", 1.0))
        tool = map_axes(reading, mapping)
        cut = cut_id(args, src, len(sources))
        rel = f"forces/{cut}.csv"
        write_csv(staging / rel, ("t_s", "Fx_N", "Fy_N", "Fz_N"),
                  (np.arange(reading.shape[0]) / fs, *tool.T),
                  ("%.9f", "%.6g", "%.6g", "%.6g"))
        entries.append({"path": rel, "kind": KIND, "cut": cut, "fs_hz": fs})
    return entries
