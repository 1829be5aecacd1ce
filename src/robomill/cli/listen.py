"""``robomill listen FILE [--rpm N --flutes Z] [--air AIRFILE]``: did this cut chatter, at what
frequency, and which spindle speeds to try instead, from one recording (sound, vibration or a
force record in CSV), with the pipeline's verdict (:func:`robomill.chatter.verdicts.judge`,
settings ``chatter.verdicts`` of the schema). With ``--air``, the recording of the same path
moved without material by the same instrument: a chatter line that it shows and the cut does
not raise is ``forced`` (:func:`robomill.chatter.air.air_test`), and the recording is
judged again without it (:func:`robomill.chatter.air.judge_beside_air`).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from robomill.errors import RawDataError

HELP = ("chatter verdict of one recording (WAV/FLAC/MP3 sound, accelerometer CSV/TDMS/UFF 58): "
        "stable | chatter | forced | undetermined, the chatter frequency and the speeds to try")


def add_parser(sub: Any) -> None:  # what ArgumentParser.add_subparsers() returns
    p = sub.add_parser("listen", help=HELP, description=HELP + ".")
    p.add_argument("file", type=Path, metavar="FILE", help="the recording")
    p.add_argument("--rpm", type=float, default=None,
                   help="spindle speed [rpm] (default: estimated from the signal's comb)")
    p.add_argument("--flutes", type=int, default=None,
                   help="number of flutes Z (needed for the recommended speeds)")
    p.add_argument("--kind", choices=("sound", "vibration"), default=None,
                   help="the recording's kind (default: from the suffix)")
    p.add_argument("--fs-hz", type=float, default=None,
                   help="sampling rate of a vibration CSV (default: from its t_s column)")
    p.add_argument("--air", type=Path, metavar="AIRFILE", default=None,
                   help="an air pass of the same cut by the same instrument (the same path "
                        "without material): a chatter line that the cut raises over it by less "
                        "than chatter.verdicts.air_rise_db is forced vibration, set aside, and "
                        "the recording judged on its other lines")
    p.add_argument("--range", type=float, nargs=2, metavar=("MIN", "MAX"), default=None,
                   help="range of the recommended speeds [rpm] (default: "
                        "chatter.verdicts.speed_range_rpm)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    import dataclasses

    from robomill.chatter.air import air_test, judge_beside_air
    from robomill.chatter.verdicts import default_settings, judge
    from robomill.io.recordings import read_recording

    settings = default_settings()
    if args.range is not None:
        settings = dataclasses.replace(settings, speed_range_rpm=tuple(sorted(args.range)))
    try:
        rec = read_recording(args.file, args.kind, fs_hz=args.fs_hz)
    except RawDataError as exc:
        print(f"robomill listen: {exc}")
        return 1
    air = None
    if args.air is not None:
        try:
            air = read_recording(args.air, args.kind or rec.kind, fs_hz=args.fs_hz)
        except RawDataError as exc:
            print(f"robomill listen: {exc}")
            return 1
    design = {"spindle_rpm": args.rpm, "flutes": args.flutes}
    if air is None:
        v = judge(rec.samples, rec.fs_hz, settings, **design)
    else:
        v = judge_beside_air(rec.samples, rec.fs_hz, settings, lambda line_hz: [air_test(
            rec.samples, rec.fs_hz, air.samples, air.fs_hz, line_hz, settings,
            air_name=f"the air pass {args.air}")], **design)
    print(f"{args.file}: {v.verdict}"
          + (f" at {v.chatter_hz:.1f} Hz" if v.verdict == "chatter" else "")
          + (f" at {v.line_hz:.1f} Hz (forced vibration, not chatter)"
             if v.verdict == "forced" else ""))
    print(f"  {rec.duration_s:.1f} s at {rec.fs_hz:g} Hz, {len(rec.channels)} channel(s)")
    print(f"  evidence: {v.evidence}")
    if v.speeds_rpm:
        lo, hi = settings.speed_range_rpm
        print(f"  try spindle speeds (n = 60 f_c / (Z k), {lo:g}-{hi:g} rpm): "
              + ", ".join(f"{n:.0f}" for n in v.speeds_rpm) + " rpm")
    return 0 if v.verdict != "undetermined" else 1
