"""Forced vibration apart from chatter: a line that an air pass of the same instrument (the same
path without material) shows, and that the cut does not raise, is ``forced``
(:func:`robomill.chatter.air.air_test`), on constructed signals whose lines are known and
on a real milling sound (``tests/data/real/chatter_sound``, source and licence in its
SOURCE.md) through ``robomill listen FILE --air AIRFILE``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import soundfile

from robomill.chatter.air import air_test, call_forced
from robomill.chatter.verdicts import default_settings, judge
from robomill.cli import main

SOUND = Path(__file__).parent / "data" / "real" / "chatter_sound"
FS_HZ = 10_000.0
RPM, FLUTES = 6000.0, 3  # tooth passing 300 Hz
LINE_HZ = 437.0  # off the spindle's 100 Hz comb


def _record(line_amp: float, comb: bool, seed: int, seconds: float = 3.0) -> np.ndarray:
    t = np.arange(int(FS_HZ * seconds)) / FS_HZ
    x = 0.05 * np.random.default_rng(seed).standard_normal(t.size)
    if comb:
        x = x + sum(np.cos(2 * np.pi * 300.0 * k * t + k) / k for k in range(1, 8))
    return x + line_amp * np.sin(2 * np.pi * LINE_HZ * t)


@pytest.fixture(scope="module")
def settings():
    return default_settings()


def test_a_line_the_air_pass_has_at_the_same_level_is_forced(settings):
    cut = _record(0.6, comb=True, seed=1)
    v = judge(cut, FS_HZ, settings, spindle_rpm=RPM, flutes=FLUTES)
    assert v.verdict == "chatter" and v.chatter_hz == pytest.approx(LINE_HZ, abs=2.0)
    test = air_test(cut, FS_HZ, _record(0.6, comb=False, seed=2), FS_HZ, v.chatter_hz, settings)
    # the same amplitude in the air: the cut raises it by about 0 dB
    assert test.forced and abs(test.rise_db) < 1.0, test.evidence
    out = call_forced(v, test)
    assert out.verdict == "forced" and np.isnan(out.chatter_hz) and out.speeds_rpm == []
    assert out.line_hz == pytest.approx(LINE_HZ, abs=2.0)
    assert out.evidence.startswith("air test: forced")  # the test that decided first


def test_a_line_the_cut_raises_or_the_air_lacks_stays_chatter(settings):
    cut = _record(0.6, comb=True, seed=1)
    v = judge(cut, FS_HZ, settings, spindle_rpm=RPM, flutes=FLUTES)
    # the air pass rings at the line 30 dB weaker (amplitude / 31.6): the line grows with depth
    weak = air_test(cut, FS_HZ, _record(0.6 / 31.6, comb=False, seed=2), FS_HZ, v.chatter_hz,
                    settings)
    assert not weak.forced and weak.rise_db == pytest.approx(30.0, abs=1.5), weak.evidence
    assert "grows with depth" in weak.evidence
    quiet = air_test(cut, FS_HZ, _record(0.0, comb=False, seed=2), FS_HZ, v.chatter_hz, settings)
    assert not quiet.forced and "no line" in quiet.evidence
    out = call_forced(v, quiet)
    assert out.verdict == "chatter" and "air test: the air pass has no line" in out.evidence
    # another instrument (another rate) is not compared
    other = air_test(cut, FS_HZ, _record(0.6, comb=False, seed=2), 2 * FS_HZ, v.chatter_hz,
                     settings)
    assert not other.forced and "not the same instrument" in other.evidence


def _listen(capsys, *args: str) -> tuple[int, str]:
    rc = main(["listen", *args])
    return rc, capsys.readouterr().out


def test_listen_real_chatter_with_its_air_pass_is_still_chatter(capsys):
    """The authors' chatter recording, its air pass the seconds before the tool entered."""
    rc, out = _listen(capsys, str(SOUND / "rahimi_chatter_12500rpm_z4.flac"), "--rpm", "12500",
                      "--flutes", "4", "--air", str(SOUND / "rahimi_chatter_aircut.flac"))
    assert rc == 0
    first = out.splitlines()[0]
    assert first.endswith("chatter at 1067.4 Hz"), out
    assert "air test: the air pass" in out and "no line at 1067.4 Hz" in out


def test_listen_real_air_cut_line_is_forced_with_the_air_pass(capsys):
    """Seconds without material (no chatter can regenerate) that the spectral test alone calls
    chatter: with another air segment of the same microphone as the air pass, forced."""
    alone_rc, alone = _listen(capsys, str(SOUND / "rahimi_chatter_aircut.flac"), "--rpm",
                              "12500", "--flutes", "4")
    assert alone_rc == 0 and " chatter at 1770.7 Hz" in alone.splitlines()[0], alone
    rc, out = _listen(capsys, str(SOUND / "rahimi_chatter_aircut.flac"), "--rpm", "12500",
                      "--flutes", "4", "--air", str(SOUND / "rahimi_chatter_aircut_after.flac"))
    assert rc == 0
    assert out.splitlines()[0].endswith(
        "forced at 1770.7 Hz (forced vibration, not chatter)"), out
    assert "try spindle speeds" not in out


def test_listen_air_file_that_cannot_be_read_is_one_line(tmp_path, capsys):
    cut = tmp_path / "cut.flac"
    soundfile.write(cut, 0.05 * _record(0.6, comb=True, seed=1), int(FS_HZ))
    bad = tmp_path / "air.wav"
    bad.write_bytes(b"RIFF\x00\x00not a wave")
    rc, out = _listen(capsys, str(cut), "--air", str(bad))
    assert rc == 1 and len(out.strip().splitlines()) == 1 and "air.wav" in out


MANIFEST = {"experiment": {"spindle_rpm": 12500.0, "flutes": 4, "tool_diameter_mm": 6.0,
                           "cut_length_mm": 40.0},
            "cuts": [{"id": "c1", "feed_mm_s": 10.0, "depth_mm": 0.2, "direction": "px"}]}


def test_the_manifest_lists_air_passes_and_refuses_another_pass_in_one_line():
    from robomill.chatter.recordings import is_air_pass
    from robomill.errors import RawDataError
    from robomill.io.manifest import parse_manifest

    files = [{"path": "sound/c1.wav", "kind": "sound", "cut": "c1"},
             {"path": "sound/c1_air.wav", "kind": "sound", "cut": "c1", "pass": "air"},
             {"path": "vibration/c1_air.csv", "kind": "vibration", "cut": "c1", "pass": "air"}]
    m = parse_manifest({**MANIFEST, "files": files}, "m.yaml", require_sha256=False)
    assert [is_air_pass(f) for f in m.files] == [False, True, True]
    bad = {"path": "sound/c1_x.wav", "kind": "sound", "cut": "c1", "pass": "idle"}
    with pytest.raises(RawDataError, match=r"m.yaml: files\[0\] \(sound/c1_x.wav\).pass: pass "
                                           r"is 'idle' \(expected one of loaded, air\)"):
        parse_manifest({**MANIFEST, "files": [bad]}, "m.yaml", require_sha256=False)


def test_the_planner_reads_forced_as_not_chatter(tmp_path):
    import pandas as pd

    from robomill.plan.evidence import read_verdicts, verdict_stability

    path = tmp_path / "verdicts.csv"
    pd.DataFrame({"cut": ["a", "a", "b", "b", "c"],
                  "verdict": ["forced", "stable", "forced", "chatter", "forced"],
                  "chatter_hz": [np.nan, np.nan, np.nan, 900.0, np.nan],
                  "source": ["forces/a.h5", "vibration/a.csv", "forces/b.h5", "sound/b.wav",
                             "forces/c.h5"],
                  "evidence": ["air test: forced", "", "air test: forced", "", "air test"]},
                 ).to_csv(path, index=False)
    stability = verdict_stability(read_verdicts(path))
    assert stability.to_dict() == {"a": 1.0, "b": 0.0, "c": 1.0}


def _two_lines(machine_amp: float, chatter_amp: float, comb: bool, seed: int) -> np.ndarray:
    """A machine line at 180 Hz (off the 100 Hz spindle comb) and the chatter line."""
    t = np.arange(int(FS_HZ * 3.0)) / FS_HZ
    return _record(chatter_amp, comb, seed) + machine_amp * np.sin(2 * np.pi * 180.0 * t)


def test_a_forced_line_stronger_than_the_chatter_line_is_set_aside(settings):
    from robomill.chatter.air import judge_beside_air

    cut = _two_lines(2.0, 0.6, comb=True, seed=1)
    first = judge(cut, FS_HZ, settings, spindle_rpm=RPM, flutes=FLUTES)
    assert first.chatter_hz == pytest.approx(180.0, abs=2.0)  # the machine's line first

    def with_air(air):
        return judge_beside_air(cut, FS_HZ, settings, lambda hz: [
            air_test(cut, FS_HZ, air, FS_HZ, hz, settings)], spindle_rpm=RPM, flutes=FLUTES)

    # the air pass holds the machine's line only: chatter at the line the cut makes
    v = with_air(_two_lines(2.0, 0.0, comb=False, seed=2))
    assert v.verdict == "chatter" and v.chatter_hz == pytest.approx(LINE_HZ, abs=2.0)
    assert "set aside as forced by the air pass: 180.0 Hz" in v.evidence
    assert v.speeds_rpm  # chatter: speeds to try
    # the air pass holds both at the cut's level: forced at the first, nothing else left
    v = with_air(_two_lines(2.0, 0.6, comb=False, seed=2))
    assert v.verdict == "forced" and v.line_hz == pytest.approx(180.0, abs=2.0)
    assert v.evidence.startswith("air test: forced") and "without the forced line(s)" in v.evidence


def test_a_line_the_cut_does_not_raise_is_forced_even_faint_in_the_air(settings):
    """A line the air pass shows below ``prominence_db`` that the cut does not raise does not
    grow with depth: forced, and the evidence says the air pass holds it only faintly."""
    cut = _record(0.007, comb=True, seed=1)  # a faint line (about 8 dB over the floor)
    air = _record(0.007, comb=False, seed=2)
    test = air_test(cut, FS_HZ, air, FS_HZ, LINE_HZ, settings)
    assert test.air_above_floor_db < settings.prominence_db, test.evidence
    assert test.forced and abs(test.rise_db) < 3.0 and "holds the power" in test.evidence
