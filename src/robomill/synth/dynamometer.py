"""Kistler dynamometer: ``forces/<cut>.h5`` (or ``.csv``) with ``t_s, Fx_N, Fy_N, Fz_N``.

The simulated record of one cut is the mechanistic milling force (thesis eq. 3.1,
:func:`robomill.forces.model.slot_forces`, coefficients ``synth.cutting``) of the virtual cell, with
the cut's own chip model: a slot, or partial immersion in up or down milling (the teeth engage
between the entry and exit angles of :func:`robomill.forces.model.engagement_angles_rad` from the
cut's ``radial_immersion`` a_e/D and ``milling``; Altintas 2012, §2.2), modulated by the cell
itself:

- **tool-tip vibration** from the cell's modal model (:meth:`VirtualCell.random_vibration_m`,
  the same modes the impact test sees), driven by the broadband part of the cutting force (a
  white force whose standard deviation is ``excitation_ratio`` × the cut's mean resultant
  force). The vibration changes the chip load through the regenerative chip thickness
  ``h = (c + Δx) sin φ + Δy cos φ`` with ``Δ = d(t) − d(t − T_tooth)`` (displacement along /
  across the feed over one tooth period), and the axial depth ``a = a₀ − d_z(t)``;
- **path error** of the gear trains (:meth:`VirtualCell.joint_path_rad` +
  :meth:`VirtualCell.tcp_error_mm`, the same eccentric gears as the surface and the tracker
  see), entering the same way (its mean over the cut is removed: the tool frame is calibrated
  to R0 before cutting, thesis §2.1);
- **dynamometer dynamics**: a second-order low-pass per axis, unit static gain, natural
  frequency ``dynamometer_f_n_hz`` and damping ``dynamometer_zeta`` (*assumed*: chosen so that
  the tooth-passing harmonics near it dominate the full-band spectrum above 10 kHz as in thesis
  Fig 3.4; a Kistler 9255B alone is stiffer, the block and clamping lower it);
- **acquisition anti-alias filter**: the force's periodic shape is band-limited to spindle
  harmonics below ``anti_alias_fraction`` × fs (:func:`robomill.forces.model.slot_force_tables`);
  without it the edge-force jumps alias tooth-passing harmonics into the 0–250 Hz band;
- **noise**: white, ``noise_N`` standard deviation per axis (charge amplifier, *assumed*).

The slow quantities (vibration, path error, chip load, depth) are simulated at
``vibration_fs_hz`` for the whole cut (the modes are below 100 Hz), then interpolated into
each ``chunk_samples`` block of the full-rate record; the full-rate record is produced and
written block by block and is never held whole. Forces are on the tool in R0 axes (see
``docs/data-contract.md``).
"""

from __future__ import annotations

import zlib
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from robomill.settings import config_section

INSTRUMENT_NUMBER = 2
"""Stream number of this instrument in per-file random generators."""



def settings(config: Mapping[str, Any]) -> dict[str, Any]:
    """``synth.dynamometer``, the schema's defaults filled
    (:func:`robomill.settings.config_section`)."""
    return config_section(config, "synth.dynamometer")



def truth(config: Mapping[str, Any], cell) -> Any:
    """Planted dynamometer parameters for ``truth.nc``."""
    import xarray as xr

    s = settings(config)
    return xr.Dataset({
        "dynamometer_f_n_hz": ((), float(s["dynamometer_f_n_hz"]),
                               {"units": "Hz", "long_name": "dynamometer natural frequency"}),
        "dynamometer_zeta": ((), float(s["dynamometer_zeta"]),
                             {"units": "1", "long_name": "dynamometer damping ratio"}),
        "dynamometer_noise_N": ((), float(s["noise_N"]),
                                {"units": "N", "long_name": "dynamometer noise std per axis"}),
    })


def record_length_mm(config: Mapping[str, Any]) -> float:
    """Length of the cut the dynamometer records [mm] (``record_length_mm`` or the cut)."""
    s = settings(config)
    return float(s["record_length_mm"] or config["experiment"]["cut_length_mm"])


def _dynamometer_filter(f_n_hz: float, zeta: float, fs_hz: float):
    """Bilinear (prewarped at f_n) 2nd-order low-pass ω²/(s² + 2ζωs + ω²), unit DC gain."""
    import scipy.signal

    wn = 2 * np.pi * f_n_hz
    if f_n_hz >= fs_hz / 2:
        raise ValueError(f"dynamometer_f_n_hz {f_n_hz} must be below Nyquist {fs_hz / 2}")
    g = 2 * fs_hz * np.tan(wn / (2 * fs_hz)) / wn
    return scipy.signal.bilinear([(wn * g) ** 2], [1.0, 2 * zeta * wn * g, (wn * g) ** 2],
                                 fs=fs_hz)


def slow_channels(cell, cut, config: Mapping[str, Any], rng: np.random.Generator
                  ) -> dict[str, np.ndarray]:
    """Chip load and depth at ``vibration_fs_hz`` over the whole record.

    Returns ``t_s``, ``c_feed_mm``, ``c_cross_mm``, ``depth_mm`` (slow grid) and the
    displacement components for inspection (``vib_mm``, ``path_mm``, cut frame).
    """
    from scipy.interpolate import CubicSpline

    from robomill.experiment import (
        cut_process,
        feed_direction,
        feed_per_tooth_mm,
        tooth_passing_hz,
    )
    from robomill.forces.model import (
        CuttingCoefficients,
        cut_frame,
        engagement_angles_rad,
        mean_milling_forces,
        mean_slot_forces,
    )

    s = settings(config)
    exp = cell.experiment
    proc = cut_process(cut, exp)  # the cut's own speed and flutes (else the experiment's)
    flutes, rpm = int(proc["flutes"]), float(proc["spindle_rpm"])
    L = record_length_mm(config)
    v = cut.feed_mm_s
    duration = L / v
    fs_v = float(s["vibration_fs_hz"])
    n_v = int(np.ceil(duration * fs_v)) + 2
    t_v = np.arange(n_v) / fs_v
    R = cut_frame(feed_direction(cut))
    c0 = feed_per_tooth_mm(v, rpm, flutes)
    coeffs = CuttingCoefficients.from_mapping(cell.cutting)
    # gear path error along the recorded length, mean removed, cut frame [mm]
    s_ik = np.linspace(0.0, L, int(s["ik_points"]))
    spline = CubicSpline(s_ik, cell.joint_path_rad(cut, s_ik), axis=0)
    s_fine = np.arange(0.0, L + s["path_step_mm"], s["path_step_mm"])
    e = cell.tcp_error_mm(spline(s_fine))
    e -= e.mean(axis=0)
    path = np.column_stack([np.interp(np.clip(v * t_v, 0, L), s_fine, e[:, k])
                            for k in range(3)]) @ R
    # tool-tip vibration of the cell's modes [mm], cut frame
    st, ex = engagement_angles_rad(proc["radial_immersion"], proc["milling"])
    f_mean = np.linalg.norm(
        mean_slot_forces(c0, cut.depth_mm, coeffs, flutes=flutes) if proc["milling"] == "slot"
        else mean_milling_forces(c0, cut.depth_mm, coeffs, flutes=flutes, entry_rad=st,
                                 exit_rad=ex))
    vib = cell.random_vibration_m(n_v, fs_v, float(s["excitation_ratio"]) * f_mean, rng)
    vib = (vib * 1e3) @ R
    d = vib + path
    T = 1.0 / tooth_passing_hz(rpm, flutes)
    d_prev = np.column_stack([np.interp(t_v - T, t_v, d[:, k]) for k in range(3)])
    return {"t_s": t_v, "c_feed_mm": c0 + d[:, 0] - d_prev[:, 0],
            "c_cross_mm": d[:, 1] - d_prev[:, 1], "depth_mm": cut.depth_mm - d[:, 2],
            "vib_mm": vib, "path_mm": path}


def simulate_blocks(cell, cut, config: Mapping[str, Any]
                    ) -> tuple[int, float, Iterator[tuple[np.ndarray, np.ndarray]]]:
    """The record of one cut as ``(n_samples, fs_hz, blocks)``; ``blocks`` yields
    ``(t_s, force_N (n, 3))`` of at most ``chunk_samples`` samples (R0 axes, on the tool)."""
    import scipy.signal

    from robomill.experiment import cut_process, feed_direction
    from robomill.forces.model import (
        CuttingCoefficients,
        cut_frame,
        engagement_angles_rad,
        slot_force_tables,
        slot_forces_band_limited,
    )

    s = settings(config)
    rng = np.random.default_rng([cell.seed, INSTRUMENT_NUMBER, zlib.crc32(cut.id.encode())])
    fs = float(s["fs_hz"])
    exp = cell.experiment
    proc = cut_process(cut, exp)
    flutes, spindle_hz = int(proc["flutes"]), float(proc["spindle_rpm"]) / 60.0
    n = int(round(record_length_mm(config) / cut.feed_mm_s * fs))
    phase0 = float(rng.uniform(0, 2 * np.pi))
    slow = slow_channels(cell, cut, config, rng)
    R = cut_frame(feed_direction(cut))
    coeffs = CuttingCoefficients.from_mapping(cell.cutting)
    b, a = _dynamometer_filter(float(s["dynamometer_f_n_hz"]), float(s["dynamometer_zeta"]), fs)
    st, ex = engagement_angles_rad(proc["radial_immersion"], proc["milling"])
    tables = slot_force_tables(flutes, int(s["anti_alias_fraction"] * fs / spindle_hz),
                               entry_rad=st, exit_rad=ex)
    chunk = int(s["chunk_samples"])
    noise = float(s["noise_N"])

    def blocks():
        zi = None
        for i0 in range(0, n, chunk):
            t = np.arange(i0, min(i0 + chunk, n)) / fs
            cx = np.interp(t, slow["t_s"], slow["c_feed_mm"])
            cy = np.interp(t, slow["t_s"], slow["c_cross_mm"])
            depth = np.interp(t, slow["t_s"], slow["depth_mm"])
            F = slot_forces_band_limited(2 * np.pi * spindle_hz * t + phase0, cx, depth,
                                         coeffs, tables, cross_feed_mm=cy) @ R.T
            if zi is None:  # start at rest under the first (static) force
                zi = scipy.signal.lfilter_zi(b, a)[:, None] * F[0][None, :]
            F, zi = scipy.signal.lfilter(b, a, F, axis=0, zi=zi)
            F += rng.normal(0.0, noise, size=F.shape)
            yield t, F

    return n, fs, blocks()


def simulate_file(config: Mapping[str, Any], cut, path: str | Path, cell=None,
                  progress=None) -> Path:
    """Simulate one cut's record and write it to ``path`` (``.h5`` or ``.csv``) block by
    block; ``progress(fraction)`` is called after each block."""
    from robomill.io.atomic import atomic_path
    from robomill.io.forces import write_forces_csv, write_forces_h5
    from robomill.synth.cell import cell_from_config

    cell = cell or cell_from_config(config)
    n, fs, blocks = simulate_blocks(cell, cut, config)
    if progress is not None:
        inner = blocks

        def reporting():
            done = 0
            for t, F in inner:
                yield t, F
                done += len(t)
                progress(done / n)

        blocks = reporting()
    path = Path(path)
    with atomic_path(path) as tmp:
        if path.suffix == ".csv":
            write_forces_csv(tmp, blocks)
        else:
            write_forces_h5(tmp, n, fs, blocks, dtype=settings(config)["dtype"])
    return path
