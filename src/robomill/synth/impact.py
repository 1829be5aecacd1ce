"""Impact hammer + accelerometer at the tool tip: ``impact/hit<X|Y|Z>_<k>.csv``.

The thesis' impact test (§3.3, Fig 3.18): a force-sensing hammer hits the tool tip along base
X, Y or Z; a triaxial accelerometer beside the tip records the response. ``hits_per_direction``
hits per direction (thesis: 5). Each file holds ``t_s, force_N, ax_ms2, ay_ms2, az_ms2``.

Physics (all from the virtual cell's structure at the test pose: the robot's modes there,
:attr:`VirtualCell.modes`, and the spindle's and tool's, :func:`test_modes`):

* hammer pulse: a half-sine of contact time ``pulse_duration_s`` (a hard tip: 1–3 ms, whose
  force spectrum is flat to within 3 dB up to ≈ 0.6/T ≈ 300 Hz),
  ``F(t) = F₀ sin(π (t − t₀)/T)`` for ``t₀ ≤ t ≤ t₀ + T``, F₀ drawn around ``force_peak_N``;
* acceleration of each mode r driven by the modal force φ_rᵀF:
  ``a = φ_r s²/(m_r (s² + 2ζ_r ω_r s + ω_r²)) φ_rᵀ F``, discretized exactly for a
  piecewise-linear force (first-order hold, :func:`scipy.signal.cont2discrete`), so that the
  sampled force and acceleration are exactly consistent with the continuous modal model;
* white noise on every channel; a channel saturates at its range (force or accelerometer).

Planted defects (seeded, per file, independent of job order): with probability
``double_hit_probability`` the hammer bounces and hits again ``double_hit_delay_s`` later with
a fraction ``double_hit_ratio`` of the first peak; with probability ``overload_probability``
the operator hits ``overload_factor`` times too hard and the accelerometer clips at its range.
:func:`planted_defect` decides, :func:`truth` records every planted defect.
"""

from __future__ import annotations

import zlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill.io.synthetic_layout import IMPACT_DIRECTIONS, hit_path, instrument_files

DIRECTIONS = IMPACT_DIRECTIONS
"""Hit directions (base axes)."""
INSTRUMENT_NUMBER = 6
"""Stream number of this instrument in the per-file random generators."""
COLUMNS = ("t_s", "force_N", "ax_ms2", "ay_ms2", "az_ms2")
"""Columns of an impact file (``docs/data-contract.md``)."""



def _rng(seed: int, direction: str, hit: int) -> np.random.Generator:
    return np.random.default_rng([int(seed), INSTRUMENT_NUMBER,
                                  zlib.crc32(hit_path(direction, hit).encode())])


def planted_defect(config: Mapping[str, Any], direction: str, hit: int) -> str:
    """The defect planted in one hit: ``none``, ``double_hit`` or ``overload`` (seeded)."""
    imp = config["synth"]["impact"]
    p_double = float(imp["double_hit_probability"])
    p_over = float(imp["overload_probability"])
    u = _rng(config["synth"]["seed"], direction, hit).uniform()
    if u < p_double:
        return "double_hit"
    if u < p_double + p_over:
        return "overload"
    return "none"


def half_sine_pulse(t_s: np.ndarray, t0_s: float, duration_s: float,
                    peak_N: float) -> np.ndarray:
    """Hammer force ``F₀ sin(π (t − t₀)/T)`` on ``[t₀, t₀ + T]``, zero elsewhere."""
    tau = (np.asarray(t_s, float) - t0_s) / duration_s
    return np.where((tau >= 0) & (tau <= 1), peak_N * np.sin(np.pi * np.clip(tau, 0, 1)), 0.0)


def modal_acceleration_ms2(modes, force_N: np.ndarray, fs_hz: float) -> np.ndarray:
    """Tool-tip acceleration ``(n, 3)`` [m/s²] of the modal model under a force ``(n, 3)`` [N].

    Per mode: ``A_r(s) = s² / (m_r (s² + 2ζ_r ω_r s + ω_r²))`` on the modal force φ_rᵀF,
    discretized with a first-order hold (exact for a force linear between samples); the
    acceleration is ``Σ_r φ_r a_r``. ``modes`` are :class:`robomill.synth.cell.Mode`.
    """
    force = np.asarray(force_N, float)
    acc = np.zeros_like(force)
    import scipy.signal  # here, not at the top: keeps Snakemake's start-up short

    for m in modes:
        wn = 2 * np.pi * m.f_hz
        num, den = [1.0 / m.m_kg, 0.0, 0.0], [1.0, 2 * m.zeta * wn, wn**2]
        b, a, _ = scipy.signal.cont2discrete((num, den), 1.0 / fs_hz, method="foh")
        phi = np.asarray(m.shape, float)
        acc += np.outer(scipy.signal.lfilter(np.ravel(b), a, force @ phi), phi)
    return acc


def test_modes(cell, fs_hz: float) -> list:
    """The structure's modes at the test pose (:func:`robomill.synth.structure.modes_at` at
    the cell's reference pose) that the acquisition passes: those below 0.4 × ``fs_hz`` (the
    analyzer's anti-alias filter removes the response of the others, which the hammer's
    pulse hardly excites either)."""
    from robomill.synth.structure import modes_at

    q = cell.q_reference_rad if cell.q_reference_rad is not None else cell.q_home_rad
    return [m for m in modes_at(cell, q) if m.f_hz < 0.4 * float(fs_hz)]


def simulate_hit(config: Mapping[str, Any], cell, direction: str, hit: int) -> pd.DataFrame:
    """One hit's record (columns :data:`COLUMNS`), defect as :func:`planted_defect` says."""
    imp = config["synth"]["impact"]
    rng = _rng(config["synth"]["seed"], direction, hit)
    rng.uniform()  # the draw used by planted_defect
    defect = planted_defect(config, direction, hit)
    fs = float(imp["fs_hz"])
    n = int(round(float(imp["duration_s"]) * fs))
    t = np.arange(n) / fs
    t0 = float(imp["pretrigger_s"]) + rng.uniform(0.0, 2.0 / fs)  # trigger jitter
    width = float(imp["pulse_duration_s"]) * rng.uniform(0.9, 1.1)
    peak = float(imp["force_peak_N"]) * (1.0 + float(imp["force_peak_spread"])
                                         * rng.standard_normal())
    delay = rng.uniform(*imp["double_hit_delay_s"])
    ratio = rng.uniform(*imp["double_hit_ratio"])
    if defect == "overload":
        peak *= float(imp["overload_factor"])
    f = half_sine_pulse(t, t0, width, peak)
    if defect == "double_hit":
        f = f + half_sine_pulse(t, t0 + width + delay, width, ratio * peak)
    force = np.zeros((n, 3))
    force[:, DIRECTIONS.index(direction)] = f
    acc = modal_acceleration_ms2(test_modes(cell, fs), force, fs)
    f_meas = f + rng.normal(0.0, float(imp["force_noise_N"]), n)
    acc = acc + rng.normal(0.0, float(imp["accel_noise_ms2"]), (n, 3))
    f_meas = np.clip(f_meas, -float(imp["force_range_N"]), float(imp["force_range_N"]))
    acc = np.clip(acc, -float(imp["accel_range_ms2"]), float(imp["accel_range_ms2"]))
    return pd.DataFrame({"t_s": t, "force_N": f_meas, "ax_ms2": acc[:, 0],
                         "ay_ms2": acc[:, 1], "az_ms2": acc[:, 2]})


def write_hit(config: Mapping[str, Any], cell, direction: str, hit: int,
              path: str | Path) -> Path:
    """Simulate one hit and write it as CSV (atomically)."""
    from robomill.io.atomic import atomic_path

    df = simulate_hit(config, cell, direction, hit)
    with atomic_path(path) as tmp:
        df.to_csv(tmp, index=False, float_format="%.9g")
    return Path(path)


def truth(config: Mapping[str, Any], cell) -> xr.Dataset:
    """Planted impact-test truth: the defect of every hit (``impact_defect``)."""
    if "impact" not in config["synth"]:
        return xr.Dataset()
    files = instrument_files(config, "impact")
    defects = [planted_defect(config, f["direction"], f["hit"]) for f in files]
    return xr.Dataset(
        {"impact_defect": ("impact_file", np.array(defects, dtype=object),
                           {"units": "1", "long_name": "planted defect of the hit "
                                                       "(none, double_hit, overload)"}),
         "impact_direction": ("impact_file", np.array([f["direction"] for f in files],
                                                      dtype=object),
                              {"units": "1", "long_name": "hit direction (base axis)"}),
         "impact_hit": ("impact_file", np.array([f["hit"] for f in files]),
                        {"units": "1", "long_name": "hit number"})},
        coords={"impact_file": ("impact_file", [f["path"] for f in files],
                                {"units": "1", "long_name": "impact file (raw path)"})})


def structure_hit(modes, dofs, reference, responses, *, fs_hz: float, n: int,
                  rng: np.random.Generator, t0_s: float = 0.05, pulse_s: float = 0.002,
                  peak_N: float = 100.0, force_noise_N: float = 0.0,
                  accel_noise_ms2: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """One hit on a multi-node structure (the known truth of the layout tests).

    ``modes`` are :class:`robomill.synth.cell.Mode` whose ``shape`` spans the degrees of
    freedom ``dofs`` (``(node, axis code)`` with positive axes); the hammer hits
    ``reference`` (``(node, ±axis)``) with a half-sine pulse (:func:`half_sine_pulse`) and the
    accelerations at ``responses`` (``(node, ±axis)``) follow from
    :func:`modal_acceleration_ms2`. A negative direction flips the sign of the force or the
    measured acceleration.

    Returns
    -------
    force_N (n,), accel_ms2 (n, len(responses))
    """
    dofs = [tuple(d) for d in dofs]
    t = np.arange(n) / fs_hz
    f = half_sine_pulse(t, t0_s + rng.uniform(0, 2 / fs_hz), pulse_s * rng.uniform(0.9, 1.1),
                        peak_N * rng.uniform(0.8, 1.2))
    force = np.zeros((n, len(dofs)))
    force[:, dofs.index((reference[0], abs(reference[1])))] = np.sign(reference[1]) * f
    acc = modal_acceleration_ms2(modes, force, fs_hz)
    cols = [np.sign(d) * acc[:, dofs.index((node, abs(d)))] for node, d in responses]
    out = np.column_stack(cols) + rng.normal(0.0, accel_noise_ms2, (n, len(responses)))
    return f + rng.normal(0.0, force_noise_N, n), out
