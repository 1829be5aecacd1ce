"""Creaform C-Track optical CMM measuring the virtual IRB 1600 (thesis ch. 1): ``ctrack/*.csv``.

The "true" robot is the cell's nominal D-H geometry (as a vector model, eq. 1.4) plus the
errors planted in ``config.yaml: synth.ctrack``:

* joint-axis misalignments (a small rotation of each zero-configuration axis) and centre
  offsets, a TCP offset;
* joint zero offsets;
* the cell's gear-train periodic errors (``VirtualCell.joint_error_rad``, the same gears the
  straightness chapter sees);
* backlash: ±b/2 on a joint, by the direction it last moved;
* joint compliance: δθ_j = c_j τ_j, τ from gravity on the links, the tool and any load discs
  (the true masses: the cell's documented ``cell.mass_model`` unless
  ``synth.ctrack.true_mass_model`` plants a deviation from it);
* base compliance: the base turns by c_base τ_2 about an axis parallel to joint 2 through a
  pivot on axis 1 (the joint-1 bearing), carrying the arm and the base targets.

Tables (kind ``ctrack``, manifest key ``table``), all coordinates in the C-Track frame
(registered to the robot base) with per-target Gaussian noise ``target_noise_mm``:

``circles``  joint i alone over a range, a target on link i: ``joint, q_deg, x_mm, y_mm, z_mm``
``home``     the tool tip at home, repeated: ``repeat, x_mm, y_mm, z_mm``
``steps``    joint i at equal intervals from both directions:
             ``joint, step, q_deg, direction, x_mm, y_mm, z_mm``
``base``     two target groups on the base while joint 2 turns with the arm stretched:
             ``pose, q1_deg..q6_deg, group, target, repeat, x_mm, y_mm, z_mm``
``loads``    load discs on a fixture, the target at its hook:
             ``test, q1_deg..q6_deg, load_kg, repeat, x_mm, y_mm, z_mm``
``accuracy`` random points, each visited from both directions:
             ``point, visit, q1_deg..q6_deg, x_cmd_mm, y_cmd_mm, z_cmd_mm, x_mm, y_mm, z_mm``
"""

from __future__ import annotations

import zlib
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill.calibration.geometry import VectorModel, vector_model_from_serial
from robomill.calibration.gravity import MassModel, gravity_torques_Nm
from robomill.io.atomic import atomic_path
from robomill.io.synthetic_layout import CTRACK_TABLES
from robomill.kinematics import rodrigues

TABLES = CTRACK_TABLES
INSTRUMENT = 5
ARCSEC = np.pi / (180.0 * 3600.0)
XYZ = ["x_mm", "y_mm", "z_mm"]



@dataclass
class TrueRobot:
    """The planted robot: true geometry at θ = 0 plus its joint-error sources."""

    geometry: VectorModel
    zero_offset_rad: np.ndarray
    backlash_rad: np.ndarray
    compliance: np.ndarray
    base_compliance: float
    base_pivot_mm: np.ndarray  # (radial along the arm, height) of the base pivot
    masses: MassModel
    gear_error: Any  # callable q -> (..., n) [rad]

    def joint_state(self, q: np.ndarray, direction: np.ndarray | float = 1.0,
                    masses: MassModel | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Actual joint angles θ and gravity torques τ for commanded q and approach
        direction(s) (±1 per joint). Compliance is first order: τ at the undeflected pose."""
        q = np.asarray(q, float)
        th = q + self.zero_offset_rad + self.gear_error(q) + \
            0.5 * np.asarray(direction, float) * self.backlash_rad
        tau = gravity_torques_Nm(self.geometry, masses or self.masses, th)
        return th + self.compliance * tau, tau

    def _base_rotation(self, theta, tau2):
        """Base tilt (R, pivot) at joint angles θ: c_base τ_2 about the current joint-2
        direction through the pivot on axis 1."""
        g = self.geometry
        e, o = g.joint_lines(theta)
        u = e[..., 1, :]
        e1, o1 = g.axes[0], g.centres[0]
        foot = o1 + e1 * (self.base_pivot_mm[1] - o1[2]) / e1[2]
        radial = o[..., 1, :] - o1
        radial = radial - (radial @ e1)[..., None] * e1
        radial = radial / np.linalg.norm(radial, axis=-1, keepdims=True)
        pivot = foot + self.base_pivot_mm[0] * radial
        ang = self.base_compliance * tau2
        R = np.stack([rodrigues(uu, a) for uu, a in zip(u.reshape(-1, 3), np.ravel(ang),
                                                          strict=True)])
        return R.reshape(np.shape(ang) + (3, 3)), pivot

    def measure(self, q: np.ndarray, points: list[tuple[np.ndarray, int]],
                direction: np.ndarray | float = 1.0, masses: MassModel | None = None
                ) -> np.ndarray:
        """True positions ``(m, k, 3)`` of points (zero-config position, link) at poses
        ``q (m, n)``, with every planted error."""
        q = np.atleast_2d(np.asarray(q, float))
        th, tau = self.joint_state(q, direction, masses)
        R, pivot = self._base_rotation(th, tau[:, 1])
        out = np.empty((len(q), len(points), 3))
        for k, (x0, link) in enumerate(points):
            x = self.geometry.point(th, x0, link)
            out[:, k] = np.einsum("mij,mj->mi", R, x - pivot) + pivot
        return out

    def home_geometry(self) -> VectorModel:
        """The geometry the single-joint method should find: axes, centres and TCP in the
        home state (commanded 0, approached in the + direction, deflected by its torques)."""
        q0 = np.zeros((1, self.geometry.n_joints))
        th, tau = self.joint_state(q0)
        R, pivot = self._base_rotation(th, tau[:, 1])
        e, o = self.geometry.joint_lines(th)
        axes = np.einsum("ij,kj->ki", R[0], e[0])
        centres = np.einsum("ij,kj->ki", R[0], o[0] - pivot[0]) + pivot[0]
        # the tilt axis turns with joint 1 (it follows the arm's moment): axis 1 keeps its line
        axes[0], centres[0] = e[0, 0], o[0, 0]
        tcp = self.measure(q0, [(self.geometry.tcp_mm, self.geometry.n_joints)])[0, 0]
        return VectorModel(axes, centres, tcp)


def _rot(vec_mrad):
    v = np.asarray(vec_mrad, float) * 1e-3
    a = np.linalg.norm(v)
    return np.eye(3) if a == 0 else rodrigues(v / a, a)


def true_robot(config: Mapping[str, Any], cell) -> TrueRobot:
    """Build the planted robot from ``synth.ctrack`` and the cell (nominal geometry, gears)."""
    sc = config["synth"]["ctrack"]
    nom = vector_model_from_serial(cell.robot)
    axes = np.array([_rot(w) @ e for w, e in zip(sc["axis_rotation_mrad"], nom.axes,
                                                 strict=True)])
    centres = nom.centres + np.asarray(sc["centre_offset_mm"], float)
    geo = VectorModel(axes, centres, nom.tcp_mm + np.asarray(sc["tcp_offset_mm"], float))
    return TrueRobot(
        geometry=geo,
        zero_offset_rad=np.deg2rad(np.asarray(sc["zero_offset_deg"], float)),
        backlash_rad=np.asarray(sc["backlash_arcsec"], float) * ARCSEC,
        compliance=np.asarray(sc["compliance_rad_per_Nm"], float),
        base_compliance=float(sc["base_compliance_rad_per_Nm"]),
        base_pivot_mm=np.asarray(sc["base_pivot_mm"], float),
        masses=true_masses(config, cell.robot.n_joints),
        gear_error=cell.joint_error_rad,
    )


def true_masses(config: Mapping[str, Any], n_links: int) -> MassModel:
    """The virtual robot's true point masses: ``synth.ctrack.true_mass_model`` when it plants a
    deviation from the documented masses, else the cell's ``cell.mass_model`` (the cell file's
    values are then exact), checked as the cell file's mass model is
    (:func:`robomill.io.cell.parse_mass_model`).

    Raises
    ------
    ValueError
        When neither states a mass model: the simulated robot needs true masses.
    robomill.errors.RawDataError
        One line naming ``config.yaml``, the key and what was expected, for a malformed one.
    """
    masses = true_masses_or_none(config, n_links)
    if masses is None:
        raise ValueError("the C-Track simulator needs the robot's true masses: set "
                         "cell.mass_model (the documented masses, written into cell.yaml) or "
                         "synth.ctrack.true_mass_model (planted truth the analysis is not told)")
    return masses


def true_masses_or_none(config: Mapping[str, Any], n_links: int) -> MassModel | None:
    """:func:`true_masses`, or None where the configuration states no masses."""
    from robomill.io.cell import parse_mass_model

    planted = (config["synth"].get("ctrack") or {}).get("true_mass_model")
    key, spec = (("synth.ctrack.true_mass_model", planted) if planted is not None
                 else ("cell.mass_model", config["cell"].get("mass_model")))
    if spec is None:
        return None
    points = parse_mass_model(spec, f"config.yaml ({key})", n_links).point_masses()
    return MassModel([m.link for m in points], [m.mass_kg for m in points],
                     np.array([m.com_mm for m in points], float).reshape(-1, 3))


def _rng(cell, table: str) -> np.random.Generator:
    return np.random.default_rng([cell.seed, INSTRUMENT, zlib.crc32(table.encode())])


def _qcols(n):
    return [f"q{i}_deg" for i in range(1, n + 1)]


def simulate_table(config: Mapping[str, Any], cell, table: str, *,
                   noise_mm: float | None = None) -> pd.DataFrame:
    """One C-Track table of the virtual experiment (noise ``target_noise_mm`` unless given)."""
    sc = config["synth"]["ctrack"]
    tr = true_robot(config, cell)
    rng = _rng(cell, table)
    sigma = float(sc["target_noise_mm"] if noise_mm is None else noise_mm)
    n = tr.geometry.n_joints
    nom = vector_model_from_serial(cell.robot)
    # targets: zero-configuration positions (nominal frames) on each link
    targets = [(np.asarray(t, float), i + 1) for i, t in enumerate(sc["targets_mm"])]
    tcp = (tr.geometry.tcp_mm, n)

    def noisy(x):
        return x + rng.normal(0.0, sigma, size=x.shape) if sigma > 0 else x

    if table == "circles":
        rows = []
        for j in range(1, n + 1):
            lo, hi = sc["circle_range_deg"][j - 1]
            qd = np.linspace(lo, hi, int(sc["circle_points"]))
            q = np.zeros((len(qd), n))
            q[:, j - 1] = np.deg2rad(qd)
            x = noisy(tr.measure(q, [targets[j - 1]])[:, 0])
            rows.append(pd.DataFrame({"joint": j, "q_deg": qd, **dict(zip(XYZ, x.T,
                                                                           strict=True))}))
        return pd.concat(rows, ignore_index=True)
    if table == "home":
        m = int(sc["home_repeats"])
        x = noisy(np.repeat(tr.measure(np.zeros((1, n)), [tcp])[:, 0], m, axis=0))
        return pd.DataFrame({"repeat": np.arange(1, m + 1), **dict(zip(XYZ, x.T, strict=True))})
    if table == "steps":
        rows = []
        step = float(sc["step_deg"])
        for j in range(1, n + 1):
            lo, hi = sc["step_range_deg"][j - 1]
            qd = np.arange(np.ceil(lo / step), np.floor(hi / step) + 1) * step
            q = np.zeros((len(qd), n))
            q[:, j - 1] = np.deg2rad(qd)
            for d in (1, -1):
                direc = np.ones(n)
                direc[j - 1] = d
                x = noisy(tr.measure(q, [targets[j - 1]], direction=direc)[:, 0])
                rows.append(pd.DataFrame({"joint": j, "step": np.arange(len(qd)), "q_deg": qd,
                                          "direction": d,
                                          **dict(zip(XYZ, x.T, strict=True))}))
        return pd.concat(rows, ignore_index=True)
    if table == "base":
        q2 = np.linspace(*sc["base_q2_range_deg"], int(sc["base_poses"]))
        q = np.tile(np.deg2rad(np.asarray(sc["base_pose_deg"], float)), (len(q2), 1))
        q[:, 1] = np.deg2rad(q2)
        pts = [(np.asarray(p, float), 0) for grp in sc["base_groups_mm"] for p in grp]
        x = tr.measure(q, pts)
        rows = []
        k = 0
        for gi, grp in enumerate(sc["base_groups_mm"], start=1):
            for ti in range(len(grp)):
                for rep in range(1, int(sc["base_repeats"]) + 1):
                    xx = noisy(x[:, k])
                    rows.append(pd.DataFrame({"pose": np.arange(1, len(q) + 1),
                                              **dict(zip(_qcols(n), np.rad2deg(q).T,
                                                         strict=True)),
                                              "group": gi, "target": ti + 1, "repeat": rep,
                                              **dict(zip(XYZ, xx.T, strict=True))}))
                k += 1
        return pd.concat(rows, ignore_index=True).sort_values(["pose", "group", "target",
                                                               "repeat"])
    if table == "loads":
        poses = np.deg2rad(np.asarray(sc["load_poses_deg"], float))
        fix = tr.geometry.tcp_mm + np.asarray(sc["fixture_offset_mm"], float)
        base_mass = tr.masses.plus(n, float(sc["fixture_mass_kg"]), fix)
        rows = []
        for t, qq in enumerate(poses, start=1):
            for load in sc["loads_kg"]:
                mm = base_mass.plus(n, float(load), fix)
                x = tr.measure(qq[None], [(fix, n)], masses=mm)[0, 0]
                reps = int(sc["load_repeats"])
                xx = noisy(np.repeat(x[None], reps, axis=0))
                rows.append(pd.DataFrame({"test": t, **{c: np.rad2deg(v) for c, v in
                                                        zip(_qcols(n), qq, strict=True)},
                                          "load_kg": float(load), "repeat": np.arange(1, reps + 1),
                                          **dict(zip(XYZ, xx.T, strict=True))}))
        return pd.concat(rows, ignore_index=True)
    if table == "accuracy":
        m = int(sc["accuracy_points"])
        rng_q = np.random.default_rng([cell.seed, INSTRUMENT, 99])
        lo, hi = np.asarray(sc["accuracy_range_deg"], float).T
        qd = rng_q.uniform(lo, hi, size=(m, n))
        q = np.deg2rad(qd)
        cmd = cell.robot.fk(q)[:, :3, 3]
        rows = []
        for v, d in enumerate((1.0, -1.0), start=1):
            x = noisy(tr.measure(q, [tcp], direction=d)[:, 0])
            rows.append(pd.DataFrame({"point": np.arange(1, m + 1), "visit": v,
                                      **dict(zip(_qcols(n), qd.T, strict=True)),
                                      "x_cmd_mm": cmd[:, 0], "y_cmd_mm": cmd[:, 1],
                                      "z_cmd_mm": cmd[:, 2], **dict(zip(XYZ, x.T, strict=True))}))
        return pd.concat(rows, ignore_index=True).sort_values(["point", "visit"])
    del nom
    raise ValueError(f"unknown C-Track table {table!r}; expected one of {TABLES}")


def write_table(config: Mapping[str, Any], cell, table: str, path: str | Path) -> Path:
    """Simulate one table and write it as CSV (atomically)."""
    df = simulate_table(config, cell, table)
    path = Path(path)
    with atomic_path(path) as tmp:
        df.to_csv(tmp, index=False, float_format="%.6f")
    return path


def truth(config: Mapping[str, Any], cell) -> xr.Dataset:
    """Planted C-Track truth (``ctrack_*`` variables in ``truth.nc``)."""
    tr = true_robot(config, cell)
    home = tr.home_geometry()
    n = tr.geometry.n_joints

    def v(dims, data, units, long_name):
        return (dims, np.asarray(data, float), {"units": units, "long_name": long_name})

    j, x = "ctrack_joint", "ctrack_xyz"
    return xr.Dataset(
        {
            "ctrack_axis_true": v((j, x), tr.geometry.axes, "1",
                                  "true joint axis at theta = 0 (planted)"),
            "ctrack_centre_true_mm": v((j, x), tr.geometry.centres, "mm",
                                       "true joint centre at theta = 0 (planted)"),
            "ctrack_axis_home": v((j, x), home.axes, "1",
                                  "true joint axis in the home state (what circles measure)"),
            "ctrack_centre_home_mm": v((j, x), home.centres, "mm",
                                       "a point of the true axis in the home state"),
            "ctrack_tcp_home_mm": v((x,), home.tcp_mm, "mm", "true tool tip at home"),
            "ctrack_zero_offset_rad": v((j,), tr.zero_offset_rad, "rad", "joint zero offset"),
            "ctrack_backlash_rad": v((j,), tr.backlash_rad, "rad", "joint backlash"),
            "ctrack_compliance_rad_per_Nm": v((j,), tr.compliance, "rad/(N m)",
                                              "joint compliance"),
            "ctrack_base_compliance_rad_per_Nm": v((), tr.base_compliance, "rad/(N m)",
                                                   "base rotational compliance per joint-2 "
                                                   "torque"),
        },
        coords={j: (j, np.arange(1, n + 1), {"units": "1", "long_name": "joint"}),
                x: (x, ["x", "y", "z"], {"units": "1", "long_name": "C-Track axis"})},
    )
