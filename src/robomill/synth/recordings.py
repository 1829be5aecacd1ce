"""A microphone and a spindle accelerometer: ``sound/<cut>.wav`` and ``vibration/<cut>.csv``,
two more instruments on the same simulated cut as the dynamometer
(:func:`robomill.synth.process.simulate_cut`, stored once by :mod:`robomill.synth.cutstate`),
over the same span (the dynamometer's
``record_length_mm``). Off by default (``synth.recordings.sound`` / ``vibration``); every
parameter below is config ``synth.recordings`` and *assumed* (no source gives them).

**Accelerometer** (triaxial, on the spindle at the tool, base axes): it rides on the
structure, so it measures the acceleration of the tool's structural displacement d(t) (the
robot's modes at the cut's pose and the spindle's and tool's modes, static deflection
included, which the derivative removes), as the central second difference at the
simulation's rate f_s,

.. math:: a[n] = f_s^2 \\, (d[n+1] - 2 d[n] + d[n-1])

(gain ``(2 f_s \\sin(π f/f_s))² / (2π f)²`` of the exact ``d̈``: 2 % low at 2 kHz and 25 kHz),
plus white noise ``accel_noise_m_s2`` per axis, resampled to ``accel_fs_hz`` (polyphase,
:func:`scipy.signal.resample_poly`). The gear trains' path error (micrometres over tenths of a
second: micro-g) and the accelerometer's own mass and resonance are left out.

**Microphone** at ``distance_m`` r from the tool in the direction u (``direction``): the
vibrating spindle, tool and block radiate as a small piston of area S (``radiating_area_m2``)
in a baffle, whose far-field pressure at low ka is proportional to its acceleration
[Kinsler 2000, §7.4],

.. math:: p(t) = \\frac{ρ_0 S}{2π r} \\, u \\cdot a(t - r/c)
          + A_s \\sin(2π n t / 60 + φ) + p_n(t)

with ρ₀ ``air_density_kg_m3``, c ``speed_of_sound_m_s``, A_s the spindle's tone at its
rotation frequency (``spindle_tone_Pa``: the rotor's residual imbalance) and p_n the shop's
ambient noise (white, ``ambient_noise_Pa``); the sum passes the microphone's low cut (first
order high-pass at ``highpass_hz``) and is sampled at ``sound_fs_hz``, then written as a
24-bit WAV whose full scale is ``full_scale_Pa`` (louder samples clip, as a recorder does).
The simulation holds no content above its Nyquist frequency (12.5 kHz at 25 kHz): the
recording has none either.

Each file's noise is seeded per cut (``[seed, 8, crc32(cut)]`` and ``[seed, 9, …]``).

**Air pass** (``synth.recordings.air_pass``, :func:`simulate_air_pass_file`): each recorded cut
is recorded a second time by the same instrument while the robot moves along the same path
without material (:func:`robomill.synth.process.simulate_cut` with ``cutting=False``, the
``air`` pass of the cut's stored state: the servo excitation and the gear trains' path error
remain, no chip, no cutting force), as a lab
records an air cut to tell forced vibration from chatter; ``sound/<cut>_air.wav``,
``vibration/<cut>_air.csv``, manifest ``pass: air``. Its noise is seeded apart
(``[seed, 8 or 9, crc32(cut), 1]``); the spindle turns, so the microphone hears its tone.

Reference: Kinsler, L. E.; Frey, A. R.; Coppens, A. B.; Sanders, J. V. *Fundamentals of
Acoustics*, 4th ed. Wiley, New York, 2000 (§7.4, radiation from a baffled circular piston:
at ka ≪ 1 the far-field pressure is ρ₀ S times the piston's acceleration over 2π r).
"""

from __future__ import annotations

import zlib
from collections.abc import Mapping
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from robomill.settings import config_section

SOUND_NUMBER, VIBRATION_NUMBER = 8, 9
"""Stream numbers of the microphone and the accelerometer in per-file random generators."""


def settings(config: Mapping[str, Any]) -> dict[str, Any]:
    """``synth.recordings``, the schema's defaults filled."""
    return config_section(config, "synth.recordings")


def _resample(x: np.ndarray, fs_in_hz: float, fs_out_hz: float) -> np.ndarray:
    """``x`` (along axis 0) from ``fs_in_hz`` to ``fs_out_hz`` (polyphase FIR)."""
    import scipy.signal

    ratio = Fraction(fs_out_hz / fs_in_hz).limit_denominator(1000)
    if ratio == 1:
        return np.array(x, float)
    return scipy.signal.resample_poly(x, ratio.numerator, ratio.denominator, axis=0,
                                      padtype="line")


def tool_acceleration_m_s2(sim) -> np.ndarray:
    """The tool's structural acceleration ``(n, 3)`` [m/s², base axes] at the simulation's
    rate: the central second difference of its displacement (module docstring; the end
    samples repeat their neighbours)."""
    d = sim.deflection_m @ sim.frame.T
    a = np.empty_like(d)
    a[1:-1] = (d[2:] - 2.0 * d[1:-1] + d[:-2]) * sim.fs_hz ** 2
    a[0], a[-1] = a[1], a[-2]
    return a


def _record(cut, config: Mapping[str, Any], sim):
    """The simulated cut (or its air pass) ``sim`` over the dynamometer's span and that span's
    sample count."""
    from robomill.synth.dynamometer import record_length_mm

    length = record_length_mm(config)
    sim = sim.span(length)
    n = min(int(round(length / cut.feed_mm_s * sim.fs_hz)), sim.t_s.size)
    return sim, n


def _rng(cell, cut, number: int, cutting: bool = True) -> np.random.Generator:
    key = [cell.seed, number, zlib.crc32(cut.id.encode())]
    return np.random.default_rng(key if cutting else [*key, 1])


def simulate_vibration(cell, cut, config: Mapping[str, Any], sim, *, cutting: bool = True
                       ) -> tuple[np.ndarray, float]:
    """The accelerometer's record of one cut (``cutting=False``: of its air pass):
    ``(a (m, 3) [m/s², base axes], fs_hz)``; ``sim`` the simulated cut, or its air pass
    (:class:`robomill.synth.process.SimulatedCut`)."""
    s = settings(config)
    sim, n = _record(cut, config, sim)
    a = tool_acceleration_m_s2(sim)[:n]
    a = a + _rng(cell, cut, VIBRATION_NUMBER, cutting).normal(0.0, float(s["accel_noise_m_s2"]),
                                                     a.shape)
    fs = float(s["accel_fs_hz"])
    return _resample(a, sim.fs_hz, fs), fs


def simulate_sound(cell, cut, config: Mapping[str, Any], sim, *, cutting: bool = True
                   ) -> tuple[np.ndarray, float]:
    """The microphone's record of one cut (``cutting=False``: of its air pass):
    ``(p (m,) [Pa], fs_hz)`` (module docstring; ``sim`` the simulated cut, or its air
    pass)."""
    import scipy.signal

    from robomill.experiment import cut_process

    s = settings(config)
    sim, n = _record(cut, config, sim)
    u = np.asarray(s["direction"], float)
    if not np.linalg.norm(u) > 0:
        from robomill.errors import ConfigError

        raise ConfigError(f"config key 'synth.recordings.direction': {list(u)} has no "
                          "direction (expected a non-zero vector, base axes)")
    u = u / np.linalg.norm(u)
    r = float(s["distance_m"])
    gain = float(s["air_density_kg_m3"]) * float(s["radiating_area_m2"]) / (2 * np.pi * r)
    fs = float(s["sound_fs_hz"])
    p = _resample(gain * (tool_acceleration_m_s2(sim)[:n] @ u), sim.fs_hz, fs)
    lag = int(round(r / float(s["speed_of_sound_m_s"]) * fs))  # the sound's travel time
    if lag:
        p = np.concatenate([np.full(lag, p[0]), p[:-lag]])
    rng = _rng(cell, cut, SOUND_NUMBER, cutting)
    t = np.arange(p.size) / fs
    rpm = float(cut_process(cut, cell.experiment)["spindle_rpm"])
    p = p + float(s["spindle_tone_Pa"]) * np.sin(2 * np.pi * rpm / 60.0 * t
                                                   + rng.uniform(0, 2 * np.pi))
    p = p + rng.normal(0.0, float(s["ambient_noise_Pa"]), p.size)
    if float(s["highpass_hz"]) > 0:
        sos = scipy.signal.butter(1, float(s["highpass_hz"]), "highpass", fs=fs, output="sos")
        p = scipy.signal.sosfilt(sos, p - p[0])
    return p, fs


def simulate_air_pass_file(config: Mapping[str, Any], cut, path: str | Path, kind: str,
                           air, cell=None) -> Path:
    """The air pass of one cut (the same path without material; module docstring) as the
    instrument ``kind`` records it, written as :func:`simulate_file` writes the cut's own;
    ``air`` the simulated air pass (the cut state's ``air`` pass,
    :func:`robomill.synth.cutstate.read_cut_state`)."""
    return simulate_file(config, cut, path, kind, air, cell=cell, cutting=False)


def simulate_file(config: Mapping[str, Any], cut, path: str | Path, kind: str, sim,
                  cell=None, *, cutting: bool = True) -> Path:
    """Simulate one cut's recording of ``kind`` (``sound``: a 24-bit WAV scaled to
    ``full_scale_Pa``; ``vibration``: CSV ``t_s, ax_m_s2, ay_m_s2, az_m_s2``) from the
    simulated cut ``sim`` into ``path`` (``cutting=False``: its air pass, ``sim`` the air
    pass, :func:`simulate_air_pass_file`); returns ``path``."""
    from robomill.io.atomic import atomic_path
    from robomill.synth.cell import cell_from_config

    cell = cell or cell_from_config(config)
    path = Path(path)
    with atomic_path(path) as tmp:
        if kind == "sound":
            import soundfile

            p, fs = simulate_sound(cell, cut, config, sim, cutting=cutting)
            full = float(settings(config)["full_scale_Pa"])
            soundfile.write(str(tmp), np.clip(p / full, -1.0, 1.0), int(round(fs)),
                            subtype="PCM_24", format="WAV")
        elif kind == "vibration":
            import pandas as pd

            a, fs = simulate_vibration(cell, cut, config, sim, cutting=cutting)
            pd.DataFrame({"t_s": np.arange(a.shape[0]) / fs, "ax_m_s2": a[:, 0],
                          "ay_m_s2": a[:, 1], "az_m_s2": a[:, 2]}).to_csv(
                tmp, index=False, float_format="%.9g")
        else:
            raise ValueError(f"unknown recording kind {kind!r} (sound or vibration)")
    return path
