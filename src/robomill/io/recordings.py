"""Readers for recordings of the cut: ``sound/<name>.wav|flac|mp3|ogg`` (a microphone) and
``vibration/<name>.csv|tdms|uff`` (an accelerometer), judged for chatter by
:mod:`robomill.chatter.verdicts`.

Contract (``docs/data-contract.md``, sections Sound and Vibration):

* **sound**: any file libsndfile reads (``soundfile``: WAV, FLAC, MP3, OGG…); the rate is the
  file's; the channels' powers are summed by the verdict.
* **vibration**, CSV: a header row, column ``t_s`` (time [s], strictly increasing with a
  constant step) then one or more acceleration columns (e.g. ``ax_m_s2``); the rate is the
  manifest's ``fs_hz`` when given, else ``1 / step``.
* **vibration**, TDMS: the channels named by the manifest's ``channels`` (``GROUP/CHANNEL`` or
  ``CHANNEL``; default every channel of the file), waveform channels with ``wf_increment``
  (:func:`robomill.importers.tdms.read_channels`).
* **vibration**, UFF 58 (``.uff``/``.unv``): the time responses (function type 1) of the file,
  evenly spaced and of equal length and step (:func:`robomill.io.impact.read_uff58`).

Every problem raises :class:`~robomill.errors.RawDataError` naming the file, the field (and
row) and what was expected.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from robomill.errors import RawDataError

SOUND_SUFFIXES = (".wav", ".flac", ".mp3", ".ogg", ".aiff", ".aif")
"""File suffixes of the kind ``sound``."""
VIBRATION_SUFFIXES = (".csv", ".tdms", ".uff", ".unv")
"""File suffixes of the kind ``vibration``."""
RECORDING_KINDS = ("sound", "vibration")
"""Manifest kinds of recordings of the cut."""


@dataclass
class Recording:
    """A recording's samples ``(n, channels)`` at ``fs_hz``, the channels' names."""

    path: Path
    kind: str
    fs_hz: float
    samples: np.ndarray
    channels: tuple[str, ...]

    @property
    def duration_s(self) -> float:
        return self.samples.shape[0] / self.fs_hz


def read_sound(path: str | Path) -> Recording:
    """A sound file through libsndfile (``soundfile.read``)."""
    import soundfile

    path = Path(path)
    if not path.is_file():
        raise RawDataError(path, "file does not exist", expected="a sound file")
    try:
        data, fs = soundfile.read(str(path), dtype="float64", always_2d=True)
    except (soundfile.LibsndfileError, RuntimeError, TypeError, ValueError) as exc:
        raise RawDataError(path, f"cannot be read as audio ({exc})", where="file",
                           expected="a WAV, FLAC, MP3 or OGG file libsndfile reads") from None
    if data.shape[0] < 2:
        raise RawDataError(path, f"only {data.shape[0]} samples", where="audio data",
                           expected="a recording of the cut")
    return Recording(path, "sound", float(fs), data,
                     tuple(f"channel {i + 1}" for i in range(data.shape[1])))


def _read_vibration_csv(path: Path, fs_hz: float | None) -> Recording:
    import pandas as pd

    try:
        df = pd.read_csv(path)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise RawDataError(path, f"not a readable CSV ({exc})", where="file",
                           expected="a header row, then t_s and acceleration columns") from None
    if "t_s" not in df.columns or df.shape[1] < 2:
        raise RawDataError(path, f"columns {list(df.columns)[:6]}", where="header row",
                           expected="t_s, then one or more acceleration columns")
    num = df.apply(pd.to_numeric, errors="coerce")
    bad = num.isna().to_numpy()
    if bad.any():
        r, c = np.argwhere(bad)[0]
        raise RawDataError(path, f"value {df.iat[r, c]!r} is not a number",
                           where=f"row {r + 2}, column {df.columns[c]}", expected="numbers")
    t = num["t_s"].to_numpy(float)
    dt = np.diff(t)
    if t.size < 2 or not np.all(dt > 0):
        row = int(np.argmax(dt <= 0)) + 3 if t.size >= 2 else 2
        raise RawDataError(path, "time does not increase", where=f"row {row}, column t_s",
                           expected="strictly increasing time")
    step = float(np.median(dt))
    if np.max(np.abs(dt - step)) > 0.01 * step:
        row = int(np.argmax(np.abs(dt - step))) + 3
        raise RawDataError(path, f"time step {dt[row - 3]:g} s where the record's is {step:g} s",
                           where=f"row {row}, column t_s", expected="a constant time step")
    fs = float(fs_hz) if fs_hz else 1.0 / step
    cols = [c for c in df.columns if c != "t_s"]
    return Recording(path, "vibration", fs, num[cols].to_numpy(float), tuple(cols))


def _read_vibration_tdms(path: Path, channels: Sequence[str] | None) -> Recording:
    from robomill.importers.tdms import list_channels, read_channels

    if not channels:
        from nptdms import TdmsFile

        try:
            channels = list_channels(TdmsFile.read(path))
        except Exception:  # the reader below says what is wrong with the file
            channels = ["?"]
    data, fs, _ = read_channels(path, {c: c for c in channels})
    return Recording(path, "vibration", fs, np.column_stack(list(data.values())),
                     tuple(channels))


def _read_vibration_uff(path: Path) -> Recording:
    from robomill.io.impact import read_uff58

    sets = [(n, s) for n, s in enumerate(read_uff58(path)) if int(s.get("func_type", 0)) == 1]
    if not sets:
        raise RawDataError(path, "no time response (UFF 58 with function type 1)",
                           where="func_type", expected="time records of the accelerometer")
    cols, names, step = [], [], None
    for n, s in sets:
        inc = float(s.get("abscissa_inc", 0) or 0)
        data = np.asarray(s.get("data", [])).real.astype(float)
        where = f"data set {n + 1} ({str(s.get('id1', '')).strip()})"
        if int(s.get("abscissa_spacing", 1)) != 1 or not inc > 0:
            raise RawDataError(path, f"abscissa spacing {s.get('abscissa_spacing')!r}, step "
                               f"{inc!r}", where=where, expected="evenly spaced time")
        if step is None:
            step, size = inc, data.size
        elif abs(inc - step) > 1e-9 * step or data.size != size:
            raise RawDataError(path, f"{data.size} samples every {inc:g} s", where=where,
                               expected=f"{size} samples every {step:g} s as data set "
                                        f"{sets[0][0] + 1}")
        cols.append(data)
        names.append(f"{s.get('rsp_node', 0)}:{s.get('rsp_dir', 0)} "
                     f"{str(s.get('ordinate_axis_units_lab', '')).strip()}".strip())
    return Recording(path, "vibration", 1.0 / step, np.column_stack(cols), tuple(names))


def read_vibration(path: str | Path, *, fs_hz: float | None = None,
                   channels: Sequence[str] | None = None) -> Recording:
    """An accelerometer record (CSV, TDMS or UFF 58 time responses; see the module)."""
    path = Path(path)
    if not path.is_file():
        raise RawDataError(path, "file does not exist", expected="a vibration record")
    suffix = path.suffix.lower()
    if suffix == ".csv":
        rec = _read_vibration_csv(path, fs_hz)
    elif suffix == ".tdms":
        rec = _read_vibration_tdms(path, channels)
    elif suffix in (".uff", ".unv"):
        rec = _read_vibration_uff(path)
    else:
        raise RawDataError(path, f"suffix {suffix!r}", where="file name",
                           expected="one of " + ", ".join(VIBRATION_SUFFIXES))
    if not np.all(np.isfinite(rec.samples)):
        r, c = np.argwhere(~np.isfinite(rec.samples))[0]
        raise RawDataError(path, "value is not finite",
                           where=f"sample {r}, channel {rec.channels[c]}",
                           expected="finite numbers")
    return rec


def read_recording(path: str | Path, kind: str | None = None, *, fs_hz: float | None = None,
                   channels: Sequence[str] | None = None) -> Recording:
    """A recording of kind ``sound`` or ``vibration`` (``None``: from the file's suffix)."""
    path = Path(path)
    if kind is None:
        kind = "sound" if path.suffix.lower() in SOUND_SUFFIXES else (
            "vibration" if path.suffix.lower() in VIBRATION_SUFFIXES else "sound")
    if kind == "sound":
        return read_sound(path)
    if kind == "vibration":
        return read_vibration(path, fs_hz=fs_hz, channels=channels)
    raise RawDataError(path, f"kind {kind!r}", expected="sound or vibration")
