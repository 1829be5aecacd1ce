"""Chapter 6's findings: every number the hexapod chapter states, computed from the stage's
artefacts and the ``hexapod`` config section (the assumed geometry and masses) and rendered
by the chapter (:mod:`robomill.pipeline.prose`): the acceleration programme and its open-loop
replay, the instability rates of the force-driven platform (linearised at the start pose,
compared with √(g/h) of an inverted pendulum of the start height), the actuator forces, the
vertical move with one actuator's force off [Rybak n.d., eqs 1–8], the drift map and the force
accuracy a position tolerance needs. Seed numbers come from ``references.yaml``
(:mod:`robomill.references`), each with its key as evidence.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill import catalogue, references
from robomill.findings import Findings
from robomill.hexapod.geometry import G0_M_S2
from robomill.hexapod.sensitivity import drift_antisymmetry

_TRAJECTORY = catalogue.artefact("hexapod.trajectory")
_FORCES = catalogue.artefact("hexapod.forces")
_SENSITIVITY = catalogue.artefact("hexapod.sensitivity")
_ACCURACY = catalogue.artefact("hexapod.force_accuracy")
_REFS = "src/robomill/data/references.yaml"
_CONFIG = "config.yaml"
_TABLE1 = ("spindle_rpm", "feed_m_min", "depth_mm", "hardness_hrc_max")


def _ref(found: Findings, key: str, ref: str) -> Any:
    r = references.reference(ref)
    found.add(key, r["value"], r["unit"], artefact=_REFS, what=ref)
    return r["value"]


def _assumed(found: Findings, hexapod: Mapping[str, Any]) -> None:
    """The assumed hexapod of ``config.yaml: hexapod`` (the seed prints none of it)."""
    geo, vert, prog = hexapod["geometry"], hexapod["vertical"], hexapod["programme"]
    for key, value, unit, ck in (
            ("base_radius_mm", geo["base_radius_mm"], "mm", "geometry.base_radius_mm"),
            ("platform_radius_mm", geo["platform_radius_mm"], "mm",
             "geometry.platform_radius_mm"),
            ("platform_mass_kg", hexapod["platform"]["mass_kg"], "kg", "platform.mass_kg"),
            ("vertical_duration_s", vert["duration_s"], "s", "vertical.duration_s"),
            ("vertical_actuator", vert["actuator"], "", "vertical.actuator"),
            ("vertical_error_pct", vert["error_pct"], "%", "vertical.error_pct"),
            ("programme_edges_s", prog["edges_s"], "s", "programme.edges_s"),
            ("programme_accel_x_mm_s2", [a[0] for a in prog["accel_mm_s2"]], "mm/s2",
             "programme.accel_mm_s2"),
            ("programme_accel_y_mm_s2", [a[1] for a in prog["accel_mm_s2"]], "mm/s2",
             "programme.accel_mm_s2"),
            ("start_mm", hexapod["start_mm"], "mm", "start_mm")):
        found.add(key, value, unit, artefact=_CONFIG, what=f"hexapod.{ck}",
                  config_key=f"hexapod.{ck}")


def _programme(found: Findings, traj: xr.Dataset, gravity_m_s2: float) -> None:
    pos = traj["position_mm"]
    end = pos.isel(time=-1).values
    found.add("programme_end_mm", end, "mm", artefact=_TRAJECTORY,
              what="position_mm at the last time")
    start = pos.isel(time=0).values
    found.add("programme_sideways_mm", float(np.linalg.norm(end[:2] - start[:2])), "mm",
              artefact=_TRAJECTORY, what="horizontal distance of start and end")
    found.add("replay_tolerance_mm", float(traj["replay_tolerance_mm"]), "mm",
              artefact=_TRAJECTORY, what="replay_tolerance_mm")
    found.add("replay_hold_s", float(traj["replay_hold_s"]), "s", artefact=_TRAJECTORY,
              what="replay_hold_s")
    found.add("solver", str(traj.attrs.get("solver", "")), artefact=_TRAJECTORY,
              what="attribute solver")
    lam = np.asarray(traj["instability_rate_per_s"].values, float)
    found.add("n_unstable_modes", int(np.sum(lam > 0)), artefact=_TRAJECTORY,
              what="instability_rate_per_s > 0")
    found.add("instability_rate_range_per_s", [float(lam.min()), float(lam.max())], "1/s",
              artefact=_TRAJECTORY, what="instability_rate_per_s")
    h_m = float(pos.sel(axis="z").isel(time=0)) / 1e3
    found.add("start_height_mm", 1e3 * h_m, "mm", artefact=_TRAJECTORY,
              what="position_mm[axis = z] at t = 0")
    found.add("pendulum_rate_per_s", float(np.sqrt(gravity_m_s2 / h_m)), "1/s",
              artefact=_TRAJECTORY, what="√(g/h), h the start height, g hexapod.gravity_m_s2")
    grows = float(lam.max()) > 0  # else no error grows: no e-folding time
    found.add("efold_ms", 1e3 / float(lam.max()) if grows else None, "ms",
              artefact=_TRAJECTORY, what="1 / largest instability_rate_per_s")
    found.add("decade_ms", 1e3 * np.log(10) / float(lam.max()) if grows else None, "ms",
              artefact=_TRAJECTORY, what="ln 10 / largest instability_rate_per_s")


def _forces(found: Findings, frc: xr.Dataset) -> None:
    f = frc["force_N"]
    found.add("start_force_N", float(f.isel(time=0).mean()), "N", artefact=_FORCES,
              what="force_N at t = 0, mean over the actuators")
    found.add("static_force_N", float(frc["static_force_N"]), "N", artefact=_FORCES,
              what="static_force_N (closed form)")
    found.add("programme_force_range_N", [float(f.min()), float(f.max())], "N",
              artefact=_FORCES, what="force_N")


def _vertical(found: Findings, traj: xr.Dataset, frc: xr.Dataset) -> None:
    ex = traj["vertical_exact_mm"].isel(time_vertical=-1).values
    pe = traj["vertical_perturbed_mm"].isel(time_vertical=-1).values
    eul = traj["vertical_perturbed_euler_deg"].isel(time_vertical=-1).values
    f_exact = float(frc["vertical_force_N"][0, 0])
    f_pert = float(frc["vertical_perturbed_force_N"][0, 0])
    found.add("vertical_force_N", f_exact, "N", artefact=_FORCES,
              what="vertical_force_N[t = 0, actuator 1]")
    found.add("vertical_perturbed_force_N", f_pert, "N", artefact=_FORCES,
              what="vertical_perturbed_force_N[t = 0, actuator 1]")
    found.add("vertical_exact_end_mm", ex, "mm", artefact=_TRAJECTORY,
              what="vertical_exact_mm at the end")
    found.add("vertical_perturbed_end_mm", pe, "mm", artefact=_TRAJECTORY,
              what="vertical_perturbed_mm at the end")
    found.add("vertical_euler_deg", eul, "deg", artefact=_TRAJECTORY,
              what="vertical_perturbed_euler_deg at the end (ψ, θ, φ)")
    drift = np.asarray(traj["vertical_final_drift_mm"].values, float)
    found.add("vertical_drift_mm", float(np.linalg.norm(drift)), "mm", artefact=_TRAJECTORY,
              what="|vertical_final_drift_mm|")
    found.add("vertical_drift_z_share_pct", 100 * abs(drift[2]) / np.linalg.norm(drift), "%",
              artefact=_TRAJECTORY, what="|z| over |vertical_final_drift_mm|")
    found.add("vertical_rotation_deg",
              float(np.linalg.norm(traj["vertical_final_rotvec_deg"].values)), "deg",
              artefact=_TRAJECTORY, what="|vertical_final_rotvec_deg|")
    s_force = _ref(found, "seed_force_N", "seed003.hexapod.forces.static_force_N")
    s_pert = _ref(found, "seed_perturbed_force_N", "seed003.hexapod.forces.perturbed_force_N")
    s_ex = np.asarray(_ref(found, "seed_exact_end_mm",
                           "seed003.hexapod.trajectory.exact_end_mm"), float)
    s_pe = np.asarray(_ref(found, "seed_perturbed_end_mm",
                           "seed003.hexapod.trajectory.perturbed_end_mm"), float)
    s_eul = np.asarray(_ref(found, "seed_euler_deg",
                            "seed003.hexapod.trajectory.perturbed_euler_deg"), float)
    _ref(found, "seed_start_height_mm", "seed003.start_height_mm")
    s_drift = s_pe - s_ex
    found.add("seed_drift_mm", float(np.linalg.norm(s_drift)), "mm", artefact=_REFS,
              what="|perturbed_end_mm - exact_end_mm| of Rybak n.d.")
    found.add("seed_drift_z_share_pct", 100 * abs(s_drift[2]) / np.linalg.norm(s_drift), "%",
              artefact=_REFS, what="|z| over the seed's drift")
    found.add("seed_rotation_deg", float(np.linalg.norm(s_eul)), "deg", artefact=_REFS,
              what="|perturbed_euler_deg| of Rybak n.d.")
    ours = np.concatenate([[f_exact, f_pert], ex, pe, eul])
    seed = np.concatenate([[s_force, s_pert], s_ex, s_pe, s_eul])
    found.add("vertical_table_ours", ours, artefact=_TRAJECTORY,
              what="forces, exact end, perturbed end, Euler angles")
    found.add("vertical_table_seed", seed, artefact=_REFS, what="the same, Rybak n.d.")
    found.add("vertical_table_difference", ours - seed, artefact=_TRAJECTORY,
              what="ours - seed, row by row")


def _sensitivity(found: Findings, sens: xr.Dataset, need: pd.DataFrame,
                 tolerance_mm: float) -> None:
    slope = np.linalg.norm(np.asarray(sens["drift_components_per_pct"].values, float), axis=-1)
    found.add("drift_per_pct_range_mm", [float(slope.min()), float(slope.max())], "mm/%",
              artefact=_SENSITIVITY, what="|drift_components_per_pct| over the actuators")
    found.add("drift_per_pct_spread_pct", 100 * (slope.max() / slope.min() - 1), "%",
              artefact=_SENSITIVITY, what="largest over smallest slope, minus one")
    found.add("sensitivity_duration_s", float(sens.attrs.get("duration_s", np.nan)), "s",
              artefact=_SENSITIVITY, what="attribute duration_s")
    anti = drift_antisymmetry(sens)
    found.add("antisymmetry_error_pct", None if anti is None else anti[0], "%",
              artefact=_SENSITIVITY, what="smallest force error present with both signs")
    found.add("antisymmetry_pct", None if anti is None else 100 * anti[1], "%",
              artefact=_SENSITIVITY,
              what="max |drift(+e) + drift(-e)| / |drift(+e)| over the actuators")
    rows = need.set_index("position_tolerance_mm")
    tol = rows.index.to_numpy(float)
    found.add("accuracy_tolerances_mm", tol, "mm", artefact=_ACCURACY,
              what="position_tolerance_mm")
    if not len(rows):
        return
    row = rows.iloc[int(np.argmin(np.abs(tol - tolerance_mm)))]
    found.add("accuracy_tolerance_mm", float(row.name), "mm", artefact=_ACCURACY,
              what="position_tolerance_mm nearest hexapod.replay_tolerance_mm",
              config_key="hexapod.replay_tolerance_mm")
    found.add("accuracy_needed_pct", float(row["force_accuracy_pct"]), "%", artefact=_ACCURACY,
              what="force_accuracy_pct at that tolerance")
    found.add("accuracy_needed_mN", float(row["force_accuracy_mN"]), "mN", artefact=_ACCURACY,
              what="force_accuracy_mN at that tolerance")
    found.add("accuracy_worst_actuator", int(row["worst_actuator"]), artefact=_ACCURACY,
              what="worst_actuator")
    found.add("accuracy_duration_s", float(row["duration_s"]), "s", artefact=_ACCURACY,
              what="duration_s")


def _table1(found: Findings) -> None:
    for q in _TABLE1:
        for kind in ("conventional", "high_speed"):
            _ref(found, f"seed_table1_{q}_{kind}", f"seed003.table1.{q}.{kind}")


def hexapod_findings(trajectory: xr.Dataset, forces: xr.Dataset, sensitivity: xr.Dataset,
                     force_accuracy: pd.DataFrame, *, hexapod: Mapping[str, Any]) -> Findings:
    """The findings of the hexapod stage.

    Parameters
    ----------
    trajectory, forces, sensitivity, force_accuracy
        ``results/hexapod/trajectory.nc, forces.nc, sensitivity.nc, force_accuracy.csv``.
    hexapod
        The ``hexapod`` config section: the assumed geometry, masses and moves (stated as
        assumptions), ``gravity_m_s2`` and ``replay_tolerance_mm`` (the position tolerance
        whose force accuracy the chapter states).

    Returns
    -------
    Findings
        The assumptions (``base_radius_mm, platform_radius_mm, platform_mass_kg,
        vertical_duration_s, …, start_mm``); the programme (``programme_end_mm,
        programme_sideways_mm, replay_hold_s, n_unstable_modes,
        instability_rate_range_per_s, pendulum_rate_per_s, efold_ms, decade_ms``); the forces
        (``start_force_N, static_force_N, programme_force_range_N``); the vertical move (ours
        and the seed's, ``vertical_table_*``); the drift map (``drift_per_pct_range_mm,
        antisymmetry_*``) and the force accuracy at ``accuracy_tolerance_mm``; the seed's
        Table 1 (``seed_table1_*``).
    """
    found = Findings("hexapod")
    _assumed(found, hexapod)
    _programme(found, trajectory, float(hexapod.get("gravity_m_s2", G0_M_S2)))
    _forces(found, forces)
    _vertical(found, trajectory, forces)
    _sensitivity(found, sensitivity, force_accuracy, float(hexapod["replay_tolerance_mm"]))
    _table1(found)
    return found
