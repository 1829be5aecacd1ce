"""The hexapod chapter's runs from the ``hexapod`` config section: the trajectory and forces
datasets of the seed's programme and vertical move, and one actuator's sensitivity shard (one
Snakemake job). SI inside, mm/deg/N in the datasets.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from robomill.hexapod.config import (
    hexapod_from_config,
    programme_from_config,
    solver_options,
    vertical_from_config,
)
from robomill.hexapod.dynamics import static_force_closed_form
from robomill.hexapod.geometry import inverse_kinematics
from robomill.hexapod.motion import (
    force_error_drift,
    instability_rates,
    pose_error,
    programme_forces,
    run_programme,
)
from robomill.xrvars import var

AXES = ("x", "y", "z")
ANGLES = ("psi", "theta", "phi")


def _coords(t: np.ndarray, tname: str, tlong: str) -> dict:
    return {tname: (tname, t, {"units": "s", "long_name": tlong}),
            "axis": ("axis", list(AXES), {"units": "1", "long_name": "base axis"}),
            "angle": ("angle", list(ANGLES), {"units": "1", "long_name":
                      "Euler angle: psi about x, theta about y, phi about z (R = Rz Ry Rx)"}),
            "actuator": ("actuator", np.arange(1, 7), {"units": "1", "long_name": "actuator"})}


def dynamics_datasets(section: Mapping[str, Any]) -> tuple[Any, Any]:
    """The chapter's trajectory and forces datasets (SI inside, mm/deg/N outside).

    Trajectory: the seed's programme (commanded pose, open-loop replay until it leaves the
    command by ``replay_tolerance_mm``), the vertical move exact and with the force error,
    and the instability rates of the force-controlled platform at the start pose.
    Forces: actuator forces of the programme (inverse dynamics, seed Fig. 4) and of the
    vertical move (nominal and with the error).
    """
    import xarray as xr

    hx = hexapod_from_config(section)
    opts = solver_options(section)
    prog = programme_from_config(section)
    dt = section["programme"]["dt_s"]
    t = np.round(np.arange(prog.edges_s[0], prog.edges_s[-1] + dt / 2, dt), 12)
    law = programme_forces(hx, prog)
    cmd = np.array([prog.state(ti)[0] for ti in t])
    vel = np.array([prog.state(ti)[1] for ti in t])
    acc = np.array([prog.state(ti)[2] for ti in t])
    f_prog = np.array([law(ti) for ti in t])
    lengths = np.array([inverse_kinematics(hx, p, prog.rotation).length for p in cmd])
    tol_m = section["replay_tolerance_mm"] * 1e-3
    replay = run_programme(hx, prog, t, stop_error_m=tol_m, **opts)
    rep_pos = np.full_like(cmd, np.nan)
    rep_pos[:replay.t.size] = replay.position
    hold_s = t[-1] if replay.t_stop is None else replay.t_stop
    # the vertical move, exact and with the force error (seed Fig. 5)
    vcfg = section["vertical"]
    vprog = vertical_from_config(section)
    tv = np.round(np.linspace(0.0, vcfg["duration_s"],
                              int(round(vcfg["duration_s"] / vcfg["dt_s"])) + 1), 12)
    scale = np.ones(6)
    scale[vcfg["actuator"] - 1] += vcfg["error_pct"] / 100.0
    exact = run_programme(hx, vprog, tv, **opts)
    pert = run_programme(hx, vprog, tv, scale, **opts)
    v_cmd = np.array([vprog.state(ti)[0] for ti in tv])
    dp, drot = pose_error(pert, vprog)
    ev, vec = instability_rates(hx, prog.start_m, prog.rotation)
    k = np.flatnonzero(ev.real > 0)
    mode_names = [["vx", "vy", "vz", "wx", "wy", "wz"][int(np.argmax(np.abs(vec[:, j])))]
                  for j in k]

    traj = xr.Dataset(
        {
            "position_mm": var(("time", "axis"), cmd * 1e3, "mm",
                                "commanded platform position (seed programme)"),
            "velocity_mm_s": var(("time", "axis"), vel * 1e3, "mm/s", "commanded velocity"),
            "acceleration_mm_s2": var(("time", "axis"), acc * 1e3, "mm/s2",
                                       "commanded acceleration (seed: gamma_x, gamma_y)"),
            "replay_position_mm": var(("time", "axis"), rep_pos * 1e3, "mm",
                                       "forward dynamics under the inverse-dynamics forces "
                                       "(open loop; NaN after it leaves the tolerance)"),
            "replay_error_mm": var("time", np.linalg.norm(rep_pos - cmd, axis=1) * 1e3, "mm",
                                    "replay position error"),
            "replay_hold_s": var((), hold_s, "s",
                                  "time the open-loop replay stays within the tolerance"),
            "replay_tolerance_mm": var((), section["replay_tolerance_mm"], "mm",
                                        "replay tolerance"),
            "vertical_exact_mm": var(("time_vertical", "axis"), exact.position * 1e3, "mm",
                                      "vertical move, exact forces (forward dynamics)"),
            "vertical_command_mm": var(("time_vertical", "axis"), v_cmd * 1e3, "mm",
                                        "vertical move, commanded"),
            "vertical_perturbed_mm": var(("time_vertical", "axis"), pert.position * 1e3, "mm",
                                          "vertical move, one actuator with a force error"),
            "vertical_perturbed_euler_deg": var(("time_vertical", "angle"),
                                                 np.rad2deg(pert.euler), "deg",
                                                 "Euler angles with the force error"),
            "vertical_final_drift_mm": var("axis", dp * 1e3, "mm",
                                            "final position minus exact final position"),
            "vertical_final_rotvec_deg": var("axis", np.rad2deg(drot), "deg",
                                              "final orientation error as a rotation vector"),
            "instability_rate_per_s": var("mode", ev.real[k], "1/s",
                                           "growth rate of the open-loop force-controlled "
                                           "platform (linearised at the start pose)"),
        },
        coords={**_coords(t, "time", "time of the seed programme"),
                "time_vertical": ("time_vertical", tv, {"units": "s",
                                                        "long_name": "time of the vertical move"}),
                "mode": ("mode", np.arange(1, k.size + 1), {"units": "1",
                                                             "long_name": "unstable mode"}),
                "mode_dominant": ("mode", mode_names, {"units": "1", "long_name":
                                  "largest twist component of the mode"})},
        attrs={"vertical_actuator": int(vcfg["actuator"]),
               "vertical_error_pct": float(vcfg["error_pct"]),
               "vertical_duration_s": float(vcfg["duration_s"]),
               "solver": f"solve_ivp {opts['method']} rtol={opts['rtol']} atol={opts['atol']}",
               "replay_nfev": int(replay.nfev)},
    )
    forces = xr.Dataset(
        {
            "force_N": var(("time", "actuator"), f_prog, "N",
                            "actuator force, inverse dynamics of the seed programme"),
            "leg_length_mm": var(("time", "actuator"), lengths * 1e3, "mm", "leg length"),
            "vertical_force_N": var(("time_vertical", "actuator"), exact.forces, "N",
                                     "actuator force of the vertical move (exact)"),
            "vertical_perturbed_force_N": var(("time_vertical", "actuator"), pert.forces, "N",
                                               "actuator force with the force error"),
            "static_force_N": var((), static_force_closed_form(hx, prog.start_m[2]), "N",
                                   "closed-form static force at the start pose"),
        },
        coords={k: v for k, v in _coords(t, "time", "time of the seed programme").items()
                if k in ("time", "actuator")} | {
            "time_vertical": ("time_vertical", tv, {"units": "s",
                                                    "long_name": "time of the vertical move"})},
    )
    return traj, forces


def sensitivity_shard(section: Mapping[str, Any], actuator: int, progress=None) -> Any:
    """Drift of the vertical move's final pose for one actuator over every configured force
    error (one Snakemake job): signed components, ``drift_mm`` and ``tilt_deg``.
    ``progress(fraction)`` is called after each error size."""
    import xarray as xr

    hx = hexapod_from_config(section)
    prog = vertical_from_config(section)
    opts = solver_options(section)
    errs = np.asarray(section["sensitivity"]["error_pct"], float)
    dps, drs = [], []
    for k, e in enumerate(errs):
        dp, dr = force_error_drift(hx, prog, actuator, float(e), **opts)
        dps.append(dp)
        drs.append(dr)
        if progress is not None:
            progress((k + 1) / len(errs))
    dp = np.array(dps)[None] * 1e3
    dr = np.rad2deg(np.array(drs))[None]
    dims = ("actuator", "force_error_pct", "axis")
    return xr.Dataset(
        {
            "drift_mm": var(dims[:2], np.linalg.norm(dp, axis=-1), "mm",
                             "final position error of the vertical move"),
            "tilt_deg": var(dims[:2], np.linalg.norm(dr, axis=-1), "deg",
                             "final orientation error (rotation angle)"),
            "drift_components_mm": var(dims, dp, "mm", "final position error, components"),
            "rotvec_deg": var(dims, dr, "deg", "final orientation error, rotation vector"),
        },
        coords={"actuator": ("actuator", [int(actuator)], {"units": "1",
                                                           "long_name": "actuator in error"}),
                "force_error_pct": ("force_error_pct", errs, {"units": "%", "long_name":
                                    "actuator force error"}),
                "axis": ("axis", list(AXES), {"units": "1", "long_name": "base axis"})},
        attrs={"duration_s": float(section["vertical"]["duration_s"])},
    )
