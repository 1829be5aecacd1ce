"""FARO laser tracker: tracker/<dir>_f<feed>.csv (t_s, x_mm, y_mm, z_mm).

The robot moves along the path of a cut at that cut's feed while the tracker samples its
target at 815 Hz (thesis §3.2): a *loaded* pass is the cut itself
(:func:`robomill.synth.process.simulate_cut`, the same cut the dynamometer and the
profilometer see, stored once by :mod:`robomill.synth.cutstate`), an *air* pass the same
path without material (:func:`simulate_run` with ``pass_="air"``; deflection is the loaded
path minus the air path). For every direction and every feed of the experiment one run is
simulated, along the path of the last cut (in machining order) with that direction and feed
(so the feeds 2–10 mm/s follow set 3, as in thesis Figs 3.12–3.15). Coordinates are in the
robot base frame (the tracker registered to the robot, the target's offset to the TCP
removed).

Simulated position = nominal motion (trapezoidal speed profile: constant feed, ramps at
``accel_mm_s2``) + the TCP error of every eccentric gear stage of the virtual cell (joint
error through the Jacobian, :meth:`VirtualCell.tcp_error_mm`) + on a loaded pass the tool's
static and dynamic deflection in the cut where the tool is (path abscissa s; low-pass filtered
at 0.4 × the tracker's rate, the tracker's own averaging) + a servo ripple at a constant
``ripple_hz`` (13 Hz) along a fixed direction + white tracker noise (``noise_std_um`` per
axis). Configuration: ``config.yaml: synth.tracker`` (schema
``src/robomill/data/schemas/config/synth_tracker.schema.yaml``).
"""

from __future__ import annotations

import zlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill.experiment import Cut, tracker_run_id
from robomill.io.synthetic_layout import tracker_runs
from robomill.settings import config_section

INSTRUMENT_NUMBER = 3
"""Stream number of this instrument in the per-file random generators."""



def settings(config: Mapping[str, Any]) -> dict[str, Any]:
    """``synth.tracker``, the schema's defaults filled
    (:func:`robomill.settings.config_section`)."""
    return config_section(config, "synth.tracker")


def run_id(direction: str, feed_mm_s: float) -> str:
    """Run identifier ``<dir>_f<feed>`` (:func:`robomill.experiment.tracker_run_id`)."""
    return tracker_run_id(direction, feed_mm_s)



def motion_law(length_mm: float, feed_mm_s: float, accel_mm_s2: float,
               fs_hz: float) -> tuple[np.ndarray, np.ndarray]:
    """Sample times and path abscissa of a trapezoidal speed profile (rest to rest).

    If the path is too short to reach the feed, the profile is triangular.
    """
    v, a, L = float(feed_mm_s), float(accel_mm_s2), float(length_mm)
    t_acc = v / a
    if a * t_acc**2 > L:  # triangular
        t_acc = np.sqrt(L / a)
        v = a * t_acc
    t_const = (L - a * t_acc**2) / v
    total = 2 * t_acc + t_const
    t = np.arange(0.0, total, 1.0 / fs_hz)
    s = np.where(t < t_acc, 0.5 * a * t**2,
                 np.where(t < t_acc + t_const, 0.5 * a * t_acc**2 + v * (t - t_acc),
                          L - 0.5 * a * np.clip(total - t, 0, None) ** 2))
    return t, s


def _rng(cell: Any, run: str) -> np.random.Generator:
    return np.random.default_rng([cell.seed, INSTRUMENT_NUMBER, zlib.crc32(run.encode())])


def deflection_along_path_mm(sim, s_mm: np.ndarray, fs_hz: float) -> np.ndarray:
    """The tool's deflection ``(len(s), 3)`` [mm, base axes] in the simulated cut ``sim``
    (:class:`robomill.synth.process.SimulatedCut`, the whole cut is used) at path abscissae
    ``s_mm`` (the structure's static and dynamic displacement of the closed-loop cut,
    low-pass filtered at 0.4 × ``fs_hz``; held beyond the cut's ends)."""
    import scipy.signal

    sim = sim.span(None)
    d = sim.deflection_m @ sim.frame.T
    sos = scipy.signal.butter(2, 0.4 * fs_hz, fs=sim.fs_hz, output="sos")
    d = scipy.signal.sosfiltfilt(sos, d - d[0], axis=0) + d[0]
    s_sim = sim.s_mm()
    return 1e3 * np.column_stack([np.interp(s_mm, s_sim, d[:, k]) for k in range(3)])


def simulate_run(config: Mapping[str, Any], cell: Any, direction: str,
                 feed_mm_s: float, cut: Cut, pass_: str = "loaded",
                 run: str | None = None, sim=None) -> pd.DataFrame:
    """One tracker record ``t_s, x_mm, y_mm, z_mm`` along ``cut``'s path at ``feed_mm_s``.

    Joint angles come from inverse kinematics on a grid of ``path_step_mm`` (cubic spline in
    between); the gear errors act through the Jacobian at every sample. ``pass_`` (manifest
    key ``pass``): ``loaded``, the pass is the cut (the tool deflects under the cutting force
    of the closed-loop cut, :func:`deflection_along_path_mm`), or ``air``, the same path
    without material (no force: the same gear errors, its own ripple phase and noise). ``run``:
    the run's id, which seeds its noise and ripple phase (default ``<dir>_f<feed>``, with
    ``/air`` for an air pass). ``sim``: the simulated cut (the whole of it), which a loaded
    pass samples.
    """
    if pass_ == "loaded" and sim is None:
        raise ValueError(f"tracker run along {cut.id}: a loaded pass samples the simulated cut "
                         "(expected sim, robomill.synth.cutstate.read_cut_state)")
    tr = settings(config)
    fs = float(tr["fs_hz"])
    L = float(cell.experiment["cut_length_mm"])
    t, s = motion_law(L, feed_mm_s, float(tr["accel_mm_s2"]), fs)
    n_grid = int(np.ceil(L / float(tr["path_step_mm"]))) + 1
    s_grid = np.linspace(0.0, L, n_grid)
    q_grid = cell.joint_path_rad(cut, s_grid)
    import scipy.interpolate  # here, not at the top: keeps Snakemake's start-up short
    q = scipy.interpolate.CubicSpline(s_grid, q_grid, axis=0)(s)
    nominal = cell.cut_path_mm(cut, s)
    gear_err = cell.tcp_error_mm(q)
    rng = _rng(cell, run or (run_id(direction, feed_mm_s) + ("" if pass_ == "loaded" else "/air")))
    e = np.asarray(tr["ripple_direction"], float)
    e = e / np.linalg.norm(e)
    phase = rng.uniform(0, 2 * np.pi)
    ripple = 1e-3 * float(tr["ripple_amplitude_um"]) * np.outer(
        np.sin(2 * np.pi * float(tr["ripple_hz"]) * t + phase), e)
    noise = 1e-3 * float(tr["noise_std_um"]) * rng.standard_normal((t.size, 3))
    p = nominal + gear_err + ripple + noise
    if pass_ == "loaded":
        p = p + deflection_along_path_mm(sim, s, fs)
    return pd.DataFrame({"t_s": t, "x_mm": p[:, 0], "y_mm": p[:, 1], "z_mm": p[:, 2]})


def write_run(df: pd.DataFrame, path: str | Path) -> Path:
    """Write a tracker record in the contract format (µs time, 10 nm positions)."""
    from robomill.io.atomic import atomic_path

    path = Path(path)
    with atomic_path(path) as tmp:
        df.to_csv(tmp, index=False, float_format="%.6f",
                  columns=["t_s", "x_mm", "y_mm", "z_mm"])
    return path


def planted_gear_table(config: Mapping[str, Any], cell: Any, cut: Cut,
                       n_points: int = 41) -> pd.DataFrame:
    """Planted truth per gear element on ``cut``'s path: spatial frequency and the amplitude
    of its TCP deviation perpendicular to the path [µm] (Jacobian column projected off the
    path direction, times the planted angular amplitude, averaged along the path)."""
    L = float(cell.experiment["cut_length_mm"])
    s = np.linspace(0.0, L, n_points)
    q = cell.joint_path_rad(cut, s)
    a, b = cell.cut_endpoints_mm(cut)
    u = (b - a) / np.linalg.norm(b - a)
    Jv = cell.robot.jacobian(q)[:, :3, :]  # (m, 3, n) mm/rad
    Jperp = Jv - np.einsum("i,mij->mj", u, Jv)[:, None, :] * u[None, :, None]
    lever = np.linalg.norm(Jperp, axis=1).mean(axis=0)  # (n,) mm/rad
    rate = np.abs(q[-1] - q[0]) / L / (2 * np.pi)
    rows = []
    for i, g in enumerate(cell.gears):
        f1 = g.rev_per_joint_rev * rate[g.joint - 1]
        for order, f, amp in (("runout", f1, g.runout_rad), ("mesh", f1 * g.teeth, g.mesh_rad)):
            rows.append({"gear": i, "joint": g.joint, "stage": g.stage, "order": order,
                         "f_spatial_per_mm": f, "amplitude_um": 1e3 * amp * lever[g.joint - 1]})
    return pd.DataFrame(rows)


def truth(config: Mapping[str, Any], cell: Any) -> xr.Dataset:
    """Planted truth of the tracker runs (merged into ``results/synthetic/truth.nc``).

    ``tracker_gear_f_spatial_per_mm`` and ``tracker_gear_amplitude_um`` over
    (``tracker_run``, ``gear``, ``order``): every gear element's spatial frequency on the
    run's path and its perpendicular TCP amplitude; the ripple's spatial frequency
    (``ripple_hz / feed``) and perpendicular amplitude per run; the noise level.
    """
    tr = settings(config)
    runs = tracker_runs(config)
    if not runs:
        return xr.Dataset()
    n_g = len(cell.gears)
    f = np.zeros((len(runs), n_g, 2))
    amp = np.zeros_like(f)
    rip_f, rip_a = [], []
    e = np.asarray(tr["ripple_direction"], float)
    e = e / np.linalg.norm(e)
    for k, r in enumerate(runs):
        tab = planted_gear_table(config, cell, r["cut"])
        f[k] = tab["f_spatial_per_mm"].to_numpy().reshape(n_g, 2)
        amp[k] = tab["amplitude_um"].to_numpy().reshape(n_g, 2)
        a, b = cell.cut_endpoints_mm(r["cut"])
        u = (b - a) / np.linalg.norm(b - a)
        rip_f.append(float(tr["ripple_hz"]) / r["feed_mm_s"])
        rip_a.append(float(tr["ripple_amplitude_um"]) * np.linalg.norm(e - (e @ u) * u))
    dims = ("tracker_run", "gear", "order")
    return xr.Dataset(
        {
            "tracker_gear_f_spatial_per_mm": (dims, f, {"units": "1/mm", "long_name":
                                              "planted gear spatial frequency on the run path"}),
            "tracker_gear_amplitude_um": (dims, amp, {"units": "um", "long_name":
                                          "planted gear TCP amplitude perpendicular to path"}),
            "tracker_ripple_f_spatial_per_mm": ("tracker_run", rip_f, {
                "units": "1/mm", "long_name": "servo ripple spatial frequency (ripple_hz/feed)"}),
            "tracker_ripple_amplitude_um": ("tracker_run", rip_a, {
                "units": "um", "long_name": "servo ripple amplitude perpendicular to path"}),
            "tracker_noise_std_um": ((), float(tr["noise_std_um"]), {
                "units": "um", "long_name": "tracker noise standard deviation per axis"}),
        },
        coords={
            "tracker_run": ("tracker_run", [r["run"] for r in runs],
                            {"units": "1", "long_name": "tracker run <dir>_f<feed>"}),
            "tracker_direction": ("tracker_run", [r["direction"] for r in runs],
                                  {"units": "1", "long_name": "cut direction"}),
            "tracker_feed_mm_s": ("tracker_run", [r["feed_mm_s"] for r in runs],
                                  {"units": "mm/s", "long_name": "feed"}),
            "tracker_cut": ("tracker_run", [r["cut"].id for r in runs],
                            {"units": "1", "long_name": "cut whose path the run follows"}),
            "order": ("order", ["runout", "mesh"], {"units": "1", "long_name": "gear error "
                                                    "order (once per rev, tooth mesh)"}),
        },
    )
