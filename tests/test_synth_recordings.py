"""Recordings simulated on the virtual cell (robomill.synth.recordings): a microphone and a
spindle accelerometer sample the same closed-loop cut as the dynamometer; the library's
verdict routine (robomill.chatter.verdicts.judge), reading the written files with the
readers of a lab's recordings, calls a chattering cut chatter and a stable one not, and the
spindle speed it recommends for the chattering one is stable in the simulation.

Truths come from the simulation, not from the verdict routine: whether a cut chatters from
the criteria of tests/test_synth_process.py (the share of tooth passages whose chip vanished,
the largest force line off the spindle's harmonics against the mean force), the chatter's
frequencies from a plain spectrum of the simulated tool displacement: regenerative chatter
of a mode at f_v shows in milling at f_v + m f_t (f_t the tooth passing) and, as the teeth
leave the cut, at its harmonics, so the frequency a sensor names must be one of
``m f_t + j f_v``.

The chattering cut is the thesis cut s1_g3_px at 3 mm (12 times its design depth). The
speed the recordings recommend first, about 30 400 rpm (k = 2 of their ≈ 2026 Hz line, i.e.
the tooth passing on the force's ≈ 1013 Hz line), lies in the stable pocket that the spindle
modes (2.1 kHz) open where their second tooth harmonic sits near them: in the simulation the
cut is stable from about 29 000 to 32 000 rpm at 3 mm, and the next speeds of the family
(k = 3, 4, 5: about 20 260, 15 200, 12 160 rpm) chatter. At 4 mm (the deep cut of
tests/test_pipeline_deep_cut.py) the pocket narrows to about 31 000–32 500 rpm and the
recommended 30 400 rpm is at its lower edge (stable or not with the cut's noise): the rule
aims 3–4 % below the pocket's middle, because the line it reads sits below the spindle mode.
"""

from __future__ import annotations

import copy
import dataclasses

import numpy as np
import pytest
from test_synth_process import _spindle_non_harmonic_line

from robomill.chatter.verdicts import default_settings, judge
from robomill.io.recordings import read_recording
from robomill.io.synthetic_layout import instrument_files, synthetic_cuts
from robomill.synth.cell import cell_from_config
from robomill.synth.process import simulate_cut
from robomill.synth.recordings import simulate_file

RPM, FLUTES = 28000.0, 2
DEEP_MM = 3.0


@pytest.fixture(scope="module")
def study(config):
    c = copy.deepcopy(config)
    c["experiment"]["cut_length_mm"] = 8.0
    c["synth"]["dynamometer"]["record_length_mm"] = 4.0
    c["synth"]["recordings"].update(sound=True, vibration=True)
    return c, cell_from_config(c)


def _cut(config, **changes):
    cut = next(c for c in synthetic_cuts(config) if c.id == "s1_g3_px")
    return dataclasses.replace(cut, **changes)


def _judged(config, cell, cut, folder):
    """The verdicts of the cut's sound and vibration files, as written and read back."""
    out = {}
    sim = simulate_cut(cell, cut, config, length_mm=4.0)  # the recordings' span
    for kind, path in (("sound", folder / f"{cut.id}.wav"),
                       ("vibration", folder / f"{cut.id}.csv")):
        simulate_file(config, cut, path, kind, sim, cell=cell)
        rec = read_recording(path, kind)
        out[kind] = judge(rec.samples, rec.fs_hz, default_settings(), spindle_rpm=RPM,
                          flutes=FLUTES)
    return out


def _tool_vibration_hz(sim) -> float:
    """The strongest line of the simulated tool displacement off the spindle's harmonics
    (second half of the record, Hann window, plain FFT)."""
    x = sim.deflection_m[sim.t_s.size // 2:]
    x = x - x.mean(axis=0)
    w = np.hanning(x.shape[0])[:, None]
    power = (np.abs(np.fft.rfft(x * w, axis=0)) ** 2).sum(axis=1)
    f = np.fft.rfftfreq(x.shape[0], 1 / sim.fs_hz)
    spindle_hz = sim.tooth_hz / FLUTES
    off = (f > 10.0) & (np.abs(f / spindle_hz - np.round(f / spindle_hz)) * spindle_hz > 20.0)
    return float(f[np.argmax(np.where(off, power, 0.0))])


def test_the_recordings_are_off_by_default(config):
    assert instrument_files(config, "recordings") == []
    assert config["synth"]["recordings"]["sound"] is False
    assert config["synth"]["recordings"]["vibration"] is False


def test_the_recordings_are_listed_with_their_cut_when_on(study):
    config, _ = study
    files = instrument_files(config, "recordings")
    cuts = [c.id for c in synthetic_cuts(config)]
    assert [f["path"] for f in files[:4]] == [
        f"sound/{cuts[0]}.wav", f"vibration/{cuts[0]}.csv",
        f"sound/{cuts[0]}_air.wav", f"vibration/{cuts[0]}_air.csv"]  # each with its air pass
    assert len(files) == 4 * len(cuts)
    assert {f["kind"] for f in files} == {"sound", "vibration"}
    assert all(f["fs_hz"] == 25600.0 for f in files if f["kind"] == "vibration")
    assert all((f.get("pass") == "air") == f["path"].endswith(("_air.wav", "_air.csv"))
               and f["cut"] in cuts for f in files)
    config = {**config, "synth": {**config["synth"], "recordings": {
        **config["synth"]["recordings"], "air_pass": False}}}
    assert len(instrument_files(config, "recordings")) == 2 * len(cuts)


def test_the_air_pass_hears_the_arm_and_not_the_teeth(study, tmp_path):
    """The accelerometer's air pass (no chip): the structure's vibration under the servo
    excitation, none of the tooth passing that the cut's own record is full of."""
    from robomill.synth.recordings import simulate_air_pass_file

    config, cell = study
    cut = _cut(config, id="design")
    simulate_file(config, cut, tmp_path / "cut.csv", "vibration",
                  simulate_cut(cell, cut, config, length_mm=4.0), cell=cell)
    simulate_air_pass_file(config, cut, tmp_path / "air.csv", "vibration",
                           simulate_cut(cell, cut, config, cutting=False, length_mm=4.0),
                           cell=cell)
    power = {}
    for name in ("cut", "air"):
        rec = read_recording(tmp_path / f"{name}.csv", "vibration")
        x = rec.samples - rec.samples.mean(axis=0)
        spec = (np.abs(np.fft.rfft(x * np.hanning(x.shape[0])[:, None], axis=0)) ** 2).sum(1)
        f = np.fft.rfftfreq(x.shape[0], 1 / rec.fs_hz)
        power[name] = (f, spec)
    f, cut_p = power["cut"]
    _, air_p = power["air"]
    tooth_hz = RPM / 60.0 * FLUTES
    at_tooth = np.abs(f - tooth_hz) < 3.0
    robot = (f > 10.0) & (f < 150.0)  # the robot's modes (config synth.modes)
    assert cut_p[at_tooth].max() > 1e4 * air_p[at_tooth].max()  # no teeth in the air
    assert air_p[robot].max() > 0 and air_p[robot].max() > 0.1 * cut_p[robot].max()


def test_a_chattering_and_a_stable_cut_get_their_verdicts_and_the_speed_is_stable(
        study, tmp_path):
    config, cell = study
    design, deep = _cut(config, id="design"), _cut(config, id="deep", depth_mm=DEEP_MM)
    # the simulation's own account: the design cut stable, the deep one chatters
    sim_design = simulate_cut(cell, design, config, length_mm=4.0)
    sim_deep = simulate_cut(cell, deep, config, length_mm=4.0)
    assert sim_design.teeth_out < 0.05 and sim_deep.teeth_out > 0.3

    # the microphone's and the accelerometer's files, read back and judged
    stable = _judged(config, cell, design, tmp_path)
    chatter = _judged(config, cell, deep, tmp_path)
    rec = read_recording(tmp_path / "deep.wav", "sound")
    assert rec.fs_hz == 44100.0 and rec.duration_s == pytest.approx(4.0 / 3.0, abs=0.01)
    for kind in ("sound", "vibration"):
        assert stable[kind].verdict == "stable", stable[kind].evidence
        assert chatter[kind].verdict == "chatter", chatter[kind].evidence
        f_c = chatter[kind].chatter_hz
        # a line of the tool's chatter: m f_t + j f_v, off the spindle's harmonics
        f_v, f_t = _tool_vibration_hz(sim_deep), sim_deep.tooth_hz
        family = [m * f_t + j * f_v for m in range(0, 12) for j in (-2, -1, 1, 2)]
        assert min(abs(f_c - g) for g in family) < 8.0, (kind, f_c, f_v)
        spindle_hz = f_t / FLUTES
        assert abs(f_c / spindle_hz - round(f_c / spindle_hz)) * spindle_hz > 20.0
    assert chatter["sound"].chatter_hz == pytest.approx(chatter["vibration"].chatter_hz,
                                                        abs=5.0)

    # the speed recommended first, n = 60 f_c / (Z k) nearest to the cut's, is stable in the
    # simulation (the feed per tooth kept), by the simulator's criteria and the recordings'
    speeds = chatter["vibration"].speeds_rpm
    lo, hi = default_settings().speed_range_rpm
    assert speeds and all(lo <= n <= hi for n in speeds)
    n = speeds[0]
    k = 60.0 * chatter["vibration"].chatter_hz / (FLUTES * n)
    assert k == pytest.approx(round(k), abs=1e-6)
    moved = _cut(config, id="moved", depth_mm=DEEP_MM, spindle_rpm=n,
                 feed_mm_s=deep.feed_mm_s * n / RPM)
    sim = simulate_cut(cell, moved, config)
    amp, _ = _spindle_non_harmonic_line(sim)
    assert sim.teeth_out < 0.05
    assert amp < 0.05 * float(np.linalg.norm(sim.force_N.mean(axis=0)))
    again = simulate_file(config, moved, tmp_path / "moved.csv", "vibration", sim, cell=cell)
    rec = read_recording(again, "vibration")
    assert judge(rec.samples, rec.fs_hz, default_settings(), spindle_rpm=n,
                 flutes=FLUTES).verdict == "stable"


def test_a_microphone_without_a_direction_is_refused_in_one_line(study, tmp_path):
    from robomill.errors import ConfigError

    config, cell = study
    bad = copy.deepcopy(config)
    bad["synth"]["recordings"]["direction"] = [0.0, 0.0, 0.0]
    with pytest.raises(ConfigError, match=r"synth\.recordings\.direction.*non-zero"):
        simulate_file(bad, _cut(bad, id="design"), tmp_path / "x.wav", "sound",
                      simulate_cut(cell, _cut(bad, id="design"), bad), cell=cell)
    assert not (tmp_path / "x.wav").exists()
