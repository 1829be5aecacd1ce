"""A real accelerometer record labelled chatter by its authors, through ``robomill import
recording`` (MATLAB ``.mat``) and ``robomill listen`` (``tests/data/real/chatter_vibration``,
source, licence and label in its SOURCE.md).

The truth is the authors' own file ``properties.mat``: its ``Label``, spindle speed ``S``,
``numFlutes`` and ``sampling``, read here, never typed in. The seconds of the cut are found
by the test from the record's level (0.1 s RMS well above the record's median, the spindle
idling out of the material before and after); the chatter line is the strongest line of the
cut's plain FFT that the idle seconds lack, found by the test without the verdict."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import scipy.io

from robomill.cli import main

REAL = Path(__file__).parent / "data" / "real" / "chatter_vibration"


@pytest.fixture(scope="module")
def props() -> dict:
    p = scipy.io.loadmat(REAL / "properties.mat", squeeze_me=True)["properties"]
    return {k: p[k].item() for k in ("Label", "S", "numFlutes", "sampling", "Source", "type")}


@pytest.fixture(scope="module")
def imported(tmp_path_factory, props) -> Path:
    """``data.mat`` imported as the lab would: ``robomill import recording`` with the rate and
    design the authors' properties state (the .mat itself carries neither)."""
    raw = tmp_path_factory.mktemp("raw")
    rc = main(["import", "recording", str(REAL / "data.mat"), "--to", str(raw), "--cut", "n255",
               "--channel", "data", "--fs-hz", str(props["sampling"]),
               "--design", f"spindle_rpm={props['S']}", "--design",
               f"flutes={props['numFlutes']}"])
    assert rc == 0
    return raw / "vibration" / "n255.csv"


def _level_segments(x: np.ndarray, fs: float) -> tuple[slice, slice, slice]:
    """(cut, before, after): the cut is the longest run of 0.1 s frames whose RMS exceeds 1.5
    times the record's median frame RMS; before and after leave 0.3 s to the cut and to the
    record's ends."""
    n = int(round(0.1 * fs))
    rms = np.array([x[i:i + n].std() for i in range(0, x.size - n + 1, n)])
    loud = rms > 1.5 * np.median(rms)
    best, start = (0, 0), None
    for i, flag in enumerate(np.append(loud, False)):
        if flag and start is None:
            start = i
        elif not flag and start is not None:
            best = max(best, (i - start, start))
            start = None
    length, first = best
    a, b = first * n, (first + length) * n
    gap = int(round(0.3 * fs))
    return slice(a, b), slice(gap, a - gap), slice(b + gap, x.size - gap)


@pytest.fixture(scope="module")
def segments(imported, tmp_path_factory) -> dict:
    d = pd.read_csv(imported)
    t, x = d["t_s"].to_numpy(), d["data"].to_numpy()
    fs = 1.0 / float(np.median(np.diff(t)))
    cut, before, after = _level_segments(x, fs)
    out = tmp_path_factory.mktemp("seg")
    paths = {}
    for name, sl in (("cut", cut), ("before", before), ("after", after)):
        seg = x[sl]
        path = out / f"{name}.csv"
        pd.DataFrame({"t_s": np.arange(seg.size) / fs, "data": seg}).to_csv(path, index=False)
        paths[name] = path
    return {"fs": fs, "x": x, "cut": cut, "before": before, "after": after, **{
        f"{k}_csv": v for k, v in paths.items()}}


def _spectrum(x: np.ndarray, fs: float) -> tuple[np.ndarray, np.ndarray]:
    x = (x - x.mean()) * np.hanning(x.size)
    return np.fft.rfftfreq(x.size, 1.0 / fs), np.abs(np.fft.rfft(x)) ** 2


def _power_near(f, p, f0, w=3.0) -> float:
    return float(p[np.abs(f - f0) <= w].max())


def _listen(capsys, *args: str) -> tuple[int, str]:
    rc = main(["listen", *args])
    return rc, capsys.readouterr().out


def test_the_authors_label_and_the_cut_seconds(props, segments):
    assert props["Label"] == "chatter" and props["Source"] == "AccelerationY"
    fs, x = segments["fs"], segments["x"]
    assert fs == pytest.approx(props["sampling"])
    cut, before = x[segments["cut"]], x[segments["before"]]
    # the cut: about 1.2 s of the 8 s record, at least twice the idle level
    assert 0.8 <= cut.size / fs <= 2.0 and before.size / fs >= 2.0
    assert cut.std() > 2.0 * before.std()


def test_listen_calls_the_authors_chatter_record_chatter_at_its_line(props, segments, capsys):
    fs, x = segments["fs"], segments["x"]
    f, pc = _spectrum(x[segments["cut"]], fs)
    fb, pb = _spectrum(x[segments["before"]], fs)
    pb = np.interp(f, fb, pb) * (x[segments["cut"]].size / x[segments["before"]].size)
    band = (f > 20.0) & (f < 0.95 * fs / 2)
    new = band & (pc > 100.0 * pb)  # 20 dB above the idle seconds: the cut's own lines
    line_hz = float(f[new][np.argmax(pc[new])])
    rc, out = _listen(capsys, str(segments["cut_csv"]), "--rpm", str(props["S"]), "--flutes",
                      str(props["numFlutes"]))
    assert rc == 0
    first = out.splitlines()[0]
    assert " chatter at " in first, out
    chatter_hz = float(first.split(" chatter at ")[1].split(" Hz")[0])
    assert chatter_hz == pytest.approx(line_hz, abs=5.0), out
    # the idle seconds as the air pass: no line there, the verdict stays chatter
    rc, out = _listen(capsys, str(segments["cut_csv"]), "--rpm", str(props["S"]), "--flutes",
                      str(props["numFlutes"]), "--air", str(segments["before_csv"]))
    assert rc == 0 and out.splitlines()[0].endswith(f"chatter at {chatter_hz:.1f} Hz"), out
    assert "not forced" in out


def test_listen_idle_seconds_line_is_forced_with_the_other_idle_seconds(props, segments,
                                                                         capsys):
    """Seconds without material: the spectral test alone calls a line of the machine chatter;
    with the seconds after the cut as the air pass it is forced."""
    fs, x = segments["fs"], segments["x"]
    rc, alone = _listen(capsys, str(segments["before_csv"]), "--rpm", str(props["S"]),
                        "--flutes", str(props["numFlutes"]))
    assert rc == 0 and " chatter at " in alone.splitlines()[0], alone
    line_hz = float(alone.splitlines()[0].split(" chatter at ")[1].split(" Hz")[0])
    f, pa = _spectrum(x[segments["after"]], fs)
    floor = float(np.median(pa[np.abs(f - line_hz) <= 50.0]))
    assert _power_near(f, pa, line_hz) > 100.0 * floor  # the line is in the seconds after too
    rc, out = _listen(capsys, str(segments["before_csv"]), "--rpm", str(props["S"]), "--flutes",
                      str(props["numFlutes"]), "--air", str(segments["after_csv"]))
    assert rc == 0
    assert out.splitlines()[0].endswith(
        f"forced at {line_hz:.1f} Hz (forced vibration, not chatter)"), out


def test_listen_whole_record_with_air_pass_sets_the_idle_line_aside(props, imported, segments,
                                                                     capsys):
    """The whole 8 s record (6.7 s of it idle) with the idle seconds before the cut as its air
    pass: the idle 150 Hz line is the strongest and forced; set aside, the cut's own line is
    the chatter (before ``judge_beside_air`` the record was called forced at 150 Hz)."""
    fs, x = segments["fs"], segments["x"]
    rc, out = _listen(capsys, str(imported), "--rpm", str(props["S"]), "--flutes",
                      str(props["numFlutes"]))
    alone = float(out.splitlines()[0].split(" chatter at ")[1].split(" Hz")[0])
    f, pb = _spectrum(x[segments["before"]], fs)
    floor = float(np.median(pb[np.abs(f - alone) <= 50.0]))
    assert _power_near(f, pb, alone) > 1000.0 * floor  # the strongest line is the idle one
    rc, out = _listen(capsys, str(imported), "--rpm", str(props["S"]), "--flutes",
                      str(props["numFlutes"]), "--air", str(segments["before_csv"]))
    assert rc == 0
    first = out.splitlines()[0]
    assert " chatter at " in first, out
    chatter_hz = float(first.split(" chatter at ")[1].split(" Hz")[0])
    rc, cut_out = _listen(capsys, str(segments["cut_csv"]), "--rpm", str(props["S"]),
                          "--flutes", str(props["numFlutes"]))
    assert cut_out.splitlines()[0].endswith(f"chatter at {chatter_hz:.1f} Hz"), (out, cut_out)
    assert abs(chatter_hz - alone) > 100.0
    assert f"set aside as forced by the air pass: {alone:.1f} Hz" in out
