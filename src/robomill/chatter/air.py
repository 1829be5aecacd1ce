"""Forced vibration apart from chatter: the air test of a chatter line (step 6 of
:mod:`robomill.chatter.verdicts`) and the record judged again beside its air passes.

A line present while the same path is moved without cutting (an **air pass** of the same
instrument) that the cut does not raise is forced vibration, not regenerative chatter, which
exists only above a limiting depth and raises its line far over the air pass
[Altintas 2012, ch. 4]. The references are those of :mod:`robomill.chatter.verdicts`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from robomill.chatter.verdicts import Verdict, VerdictSettings, judge, spectrogram_power


@dataclass(frozen=True)
class AirTest:
    """The air test of one line (:func:`air_test`): ``forced`` when the line is present in the
    air pass (``air_above_floor_db`` ≥ ``prominence_db``) and the cut raises it by less than
    ``air_rise_db`` (``rise_db``); ``evidence`` says so in words."""

    forced: bool
    line_hz: float
    air_above_floor_db: float
    rise_db: float
    evidence: str


def mean_spectrum(signal: np.ndarray, fs_hz: float, window_s: float
                  ) -> tuple[np.ndarray, np.ndarray]:
    """``(f [Hz], mean power per bin)`` of a record over all its frames
    (:func:`spectrogram_power`)."""
    f, _, S = spectrogram_power(signal, fs_hz, window_s)
    return f, S.mean(axis=1)


def air_test(cut_signal: np.ndarray, cut_fs_hz: float, air_signal: np.ndarray,
             air_fs_hz: float, line_hz: float, settings: VerdictSettings, *,
             air_name: str = "the air pass") -> AirTest:
    """Whether the line at ``line_hz`` of a cut's record is forced vibration: present in the
    air pass of the same instrument (the same path without material) and not raised by the
    cut (the module's step 6).

    Both records' mean spectra (Hann windows of ``window_s``: the same bins when the rates
    agree); within ``w = max(harmonic_halfwidth_hz, 2 Δf)`` of ``line_hz`` the air pass's
    largest power ``P_a`` over its local floor (median over ``± floor_halfwidth_hz``) and the
    cut's largest power ``P_c``: forced when ``10 log10(P_c / P_a) < air_rise_db`` (the line
    does not grow with depth; the evidence says whether the air pass shows it
    ``prominence_db`` above its floor: a line just under that is no chatter either when the
    cut does not raise it). Records of other rates (not the same instrument)
    or an air pass shorter than two windows: not forced, and the evidence says why."""
    s = settings
    if not np.isfinite(line_hz):
        return AirTest(False, line_hz, float("nan"), float("nan"), "no line to test")
    if abs(cut_fs_hz / air_fs_hz - 1.0) > 1e-6:
        return AirTest(False, line_hz, float("nan"), float("nan"),
                       f"{air_name} is sampled at {air_fs_hz:g} Hz, the cut at {cut_fs_hz:g} "
                       "Hz: not the same instrument, not compared")
    n_win = max(8, int(round(s.window_s * air_fs_hz)))
    if np.asarray(air_signal).shape[0] < 2 * n_win:
        return AirTest(False, line_hz, float("nan"), float("nan"),
                       f"{air_name} is shorter than two {s.window_s:g} s windows")
    f, P_cut = mean_spectrum(cut_signal, cut_fs_hz, s.window_s)
    fa, P_air = mean_spectrum(air_signal, air_fs_hz, s.window_s)
    if fa.size != f.size:
        P_air = np.interp(f, fa, P_air)
    df = float(f[1] - f[0])
    w = max(s.harmonic_halfwidth_hz, 2.0 * df)
    near = np.abs(f - line_hz) <= w
    ring = (np.abs(f - line_hz) <= s.floor_halfwidth_hz) & (f >= s.band_hz[0])
    tiny = 1e-300
    floor = float(np.median(P_air[ring])) if ring.any() else tiny
    p_air, p_cut = float(P_air[near].max()), float(P_cut[near].max())
    above = 10.0 * np.log10(max(p_air, tiny) / max(floor, tiny))
    rise = 10.0 * np.log10(max(p_cut, tiny) / max(p_air, tiny))
    present = above >= s.prominence_db
    forced = rise < s.air_rise_db
    if forced and present:
        text = (f"forced: the line {line_hz:.1f} Hz is in {air_name} ({above:.1f} dB above its "
                f"floor there, ≥ {s.prominence_db:g} dB) and the cut raises it by {rise:+.1f} dB "
                f"(< {s.air_rise_db:g} dB): present without cutting, it does not grow with "
                "depth")
    elif forced:
        text = (f"forced: {air_name} holds the power at {line_hz:.1f} Hz ({above:.1f} dB above "
                f"its floor) that the cut raises by {rise:+.1f} dB only (< {s.air_rise_db:g} "
                "dB): it does not grow with depth")
    elif present:
        text = (f"{air_name} has a line at {line_hz:.1f} Hz ({above:.1f} dB above its floor), but "
                f"the cut raises it by {rise:+.1f} dB (≥ {s.air_rise_db:g} dB): it grows with "
                "depth, not forced")
    else:
        text = (f"{air_name} has no line at {line_hz:.1f} Hz ({above:.1f} dB above its floor, "
                f"< {s.prominence_db:g} dB) and the cut raises the power there by {rise:+.1f} dB "
                f"(≥ {s.air_rise_db:g} dB): not forced")
    return AirTest(forced, line_hz, above, rise, text)


def call_forced(verdict: Verdict, test: AirTest) -> Verdict:
    """``verdict`` with the air test's sentence added to its evidence, and ``forced`` instead
    of ``chatter`` when the test says so (no chatter frequency, no speeds to try: nothing
    regenerates; ``line_hz`` keeps the line; the evidence then opens with the air test, the
    test that decided)."""
    import dataclasses

    if verdict.verdict != "chatter":
        return verdict
    out = dataclasses.replace(verdict, evidence=f"{verdict.evidence}; air test: {test.evidence}")
    if test.forced:  # the test that decided first
        out.evidence = f"air test: {test.evidence}; {verdict.evidence}"
        out.verdict, out.chatter_hz = "forced", float("nan")
        out.speeds_rpm, out.tooth_targets_hz = [], []
    return out


def judge_beside_air(signal: np.ndarray, fs_hz: float, settings: VerdictSettings,
                     test_line: Callable[[float], list[AirTest]], **design: Any) -> Verdict:
    """:func:`judge` with the air passes (the module's step 6) asked of each chatter line:
    ``test_line(line_hz)`` gives the air tests of a line, the first forced one decides
    (:func:`call_forced`). A forced line is set aside and the record judged again on its
    other lines, so that a forced line stronger than a regenerating one (a machine's line
    through a record with seconds out of the cut) does not hide it: **chatter** on the first
    line that no air pass explains (its evidence names the lines set aside), else the first
    line's **forced** verdict (its evidence says what the other lines gave). ``design``:
    :func:`judge`'s keywords. Ends: every pass sets one more prominent line aside."""
    aside: list[float] = []
    first: Verdict | None = None
    while True:
        v = judge(signal, fs_hz, settings, set_aside_hz=tuple(aside), **design)
        if v.verdict != "chatter":
            break
        out = v
        for test in test_line(v.chatter_hz):
            out = call_forced(out, test)
            if out.verdict == "forced":
                break
        if out.verdict != "forced":
            v = out
            break
        first = first or out
        aside.append(v.chatter_hz)
    if first is None:
        return v
    listed = ", ".join(f"{a:.1f}" for a in aside)
    if v.verdict == "chatter":
        v.evidence += (f"; set aside as forced by the air pass: {listed} Hz ({first.evidence})")
        return v
    first.evidence += f"; without the forced line(s) {listed} Hz: {v.verdict} ({v.evidence})"
    return first
