"""A recording of a cut (sound or vibration) attached to the cut → ``sound/<cut>[_air].<ext>``
or ``vibration/<cut>[_air].csv|.tdms``, kind ``sound``/``vibration`` with its ``cut``
(``docs/data-contract.md``, "Sound and vibration of the cut").

* Sound (WAV, FLAC, MP3, OGG, AIFF): read through libsndfile (:mod:`soundfile`) to check it,
  copied unchanged.
* Vibration CSV (``t_s`` and acceleration columns) and TDMS: checked with the pipeline's own
  reader (:func:`robomill.io.recordings.read_vibration`; TDMS channels by ``--channel``),
  copied unchanged.
* MATLAB ``.mat`` (v5/v7.3) and LabVIEW ``.lvm``: the channels named by ``--channel``
  (repeatable; a ``.mat`` vector, ``NAME[column]``; an LVM channel name or number) and the
  rate (the file's, else ``--fs-hz``) are written as a vibration CSV (``t_s`` then one column
  per channel, in the file's unit; the verdict needs only the lines' frequencies).

``--air`` marks the recording as an **air pass** of the cut (the same path, spindle and feed,
without material), manifest key ``pass: air``: the recording of what the machine makes
without cutting, which tells forced vibration from chatter. A cut may carry one recording of
each. ``--spindle-rpm``/``--flutes`` go into the entry when given (else the cut's design);
``--sidecar FILE`` (YAML/JSON, the ``--design`` keys) writes the cut's conditions as the lab
noted them beside the recording into the manifest's cut.
"""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path

import numpy as np

from robomill.errors import RawDataError
from robomill.importers._common import cut_id, write_csv

FORMAT = "recording"
KIND = "vibration"
DESCRIPTION = ("a recording of a cut (sound: WAV/FLAC/MP3/OGG; vibration: CSV, TDMS, .mat, "
               ".lvm), attached to its cut; --air for its air pass → sound/<cut>[_air].* or "
               "vibration/<cut>[_air].*")
SOUND = (".wav", ".flac", ".mp3", ".ogg", ".aiff", ".aif")
COPIED_VIBRATION = (".csv", ".tdms", ".uff", ".unv")
CONVERTED = (".mat", ".lvm")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """``--air``, the channels of a .mat/.lvm/.tdms file, its rate, the cut's speed."""
    parser.add_argument("--air", action="store_true",
                        help="the recording is an air pass of the cut (same path without "
                             "material): manifest key pass: air")
    parser.add_argument("--channel", action="append", default=[], metavar="CH",
                        help="a channel to keep (.mat: NAME or NAME[column]; .lvm: name or "
                             "number; .tdms: GROUP/CHANNEL); repeatable")
    parser.add_argument("--fs-hz", type=float, default=None,
                        help="sampling rate where the file states none (.mat, CSV)")
    parser.add_argument("--spindle-rpm", type=float, default=None,
                        help="the spindle speed of the recording (default: the cut's)")
    parser.add_argument("--flutes", type=int, default=None,
                        help="the tool's flutes (default: the cut's)")
    parser.add_argument("--sidecar", type=Path, default=None, metavar="FILE",
                        help="the cut's conditions beside the recording (YAML or JSON, keys "
                             "as --design: spindle_rpm, flutes, feed_mm_s or feed_mm_min, "
                             "depth_mm, tool_diameter_mm, …): written into the cut")


def _mat_channels(src: Path, names: list[str], args) -> tuple[np.ndarray, list[str], float]:
    from robomill.importers._impact import ChannelSpec
    from robomill.importers.mat import channel, read_mat, sampling_rate

    variables = read_mat(src)
    if not names:
        raise RawDataError(src, "no channel given", where="option --channel",
                           expected="--channel NAME or NAME[column] (variables: "
                           + ", ".join(list(variables)[:20]) + ")")
    cols = [channel(src, variables, ChannelSpec(n, None, "--channel")) for n in names]
    if any(c.ndim != 1 or c.size != cols[0].size for c in cols):
        raise RawDataError(src, "channels of different lengths or several records",
                           where="option --channel", expected="vectors of equal length")
    return np.column_stack(cols), names, sampling_rate(src, variables, args)


def _lvm_channels(src: Path, names: list[str], args) -> tuple[np.ndarray, list[str], float]:
    from robomill.importers._common import nice_rate
    from robomill.importers._impact import ChannelSpec, pick_channel
    from robomill.importers.lvm import read_lvm

    seg = read_lvm(src)
    if len(seg) != 1:
        raise RawDataError(src, f"{len(seg)} segments", where="file",
                           expected="one segment per recording of a cut")
    seg = seg[0]
    names = names or seg["names"]
    idx = [pick_channel(src, seg["names"], ChannelSpec(n, None, "--channel")) for n in names]
    dt = seg["dt"][idx[0]]
    fs = getattr(args, "fs_hz", None) or (nice_rate(1.0 / dt) if dt > 0 else None)
    if not fs:
        raise RawDataError(src, "no Delta_X", where="header", expected="--fs-hz")
    return seg["data"][:, idx], [seg["names"][i] for i in idx], fs


def convert(sources: list[Path], staging: Path, args: argparse.Namespace) -> list[dict]:
    """Check, copy or convert every source; return the manifest entries."""
    from robomill.io.recordings import read_sound, read_vibration

    entries = []
    air = bool(getattr(args, "air", False))
    names = list(getattr(args, "channel", []) or [])
    for src in map(Path, sources):
        if not src.is_file():
            raise RawDataError(src, "file does not exist", expected="a recording of a cut")
        cut = cut_id(args, src, len(sources))
        suffix = src.suffix.lower()
        base = f"{cut}_air" if air else cut
        entry: dict = {"kind": "vibration", "cut": cut}
        if suffix in SOUND:
            read_sound(src)
            rel = f"sound/{base}{suffix}"
            entry["kind"] = "sound"
            (staging / "sound").mkdir(parents=True, exist_ok=True)
            shutil.copyfile(src, staging / rel)
        elif suffix in COPIED_VIBRATION:
            if suffix == ".tdms" and names:
                entry["channels"] = names
            if suffix == ".csv" and getattr(args, "fs_hz", None):
                entry["fs_hz"] = float(args.fs_hz)
            read_vibration(src, fs_hz=entry.get("fs_hz"), channels=entry.get("channels"))
            rel = f"vibration/{base}{suffix}"
            (staging / "vibration").mkdir(parents=True, exist_ok=True)
            shutil.copyfile(src, staging / rel)
        elif suffix in CONVERTED:
            data, cols, fs = (_mat_channels if suffix == ".mat" else _lvm_channels)(
                src, names, args)
            bad = ~np.isfinite(data)
            if bad.any():
                r, c = np.argwhere(bad)[0]
                raise RawDataError(src, "value is not finite", where=f"sample {r}, channel "
                                   f"{cols[c]}", expected="numbers")
            header = ["t_s"] + [_column_name(c) for c in cols]
            rel = f"vibration/{base}.csv"
            write_csv(staging / rel, header, (np.arange(data.shape[0]) / fs, *data.T),
                      ("%.12g", *("%.7g",) * data.shape[1]))
            entry.update({"fs_hz": float(fs), "source_file": src.name,
                          "source_format": suffix[1:]})
        else:
            raise RawDataError(src, f"unknown file type {suffix!r}", where="file name",
                               expected="a sound file (" + ", ".join(SOUND) + ") or a "
                               "vibration record (" + ", ".join(COPIED_VIBRATION + CONVERTED)
                               + ")")
        entry["path"] = rel
        if air:
            entry["pass"] = "air"
        for key in ("spindle_rpm", "flutes"):
            if getattr(args, key, None) is not None:
                entry[key] = getattr(args, key)
        entries.append(entry)
    return entries


def _column_name(name: str) -> str:
    import re

    return re.sub(r"[^A-Za-z0-9_]+", "_", name).strip("_") or "a"
