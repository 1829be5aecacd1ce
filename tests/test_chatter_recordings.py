"""Recordings of the cut (robomill.io.recordings) and their verdicts: real milling sound labelled
chatter and no chatter (tests/data/real/chatter_sound), real vibration time records (UFF 58,
TDMS), the study's verdicts table with a bad recording in it, and ``robomill listen``."""

from pathlib import Path

import numpy as np
import pytest
import soundfile
import yaml

from robomill.chatter.recordings import VERDICT_COLUMNS, judge_study
from robomill.chatter.verdicts import default_settings, judge
from robomill.cli import main
from robomill.errors import RawDataError
from robomill.io.hashing import sha256_file
from robomill.io.manifest import load_manifest
from robomill.io.recordings import read_recording, read_sound, read_vibration

REAL = Path(__file__).parent / "data" / "real"
SOUND = REAL / "chatter_sound"


@pytest.fixture(scope="module")
def settings():
    return default_settings()


def test_real_chatter_recording_is_chatter_at_its_strongest_line(settings):
    rec = read_sound(SOUND / "rahimi_chatter_12500rpm_z4.flac")
    assert rec.fs_hz == 44100 and rec.duration_s == pytest.approx(8.0, abs=0.01)
    # the recording's strongest line, from its plain FFT (independent of the verdict's
    # spectrogram, comb and peak search)
    x = rec.samples[:, 0] - rec.samples[:, 0].mean()
    spec = np.abs(np.fft.rfft(x * np.hanning(x.size)))
    f = np.fft.rfftfreq(x.size, 1 / rec.fs_hz)
    f_strongest = f[np.argmax(np.where(f > 20, spec, 0))]
    assert f_strongest == pytest.approx(1067.0, abs=5.0)
    v = judge(rec.samples, rec.fs_hz, settings, spindle_rpm=12500, flutes=4)  # source's design
    assert v.verdict == "chatter"
    assert v.chatter_hz == pytest.approx(f_strongest, abs=2.0)
    # n = 60 f_c / (Z k) for k = 1: 60 * 1067 / 4 = 16005 rpm, nearest to 12500 first
    assert v.speeds_rpm[0] == pytest.approx(60 * v.chatter_hz / 4, rel=1e-9)


def test_real_no_chatter_recording_is_not_chatter(settings):
    rec = read_sound(SOUND / "rahimi_nochatter.flac")
    v = judge(rec.samples, rec.fs_hz, settings, flutes=4)  # no stated speed: comb estimated
    assert v.comb_source == "estimated"
    assert v.verdict != "chatter"


def test_real_vibration_time_records_read():
    uff = read_vibration(REAL / "uff" / "pyuff_binary8byte_time.uff")  # 250 samples, 0.01 s
    assert uff.fs_hz == pytest.approx(100.0) and uff.samples.shape == (250, 1)
    tdms = read_vibration(REAL / "tdms" / "raw1.tdms",
                          channels=["Layer Data/Second Chan", "Third Chan"])
    assert tdms.fs_hz == pytest.approx(50_000.0) and tdms.samples.shape == (2000, 2)
    with pytest.raises(RawDataError, match="frequency response|time response"):
        read_vibration(REAL / "uff" / "pyuff_measurement_roving_hammer.uff")


def test_vibration_csv_and_its_bad_rows(tmp_path):
    t = np.arange(2000) / 5000.0
    p = tmp_path / "acc.csv"
    p.write_text("t_s,ax_m_s2\n" + "".join(f"{a:.6f},{np.sin(600 * a):.5f}\n" for a in t))
    rec = read_vibration(p)
    assert rec.fs_hz == pytest.approx(5000.0, rel=1e-6) and rec.channels == ("ax_m_s2",)
    lines = p.read_text().splitlines()
    lines[11] = "0.002000,abc"
    p.write_text("\n".join(lines))
    with pytest.raises(RawDataError, match=r"row 12, column ax_m_s2"):
        read_vibration(p)


def test_unreadable_audio_is_one_line(tmp_path):
    bad = tmp_path / "cut.wav"
    bad.write_text("this is not audio")
    with pytest.raises(RawDataError) as e:
        read_recording(bad)
    assert str(bad) in str(e.value) and "\n" not in str(e.value)


def _study(tmp_path, files, experiment=None):
    raw = tmp_path / "raw"
    entries = []
    for rel, kind, extra in files:
        entries.append({"path": rel, "kind": kind, "cut": "c1", **extra,
                        "sha256": sha256_file(raw / rel)})
    m = {"experiment": {"spindle_rpm": 6000, "flutes": 3} if experiment is None else experiment,
         "cuts": [{"id": "c1", "feed_mm_s": 1.0, "depth_mm": 1.0, "direction": "px"}],
         "files": entries}
    (raw / "manifest.yaml").write_text(yaml.safe_dump(m))
    return load_manifest(raw / "manifest.yaml")


def _comb(fs=10_000.0, seconds=3.0, chatter=0.0, seed=0):
    t = np.arange(int(fs * seconds)) / fs
    x = sum(np.cos(2 * np.pi * 300.0 * k * t) / k for k in range(1, 8))
    x = x + chatter * np.sin(2 * np.pi * 1234.5 * t)
    return 0.1 * (x + 0.05 * np.random.default_rng(seed).standard_normal(t.size))


def test_study_table_judges_every_recording_and_survives_a_bad_one(tmp_path, settings):
    raw = tmp_path / "raw"
    (raw / "sound").mkdir(parents=True)
    (raw / "vibration").mkdir()
    soundfile.write(raw / "sound" / "c1_chatter.flac", _comb(chatter=1.0), 10_000)
    (raw / "sound" / "c1_bad.wav").write_text("not audio")
    x = _comb(seed=2)
    t = np.arange(x.size) / 10_000.0
    np.savetxt(raw / "vibration" / "c1.csv", np.column_stack([t, x]), delimiter=",",
               header="t_s,ay_m_s2", comments="", fmt="%.7g")
    m = _study(tmp_path, [("sound/c1_chatter.flac", "sound", {}),
                          ("sound/c1_bad.wav", "sound", {}),
                          ("vibration/c1.csv", "vibration", {})])
    table, ds = judge_study(m, m.files, settings)
    assert list(table.columns[:5]) == list(VERDICT_COLUMNS)
    by = table.set_index("source")
    assert by.loc["sound/c1_chatter.flac", "verdict"] == "chatter"
    assert by.loc["sound/c1_chatter.flac", "chatter_hz"] == pytest.approx(1234.5, abs=1.0)
    assert by.loc["vibration/c1.csv", "verdict"] == "stable"
    bad = by.loc["sound/c1_bad.wav"]
    assert bad["verdict"] == "undetermined" and "c1_bad.wav" in bad["evidence"]
    assert (table["cut"] == "c1").all() and (by["comb_source"].iloc[[0, 2]] == "design").all()
    assert ds.sizes["record"] == 2  # the two judged records' spectrograms


def test_recording_without_stated_or_estimable_speed_is_one_line(tmp_path, capsys):
    # a study's recordings always have their cut's speed (chapter 0 needs it); a recording
    # judged alone may have none, and a signal without a comb gives none to estimate
    p = tmp_path / "hiss.wav"
    soundfile.write(p, 0.1 * np.random.default_rng(5).standard_normal(30_000), 10_000)
    assert main(["listen", str(p)]) == 1
    out = capsys.readouterr().out
    assert f"{p}: undetermined" in out
    assert "no spindle speed stated and no harmonic comb found in the signal" in out


def test_listen_command(tmp_path, capsys):
    p = tmp_path / "cut.flac"
    soundfile.write(p, _comb(fs=20_000.0, chatter=1.0), 20_000)
    assert main(["listen", str(p), "--rpm", "6000", "--flutes", "3"]) == 0
    out = capsys.readouterr().out
    assert "chatter at 1234" in out and "try spindle speeds" in out
    assert "6172" in out  # 60 * 1234.5 / (3 * 4), by hand
    bad = tmp_path / "bad.mp3"
    bad.write_bytes(b"\x00" * 100)
    assert main(["listen", str(bad)]) == 1
    out = capsys.readouterr().out.strip()
    assert out.count("\n") == 0 and "bad.mp3" in out


def test_manifest_infers_recordings_from_their_folders(tmp_path):
    from robomill.cli.layout import infer_file

    raw = tmp_path / "raw"
    (raw / "sound").mkdir(parents=True)
    (raw / "vibration").mkdir()
    soundfile.write(raw / "sound" / "s1_g1_px.flac", np.zeros(100), 8000)
    uff = raw / "vibration" / "s1_g1_px.uff"
    uff.write_bytes((REAL / "uff" / "pyuff_binary8byte_time.uff").read_bytes())
    s = infer_file(raw, raw / "sound" / "s1_g1_px.flac")
    assert s.entry == {"path": "sound/s1_g1_px.flac", "kind": "sound", "cut": "s1_g1_px"}
    v = infer_file(raw, uff)  # a UFF in vibration/ is read as it is: no import note
    assert v.note is None and v.entry["kind"] == "vibration" and not v.missing
    soundfile.write(raw / "sound" / "s1_g1_px_air.flac", np.zeros(100), 8000)
    a = infer_file(raw, raw / "sound" / "s1_g1_px_air.flac")  # the cut's air pass
    assert a.entry == {"path": "sound/s1_g1_px_air.flac", "kind": "sound", "cut": "s1_g1_px",
                       "pass": "air"}


def test_chapter_4_recordings_prose_follows_the_verdict_findings(tmp_path, settings):
    import pandas as pd

    from robomill.chatter.recordings import verdict_findings
    from robomill.pipeline.prose import Prose, load_templates

    rows = [{"cut": "c1", "verdict": "chatter", "chatter_hz": 1234.5, "source": "forces/c1.csv",
             "evidence": "e1", "kind": "force", "energy_ratio": 0.6, "line_hz": 1234.5,
             "speeds_rpm": "6172 4938"},
            {"cut": "c1", "verdict": "chatter", "chatter_hz": 1240.0, "source": "sound/c1.flac",
             "evidence": "e2", "kind": "sound", "energy_ratio": 0.5, "line_hz": 1240.0,
             "speeds_rpm": "6200"},
            {"cut": "c2", "verdict": "stable", "chatter_hz": np.nan, "source": "forces/c2.csv",
             "evidence": "e3", "kind": "force", "energy_ratio": 0.01, "line_hz": 70.0,
             "speeds_rpm": ""},
            {"cut": "c3", "verdict": "forced", "chatter_hz": np.nan, "source": "forces/c3.csv",
             "evidence": "air test: forced: e4", "kind": "force", "energy_ratio": 0.3,
             "line_hz": 85.7, "speeds_rpm": ""}]
    found = verdict_findings(pd.DataFrame(rows), settings, n_air_passes=1)
    say = Prose(load_templates("ch4"), found)
    names = ["recordings_intro", "force_summary", "recording_lines", "force_lines",
             "forced_lines", "comparison"]
    text = " ".join(say(*names).split())
    assert ("4 records: 1 stable, 2 chatter, 1 forced, 0 undetermined (3 force records, "
            "1 recordings, 1 air passes)") in text
    assert ("Records whose line is forced vibration (the air test decided): - `forces/c3.csv` "
            "(cut c3, force): **forced** at 85.7 Hz (forced vibration, not chatter) — air test: "
            "forced: e4") in text
    assert "at least 0.1 of the comb's energy" in text
    assert "`sound/c1.flac` (cut c1, sound): **chatter** at 1240.0 Hz" in text
    assert "1 of 1 recordings agree" in text  # 1240 vs 1234.5 Hz: within 5 %
    assert "{" not in text


def _comb_with_line(line_hz, amp_t, fs=20_000.0, seconds=4.0, seed=0):
    """Tooth comb of 2 flutes at 6000 rpm (200 Hz) and one line of amplitude ``amp_t(t)``."""
    t = np.arange(int(fs * seconds)) / fs
    x = sum(np.cos(2 * np.pi * 200.0 * k * t + k) / k for k in range(1, 9))
    x = x + amp_t(t) * np.sin(2 * np.pi * line_hz * t)
    return x + 0.02 * np.random.default_rng(seed).standard_normal(t.size), fs


@pytest.mark.parametrize(("line_hz", "growing", "verdict"), [
    (500.0, False, "undetermined"),   # 5 x the 100 Hz rotation, steady: run-out or flip?
    (500.0, True, "chatter"),         # the same line growing through the record
    (537.0, False, "chatter"),        # off every spindle harmonic: regenerative chatter
])
def test_a_steady_line_on_a_spindle_harmonic_is_undetermined(settings, line_hz, growing,
                                                             verdict):
    amp = (lambda t: 0.1 + 0.9 * t / t[-1]) if growing else (lambda t: 0.6 + 0 * t)
    x, fs = _comb_with_line(line_hz, amp)
    v = judge(x, fs, settings, spindle_rpm=6000.0, flutes=2)
    assert v.verdict == verdict, v.evidence
    assert abs(v.line_hz - line_hz) < 3.0
    if verdict == "undetermined":
        assert "harmonic 5 (5 × 100.00 Hz)" in v.evidence and np.isnan(v.chatter_hz)
