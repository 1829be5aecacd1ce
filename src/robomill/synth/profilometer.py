"""Stylus profilometer: ``profiles/<cut>.csv`` (``x_mm, z_um``), one trace per cut.

The stylus is dragged along the slot floor in the feed direction, ``n_samples`` samples at
``fs_per_mm`` (thesis: 12 000 samples at 800 mm⁻¹, 15 mm), starting ``start_mm`` into the
cut. The simulated height is the sum of

* **waviness** — the tool path's deviation normal to the slot floor produced by the cell's
  eccentric gears (:meth:`VirtualCell.joint_error_rad`) along that cut's joint path (inverse
  kinematics): the base-Z component of the TCP error through the Jacobian
  (:meth:`VirtualCell.tcp_error_mm`), plus the *joint-1 axis wobble*: a gear-mesh error of
  joint 1 comes with a tilt of its axis (the mesh force on the eccentric pinion tilts the
  joint-1 bearing), ``joint1_wobble_ratio`` radians of tilt per radian of transmission
  error, which moves the TCP vertically by ``ratio · Δq₁ · r`` (``r`` its horizontal distance
  from axis 1). The rigid model alone moves the TCP vertically only for X cuts (joints 2, 3,
  5 turn, the cut is radial in the assumed layout); Y cuts turn joint 1 (a vertical axis),
  whose error is horizontal except through this wobble. The spatial frequencies come from
  the joint positions, so they do not change with feed (near 0.4–0.5 mm⁻¹, 2–2.5 mm).
  The *level* of the waviness at the floor is not given by the rigid model: the gear
  meshes' transmission error grows with the load they carry (loaded transmission error:
  mesh-stiffness variation × torque), and the cutting load — hence the torque on each joint —
  depends on the cut direction and grows with the feed until the flanks are fully loaded.
  This is modelled by scaling the kinematic shape to a segment-method RMS of
  ``level_um · (1 − exp(−v / v0_mm_s))`` per direction (``waviness.<dir>``, assumed values
  chosen to land near thesis Table 2.1: X smallest, +Y largest, growing with feed);
* **roughness marks** — the tool's vertical vibration in the cut itself
  (:func:`robomill.synth.process.simulate_cut`: the structure at the cut's pose shaken by the
  closed-loop cutting force, the same cut the dynamometer records, stored once by
  :mod:`robomill.synth.cutstate`), over the trace's span, read where the tool
  passed each stylus position (time = position / feed, so the marks of a mode keep their
  temporal frequency and their wavelength scales with feed), low-pass filtered by the stylus
  tip (cut-off wavelength ``stylus_lambda_s_mm``) and its shape scaled to a segment-method
  RMS (0.25 mm segments) of
  ``level_um · (1 + (v / knee_mm_s)^exponent)`` per direction (``roughness.<dir>``: the
  broadband excitation grows with chip load and, above a knee feed, fast as the process
  approaches its stability limit; assumed values near thesis Table 2.2);
* **feed marks** — a sinusoid at the feed per tooth ``c = v / (N n)`` of height
  ``feed_mark_um``, attenuated by the stylus' short-wave transmission
  ``exp(−π (α λs / c)²)`` (ISO 3274 tip, ``stylus_lambda_s_mm``);
* **stylus tilt** — a line of slope drawn uniformly in ``tilt_um_per_mm`` and an offset;
* **instrument noise** — white, ``noise_um`` standard deviation.

Every draw comes from ``np.random.default_rng([seed, 1, crc32(cut)])`` sub-streams, so each
file is deterministic alone. :func:`truth` records, per cut, the planted waviness and
roughness RMS by the same segment method as the analysis (the waviness after removing its
best-fit line, which no one can tell from stylus tilt), and the rigid-model waviness RMS.
"""

from __future__ import annotations

import zlib
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from robomill.experiment import DIRECTION_DEG, Cut, cut_process
from robomill.settings import config_section

if TYPE_CHECKING:  # the workflow imports this module to plan the DAG: xarray only when used
    import xarray as xr

INSTRUMENT_NUMBER = 1
"""Stream number of this instrument in the per-file random generators."""

WAVINESS_SEGMENT_MM = 2.5
ROUGHNESS_SEGMENT_MM = 0.25
ROUGHNESS_CUTOFF_MM = 0.8
"""Roughness cut-off wavelength λc of the vibration marks' band (ISO 4288, 0.8 mm)."""
ALPHA = float(np.sqrt(np.log(2.0) / np.pi))



def settings(config: Mapping[str, Any]) -> dict[str, Any]:
    """``synth.profilometer``, the schema's defaults filled
    (:func:`robomill.settings.config_section`)."""
    return config_section(config, "synth.profilometer")


def _cuts(config: Mapping[str, Any]) -> list[Cut]:
    from robomill.io.synthetic_layout import synthetic_cuts

    return synthetic_cuts(config)



def _rng(cell, cut: Cut, stream: int) -> np.random.Generator:
    return np.random.default_rng([cell.seed, INSTRUMENT_NUMBER, zlib.crc32(cut.id.encode()),
                                  stream])


def level_key(levels: Mapping[str, Any], cut: Cut) -> str:
    """The entry of a per-direction level table (``waviness``/``roughness``: px, py, my) that
    a cut takes: its own direction, else the named direction nearest its feed direction
    (assumed: a cut of another direction behaves like the nearest measured one)."""
    if cut.direction in levels:
        return str(cut.direction)
    deg = cut.direction_deg if cut.direction_deg is not None else DIRECTION_DEG[cut.direction]
    return min(levels, key=lambda k: abs((float(deg) - DIRECTION_DEG[k] + 180.0) % 360.0
                                         - 180.0))


def waviness_level_um(p: Mapping[str, Any], cut: Cut) -> float:
    """Planted waviness RMS (2.5 mm segments) of a cut: ``level (1 − exp(−v/v0))``."""
    w = p["waviness"][level_key(p["waviness"], cut)]
    return float(w["level_um"] * (1.0 - np.exp(-cut.feed_mm_s / w["v0_mm_s"])))


def roughness_level_um(p: Mapping[str, Any], cut: Cut) -> float:
    """Planted vibration-mark RMS (0.25 mm segments): ``level (1 + (v/knee)^exponent)``."""
    r = p["roughness"][level_key(p["roughness"], cut)]
    return float(r["level_um"] * (1.0 + (cut.feed_mm_s / r["knee_mm_s"]) ** r["exponent"]))


def x_mm(p: Mapping[str, Any]) -> np.ndarray:
    """Stylus positions [mm] from the start of the trace."""
    return np.arange(int(p["n_samples"])) / float(p["fs_per_mm"])


def trace_end_mm(config: Mapping[str, Any]) -> float:
    """Path abscissa of the trace's last stylus position [mm] (the span of the cut that the
    profile samples)."""
    p = settings(config)
    return float(float(p["start_mm"]) + x_mm(p)[-1])


def kinematic_waviness_um(cell, cut: Cut, p: Mapping[str, Any]) -> np.ndarray:
    """Rigid-model floor deviation [µm] along the trace: base-Z TCP error of the gear errors
    plus the joint-1 axis wobble (see module docstring). Inverse kinematics on a coarse grid
    (``ik_step_mm``), joint angles interpolated by cubic splines (they vary smoothly)."""
    x = x_mm(p)
    s = float(p["start_mm"]) + x
    step = float(p["ik_step_mm"])
    s_coarse = np.arange(s[0], s[-1] + step, step)
    q_coarse = cell.joint_path_rad(cut, s_coarse)
    import scipy.interpolate  # here, not at the top: keeps Snakemake's start-up short
    q = scipy.interpolate.CubicSpline(s_coarse, q_coarse, axis=0)(s)
    e = cell.tcp_error_mm(q)
    dq1 = cell.joint_error_rad(q)[:, 0]
    r_h = np.hypot(*cell.cut_path_mm(cut, s)[:, :2].T)
    return 1e3 * (e[:, 2] + float(p["joint1_wobble_ratio"]) * dq1 * r_h)


def _unit_segment_rms(z: np.ndarray, fs: float, segment_mm: float) -> np.ndarray:
    # imported here, not at the top: keeps Snakemake's start-up short
    from robomill.spectra import segment_rms

    rms = segment_rms(z, fs, segment_mm)
    return z / rms if rms > 0 else z


def floor_vibration_um(cell, cut: Cut, p: Mapping[str, Any], sim) -> np.ndarray:
    """The tool's vertical vibration [µm] (deflection, base Z) where the tool passed each
    stylus position, in the roughness band: band-pass filtered (2nd-order Butterworth, zero
    phase) between the roughness cut-off wavelength λc = 0.8 mm (ISO 4288; the slow static
    deflection changes along the cut belong to the waviness) and the stylus tip's
    ``stylus_lambda_s_mm``, at ``feed / λc`` to ``feed / λs`` Hz; ``sim`` the simulated cut
    (:class:`robomill.synth.process.SimulatedCut`), whose span up to the trace's end is
    filtered."""
    import scipy.signal

    s_mm = float(p["start_mm"]) + x_mm(p)
    sim = sim.span(float(s_mm[-1]))
    z = sim.deflection_m[:, 2] - sim.deflection_m[:, 2].mean()
    f_hi = min(cut.feed_mm_s / float(p["stylus_lambda_s_mm"]), 0.45 * sim.fs_hz)
    f_lo = cut.feed_mm_s / ROUGHNESS_CUTOFF_MM
    sos = scipy.signal.butter(2, [f_lo, f_hi], btype="bandpass", fs=sim.fs_hz, output="sos")
    z = scipy.signal.sosfiltfilt(sos, z)
    return 1e6 * np.interp(s_mm / cut.feed_mm_s, sim.t_s, z)


def feed_mark_height_um(cell, cut: Cut, p: Mapping[str, Any]) -> float:
    """Feed-mark amplitude after the stylus tip [µm]: ``feed_mark_um · exp(−π(α λs / c)²)``."""
    c_mm = cut_process(cut, cell.experiment)["feed_per_tooth_mm"]  # the cut's own speed, flutes
    return float(p["feed_mark_um"]) * float(
        np.exp(-np.pi * (ALPHA * float(p["stylus_lambda_s_mm"]) / c_mm) ** 2))


def roughness_component_um(cell, cut: Cut, p: Mapping[str, Any], sim) -> np.ndarray:
    """Vibration marks + feed marks [µm] (no tilt, no noise) of the simulated cut ``sim``."""
    x = x_mm(p)
    fs = float(p["fs_per_mm"])
    vib = floor_vibration_um(cell, cut, p, sim)
    vib = roughness_level_um(p, cut) * _unit_segment_rms(vib, fs, ROUGHNESS_SEGMENT_MM)
    c_mm = cut_process(cut, cell.experiment)["feed_per_tooth_mm"]
    phase = _rng(cell, cut, 3).uniform(0, 2 * np.pi)
    marks = feed_mark_height_um(cell, cut, p) * np.sin(2 * np.pi * x / c_mm + phase)
    return vib + marks


def components_um(cell, cut: Cut, p: Mapping[str, Any], sim) -> dict[str, np.ndarray]:
    """Every planted component of one trace [µm]: waviness, roughness, tilt, noise (``sim``:
    the simulated cut)."""
    x = x_mm(p)
    fs = float(p["fs_per_mm"])
    import scipy.signal  # here, not at the top: keeps Snakemake's start-up short
    kin = scipy.signal.detrend(kinematic_waviness_um(cell, cut, p))
    waviness = waviness_level_um(p, cut) * _unit_segment_rms(kin, fs, WAVINESS_SEGMENT_MM)
    rng = _rng(cell, cut, 1)
    lo, hi = p["tilt_um_per_mm"]
    tilt = rng.uniform(lo, hi) * x + rng.uniform(-5.0, 5.0)
    noise = _rng(cell, cut, 2).normal(0.0, float(p["noise_um"]), x.size)
    return {"kinematic": kin, "waviness": waviness,
            "roughness": roughness_component_um(cell, cut, p, sim), "tilt": tilt, "noise": noise}


def simulate_profile(config: Mapping[str, Any], cut: Cut, path: str | Path, sim,
                     cell=None) -> Path:
    """Simulate one cut's profile from the simulated cut ``sim`` and write it in the contract
    format (``x_mm, z_um``)."""
    from robomill.synth.cell import cell_from_config

    cell = cell or cell_from_config(config)
    p = settings(config)
    comp = components_um(cell, cut, p, sim)
    z = comp["waviness"] + comp["roughness"] + comp["tilt"] + comp["noise"]
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    pd.DataFrame({"x_mm": x_mm(p), "z_um": z}).to_csv(path, index=False, float_format="%.6f")
    return path


def truth(config: Mapping[str, Any], cell) -> xr.Dataset:
    """Planted truth per cut (dim ``surface_cut``): waviness and roughness RMS by the
    segment method, the rigid-model waviness RMS (before the load/direction scaling) and the
    feed-mark height after the stylus filter."""
    import xarray as xr

    p = settings(config)
    fs = float(p["fs_per_mm"])
    cuts = _cuts(config)
    wav, rough, rigid = [], [], []
    import scipy.signal  # here, not at the top: keeps Snakemake's start-up short

    from robomill.spectra import segment_rms

    for c in cuts:  # the vibration marks' level and the feed marks' RMS, in quadrature
        rough.append(float(np.hypot(roughness_level_um(p, c),
                                    feed_mark_height_um(cell, c, p) / np.sqrt(2.0))))
        wav.append(waviness_level_um(p, c))
        kin = scipy.signal.detrend(kinematic_waviness_um(cell, c, p))
        rigid.append(segment_rms(kin, fs, WAVINESS_SEGMENT_MM))

    def v(data, units, long_name):
        return ("surface_cut", np.asarray(data, float), {"units": units,
                                                         "long_name": long_name})

    return xr.Dataset(
        {
            "surface_planted_waviness_rms_um": v(wav, "um", "planted waviness RMS "
                                                 "(2.5 mm segment method)"),
            "surface_planted_roughness_rms_um": v(rough, "um", "planted roughness RMS "
                                                  "(vibration level (0.25 mm segment method) "
                                                  "and feed marks in quadrature)"),
            "surface_rigid_waviness_rms_um": v(rigid, "um", "rigid-model floor deviation RMS "
                                               "(2.5 mm segments), before load scaling"),
            "surface_feed_mm_s": v([c.feed_mm_s for c in cuts], "mm/s", "feed of the cut"),
        },
        coords={"surface_cut": ("surface_cut", [c.id for c in cuts],
                                {"units": "1", "long_name": "cut of each profile"})},
    )
