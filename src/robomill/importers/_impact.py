"""Shared by the impact-test importers (``lvm``, ``mat``, ``text``): channels chosen by name
or index, their units, the hits found in a long record and split, and the contract's hit
CSVs (``impact/<stem>_h<k>.csv``) or FRF file (``impact/<stem>.uff``) written.

Channels: ``--hammer CH[:unit]`` and ``--response CH:DIR[:unit]`` (repeatable), ``CH`` a
channel name as the file writes it or its 1-based index; ``DIR`` the response point, an
optional node number and a signed base axis (``X``, ``-Y``, ``2Z``, ``3-X``; node 1 when
none). A unit on the command line is used for that channel; else the file's own (LVM
``Y_Unit_Label``, a ``.mat`` variable's ``units``, a text header ``name [unit]``); neither is
a refusal (:func:`scale_to_si`).

Hits (:func:`find_hits`): the hammer channel, less its median (the amplifier's offset),
rises above ``--trigger-fraction`` of its largest pulse; pulses closer than ``--min-gap-s``
belong to one hit (a double hit, kept in the record for the modal stage to reject). Each hit
becomes one record of equal length starting ``--pretrigger-s`` before its trigger (pre-trigger
kept): the shortest of the gaps to the next hit and the file's end, or ``--record-s``. The
modal stage averages the hits of one reference point as it does every hit
(:func:`robomill.modal.frf.frf_from_groups`).
"""

from __future__ import annotations

import argparse
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from robomill.errors import RawDataError
from robomill.importers._common import write_csv

G_MS2 = 9.80665
FORCE_UNITS = {"n": 1.0, "newton": 1.0, "newtons": 1.0, "kn": 1e3, "lbf": 4.4482216152605,
               "lb": 4.4482216152605}
"""Force units → N."""
ACCEL_UNITS = {"m/s^2": 1.0, "m/s2": 1.0, "m/s²": 1.0, "ms2": 1.0, "m/s/s": 1.0,
               "mm/s^2": 1e-3, "mm/s2": 1e-3, "g": G_MS2, "gn": G_MS2, "g0": G_MS2}
"""Acceleration units → m/s²."""
_POINT = re.compile(r"^(\d+)?([+-]?)([XYZ])$", re.IGNORECASE)
NOISE_FACTOR = 20.0
"""A hit is a hammer pulse at least this many times the channel's noise (1.4826·MAD)."""
MIN_HIT_SAMPLES = 64
"""Fewest samples of a hit record (the hit CSV's own minimum)."""


@dataclass
class ChannelSpec:
    """One channel asked for on the command line."""

    channel: str
    unit: str | None
    option: str
    node: int = 1
    direction: str = ""


def parse_hammer(text: str | None, source: Path) -> ChannelSpec:
    """``CH[:unit]`` of ``--hammer``."""
    if not text:
        raise RawDataError(source, "no hammer channel given", where="option --hammer",
                           expected="--hammer CHANNEL[:unit] (a name or a 1-based index)")
    ch, _, unit = text.partition(":")
    return ChannelSpec(ch.strip(), unit.strip() or None, "--hammer")


def parse_response(text: str, source: Path) -> ChannelSpec:
    """``CH:DIR[:unit]`` of ``--response`` (DIR: ``[node][+|-]X|Y|Z``)."""
    parts = [p.strip() for p in text.split(":")]
    if len(parts) < 2 or not parts[0] or not (m := _POINT.match(parts[1])):
        raise RawDataError(source, f"--response {text!r} is not CHANNEL:DIRECTION[:unit]",
                           where="option --response",
                           expected="e.g. --response 2:X, --response acc_y:-Y:g or "
                                    "--response m_1:2X (node 2, +X)")
    node = int(m[1]) if m[1] else 1
    if node < 1:
        raise RawDataError(source, f"node {node} in --response {text!r}",
                           where="option --response", expected="nodes numbered from 1")
    unit = ":".join(parts[2:]) or None
    return ChannelSpec(parts[0], unit, "--response", node, (m[2] or "") + m[3].upper())


def scale_to_si(source: Path, spec: ChannelSpec, file_unit: str | None, *, force: bool
                ) -> tuple[float, str]:
    """The factor to N (``force``) or m/s² of a channel and where its unit came from.

    The file's unit is used where it states one; a unit on the command line wins over it (a
    mislabelled channel, such as a hammer labelled ``g``, is corrected there, and the entry
    keeps both: ``N (command line; the file says g)``); without either the channel is
    refused.
    """
    table = FORCE_UNITS if force else ACCEL_UNITS
    what = "a force unit (N, kN, lbf)" if force else "an acceleration unit (m/s^2, g, mm/s^2)"
    unit, origin = (spec.unit, "command line") if spec.unit else (file_unit, "file")
    if spec.unit and file_unit and file_unit.strip() and (
            file_unit.strip().lower() != spec.unit.strip().lower()):
        origin = f"command line; the file says {file_unit.strip()}"
    if not unit or not unit.strip():
        raise RawDataError(source, f"channel {spec.channel!r}: no unit stated",
                           where=f"option {spec.option}",
                           expected=f"the unit in the file, or {spec.option} "
                                    f"{spec.channel}{'' if force else ':' + spec.direction}:"
                                    f"UNIT with {what}")
    key = unit.strip().lower().replace(" ", "")
    if key not in table:
        raise RawDataError(source, f"channel {spec.channel!r} is in {unit!r} ({origin})",
                           where=f"option {spec.option}",
                           expected=what + (f", stated on the command line ({spec.option} "
                                            f"{spec.channel}{'' if force else ':' + spec.direction}"
                                            ":UNIT) if the file's label is wrong"
                                            if origin == "file" else ""))
    return table[key], f"{unit.strip()} ({origin})"


def pick_channel(source: Path, names: list[str], spec: ChannelSpec) -> int:
    """The column index of ``spec.channel`` among ``names``: a name (exact, then without
    case) or a 1-based index."""
    if spec.channel in names:
        return names.index(spec.channel)
    low = [n.lower() for n in names]
    if spec.channel.lower() in low and low.count(spec.channel.lower()) == 1:
        return low.index(spec.channel.lower())
    if spec.channel.isdigit() and 1 <= int(spec.channel) <= len(names):
        return int(spec.channel) - 1
    raise RawDataError(source, f"channel {spec.channel!r} is not in the file",
                       where=f"option {spec.option}",
                       expected="one of " + ", ".join(repr(n) for n in names)
                                + f" (or an index 1 … {len(names)})")


def add_hit_arguments(parser: argparse.ArgumentParser) -> None:
    """The impact options shared by ``lvm``, ``mat`` and ``text``."""
    parser.add_argument("--hammer", default=None, metavar="CH[:unit]",
                        help="the hammer channel (name or 1-based index), with its unit when "
                             "the file states none (N, kN, lbf)")
    parser.add_argument("--response", action="append", default=[], metavar="CH:DIR[:unit]",
                        help="an accelerometer channel and the point it measures: "
                             "[node][+|-]X|Y|Z (node 1 when none), unit when the file states "
                             "none (m/s^2, g); repeatable")
    parser.add_argument("--direction", default=None, metavar="DIR",
                        help="the hammer's direction, [+|-]X|Y|Z (base axes)")
    parser.add_argument("--node", type=int, default=1,
                        help="the node hit (default 1, the tool tip)")
    parser.add_argument("--invert-hammer", action="store_true",
                        help="the hammer channel's polarity is reversed (its pulses are "
                             "negative): multiply it by -1")
    parser.add_argument("--trigger-fraction", type=float, default=0.1,
                        help="a hit starts where the hammer force exceeds this fraction of "
                             "its largest pulse (default 0.1)")
    parser.add_argument("--min-gap-s", type=float, default=0.1,
                        help="pulses closer than this belong to one hit (a double hit, left "
                             "for the modal stage to reject; default 0.1 s)")
    parser.add_argument("--pretrigger-s", type=float, default=None,
                        help="samples kept before each trigger (default: 5 %% of the record, "
                             "at most what precedes the first hit)")
    parser.add_argument("--record-s", type=float, default=None,
                        help="length of each hit record (default: the shortest gap to the "
                             "next hit or to the end of the file)")
    parser.add_argument("--fs-hz", type=float, default=None,
                        help="sampling rate, where the file states none")


def hammer_direction(source: Path, text: str | None) -> str:
    """The hammer's direction, ``X``/``-Y``…"""
    m = _POINT.match(text.strip()) if text else None
    if m is None or m[1]:
        raise RawDataError(source, "no hammer direction" if not text
                           else f"--direction {text!r} is not a base axis",
                           where="option --direction",
                           expected="--direction X, Y or Z (or -X, -Y, -Z)")
    return (m[2] or "") + m[3].upper()


def find_hits(source: Path, force_N: np.ndarray, fs_hz: float, *, trigger_fraction: float,
              min_gap_s: float, pretrigger_s: float | None, record_s: float | None
              ) -> tuple[list[int], int, int]:
    """Hits in a hammer record: ``(starts, length, pretrigger)`` in samples.

    Raises
    ------
    RawDataError
        No pulse above the noise (``no hammer hit``), pulses of the wrong sign, or hit
        records shorter than :data:`MIN_HIT_SAMPLES`.
    """
    f = np.asarray(force_N, float)
    peak = float(f.max())
    sigma = 1.4826 * float(np.median(np.abs(f - np.median(f)))) or 1e-12 * max(abs(peak), 1)
    low = float(f.min())
    if -low > NOISE_FACTOR * sigma and -low > 2.0 * max(peak, 0.0):
        raise RawDataError(source, f"the hammer pulses are negative (largest {low:.4g} N at "
                           f"sample {int(np.argmin(f))}, largest positive {peak:.4g} N)",
                           where="option --hammer",
                           expected="a force pushing into the structure positive "
                                    "(--invert-hammer if the channel's polarity is reversed)")
    if not peak > NOISE_FACTOR * sigma:
        raise RawDataError(source, f"no hammer hit: the largest force {peak:.4g} N is "
                           f"{peak / sigma:.3g} times the channel's noise ({sigma:.3g} N)",
                           where="hammer channel",
                           expected=f"at least one pulse {NOISE_FACTOR:g} times the noise "
                                    "(the right channel? --hammer)")
    above = np.flatnonzero(f > trigger_fraction * peak)
    gap = max(int(round(min_gap_s * fs_hz)), 1)
    triggers = [int(above[0])]
    for i in above[1:]:
        if i - triggers[-1] >= gap:
            triggers.append(int(i))
    n_total = f.size
    gaps = [b - a for a, b in zip(triggers, triggers[1:], strict=False)]
    tail = n_total - triggers[-1]
    if record_s is None:
        first = min([*gaps, tail])
        pre = min(int(round((0.05 * first) if pretrigger_s is None else pretrigger_s * fs_hz)),
                  triggers[0])
        length = min([*gaps, tail + pre])  # records touch, none runs past the file's end
    else:
        length = int(round(record_s * fs_hz))
        pre = min(int(round((0.05 * length) if pretrigger_s is None
                            else pretrigger_s * fs_hz)), triggers[0])
    starts = [t - pre for t in triggers]
    ok = [s for s in starts if s + length <= n_total]
    if length < MIN_HIT_SAMPLES or not ok:
        raise RawDataError(source, f"hit records of {length} samples "
                           f"({len(triggers)} hit(s) at samples "
                           f"{', '.join(str(t) for t in triggers[:6])})",
                           where="hammer channel",
                           expected=f"at least {MIN_HIT_SAMPLES} samples per hit (hits "
                                    "further apart, a longer file, or --record-s)")
    return ok, length, pre


def write_hits(source: Path, staging: Path, stem: str, fs_hz: float, force_N: np.ndarray,
               responses: list[tuple[ChannelSpec, np.ndarray]], args: argparse.Namespace,
               extra: dict) -> list[dict]:
    """Split the record into hits and write one hit CSV per hit and response node; return
    the manifest entries."""
    from robomill.modal.layout import parse_direction

    direction = hammer_direction(source, getattr(args, "direction", None))
    f = np.asarray(force_N, float) * (-1.0 if getattr(args, "invert_hammer", False) else 1.0)
    f = f - np.median(f)
    starts, n, pre = find_hits(source, f, fs_hz,
                               trigger_fraction=float(getattr(args, "trigger_fraction", 0.1)),
                               min_gap_s=float(getattr(args, "min_gap_s", 0.1)),
                               pretrigger_s=getattr(args, "pretrigger_s", None),
                               record_s=getattr(args, "record_s", None))
    by_node: dict[int, dict[str, np.ndarray]] = {}
    for spec, values in responses:
        code = parse_direction(spec.direction)
        col = "a" + "xyz"[abs(code) - 1] + "_ms2"
        cols = by_node.setdefault(spec.node, {})
        if col in cols:
            raise RawDataError(source, f"two responses along {col[1].upper()} at node "
                               f"{spec.node}", where="option --response",
                               expected="one channel per node and axis")
        v = np.asarray(values, float)
        cols[col] = (v - np.median(v)) * (1.0 if code > 0 else -1.0)
    entries = []
    t = np.arange(n) / fs_hz
    node = int(getattr(args, "node", 1) or 1)
    for k, s in enumerate(starts, start=1):
        for rnode, cols in sorted(by_node.items()):
            names = [c for c in ("ax_ms2", "ay_ms2", "az_ms2") if c in cols]
            suffix = "" if len(by_node) == 1 else f"_n{rnode}"
            rel = f"impact/{stem}_h{k}{suffix}.csv"
            entry = {"path": rel, "kind": "impact", "direction": direction, "hit": k,
                     "node": node, "response_node": rnode, "fs_hz": fs_hz,
                     "pretrigger_s": round(pre / fs_hz, 9), **extra,
                     "_data": (str(source), ("t_s", "force_N", *names),
                               [t, f[s:s + n], *(cols[c][s:s + n] for c in names)])}
            entries.append(entry)
    return entries


def append_hits(entries: list[dict], got: list[dict]) -> None:
    """Append the hit entries of one more record (an LVM segment, a ``.mat`` page) of the
    same file, their hit numbers continued after those already there."""
    k0 = max((e["hit"] for e in entries), default=0)
    for e in got:
        e["hit"] += k0
    entries.extend(got)


def finish_hits(staging: Path, entries: list[dict]) -> list[dict]:
    """Write the hit records :func:`write_hits` prepared, all cut to the shortest (the
    modal stage averages records of one length; the pre-trigger is kept, the tails are
    cut), and return the entries without their data.

    Raises
    ------
    RawDataError
        Sources at different sampling rates (one impact test has one rate).
    """
    hits = [e for e in entries if "_data" in e]
    if not hits:
        return entries
    rates = {e["fs_hz"] for e in hits}
    if len(rates) > 1:
        other = next(e for e in hits if e["fs_hz"] != hits[0]["fs_hz"])
        raise RawDataError(other["_data"][0], f"sampled at {other['fs_hz']:g} Hz, "
                           f"{hits[0]['_data'][0]} at {hits[0]['fs_hz']:g} Hz",
                           where="sampling rate",
                           expected="one rate for every record of an impact test")
    n = min(len(e["_data"][2][0]) for e in hits)
    numbers: dict[tuple, int] = {}
    count: dict[str, int] = {}
    for e in hits:  # hits numbered 1, 2, … per hammer direction across the import's sources
        key = (e["_data"][0], e["path"].rsplit("_h", 1)[0], e["hit"], e["direction"])
        if key not in numbers:
            count[e["direction"]] = count.get(e["direction"], 0) + 1
            numbers[key] = count[e["direction"]]
        e["hit"] = numbers[key]
    for e in hits:
        _, header, cols = e.pop("_data")
        write_csv(staging / e["path"], header, [c[:n] for c in cols],
                  ("%.12g", "%.7g", *("%.7g",) * (len(header) - 2)))
        e["record_s"] = round(n / e["fs_hz"], 9)
    return entries


def safe_stem(src: Path) -> str:
    """A file stem usable in contract paths."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", Path(src).stem).strip("_") or "impact"
