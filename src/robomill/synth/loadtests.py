"""Stiffness load tests: stiffness/<robot>.yaml and stiffness/load_tests_<robot>.csv.

Simulator of the joint-stiffness identification experiment of Yi 2025 (§3.2): an end load
(60 kg for the KUKA KR360) hung at the TCP through a pulley rig (so its direction can change,
*assumed*: Yi 2025 only says "counterweight device"), the TCP deflection measured by a laser
tracker (Gaussian noise, *assumed* σ). Poses: a cube sampled on a regular grid (seed: 600 mm
every 300 mm) and the centres of squares in the working plane z = H (seed: 26 squares of
300 mm at H = 1.6 m) for identification, and a few plane poses for validation. Deflections
follow the joint-stiffness model X = J K_θ⁻¹ Jᵀ F with the planted K_θ
(``synth.loadtests.robots[*].k_Nm_rad``), which :func:`truth` writes into ``truth.nc``.

Robots: every entry of ``synth.loadtests.robots``; an entry without ``robot:`` is the cell's
robot (``cell.robot``, the thesis IRB 1600).
"""

from __future__ import annotations

import zlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr
import yaml

from robomill.io.atomic import atomic_path
from robomill.kinematics import robot_from_mapping
from robomill.stiffness.model import GRAVITY_M_S2, jacobian_m, predict_deflection_m
from robomill.stiffness.poses import solve_poses, tool_rotation_redundancy

INSTRUMENT = 10
TOOL_DOWN = np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, -1.0]])


def robots(config: Mapping[str, Any]) -> list[dict[str, Any]]:
    """The load-test robot entries with their robot mapping filled in."""
    lt = config["synth"].get("loadtests", {})
    out = []
    for entry in lt.get("robots", []):
        e = dict(entry)
        spec = dict(e.get("robot") or config["cell"]["robot"])  # default: the cell's robot
        spec["name"] = e["name"]
        e["robot"] = spec
        out.append(e)
    return out


def robot_entry(config: Mapping[str, Any], name: str) -> dict[str, Any]:
    for e in robots(config):
        if e["name"] == name:
            return e
    raise KeyError(f"no synth.loadtests robot named {name!r}")



def _plane_centres(e: Mapping[str, Any]) -> np.ndarray:
    """Centres of ``count`` squares of side ``square_mm`` nearest ``center_mm`` in z = H."""
    p = e["plane"]
    step = float(p["square_mm"])
    n = int(np.ceil(np.sqrt(p["count"]))) + 2
    off = (np.arange(-n, n) + 0.5) * step
    X, Y = np.meshgrid(p["center_mm"][0] + off, p["center_mm"][1] + off)
    P = np.stack([X.ravel(), Y.ravel(), np.full(X.size, float(p["height_mm"]))], -1)
    d = np.hypot(P[:, 0] - p["center_mm"][0], P[:, 1] - p["center_mm"][1])
    order = np.lexsort((P[:, 0], P[:, 1], np.round(d, 6)))
    return P[order]


def load_test_poses(e: Mapping[str, Any], rng: np.random.Generator) -> pd.DataFrame:
    """Pose names, roles, TCP points [mm] and redundancy angles of one robot's tests."""
    rows = []
    c = e["cube"]
    k = int(round(c["side_mm"] / c["step_mm"]))
    g = (np.arange(k + 1) - k / 2) * c["step_mm"]
    for ix in g:
        for iy in g:
            for iz in g:
                rows.append(("cube", "identify", np.asarray(c["center_mm"], float)
                             + [ix, iy, iz]))
    for P in _plane_centres(e):
        rows.append(("plane", "identify", P))
    v = e["validate"]
    for _ in range(int(v["count"])):
        r = v["radius_mm"] * np.sqrt(rng.uniform())
        a = rng.uniform(0, 2 * np.pi)
        rows.append(("val", "validate", np.array([e["plane"]["center_mm"][0] + r * np.cos(a),
                                                  e["plane"]["center_mm"][1] + r * np.sin(a),
                                                  e["plane"]["height_mm"]])))
    red = np.deg2rad(np.asarray(e.get("redundancy_deg", [0.0]), float))
    return pd.DataFrame({"group": [r[0] for r in rows], "role": [r[1] for r in rows],
                         "x_mm": [r[2][0] for r in rows], "y_mm": [r[2][1] for r in rows],
                         "z_mm": [r[2][2] for r in rows],
                         "redundancy_rad": [red[i % len(red)] for i in range(len(rows))]})


def simulate_load_tests(config: Mapping[str, Any], name: str,
                        *, noise: bool = True) -> pd.DataFrame:
    """The load-test table of robot ``name`` in the contract format (reachable poses only;
    the plane group is cut to ``plane.count`` reachable squares)."""
    e = robot_entry(config, name)
    lt = config["synth"]["loadtests"]
    seed = int(config["synth"]["seed"])
    rng = np.random.default_rng([seed, INSTRUMENT, zlib.crc32(name.encode())])
    robot = robot_from_mapping(e["robot"])
    poses = load_test_poses(e, rng)
    R = tool_rotation_redundancy(TOOL_DOWN, poses["redundancy_rad"].to_numpy())
    limits = np.deg2rad(np.asarray(e["limits_deg"], float)) if "limits_deg" in e else None
    q, ok = solve_poses(robot, poses[["x_mm", "y_mm", "z_mm"]].to_numpy(), R,
                        np.deg2rad(e["q_seed_deg"]), limits_rad=limits)
    poses["ok"] = ok
    keep = ok.copy()
    plane = np.flatnonzero((poses["group"] == "plane").to_numpy() & ok)
    keep[plane[int(e["plane"]["count"]):]] = False
    idx = np.flatnonzero(keep)
    q = q[idx]
    sub = poses.iloc[idx].reset_index(drop=True)
    dirs = np.asarray(lt["load_directions"], float)
    dirs = dirs / np.linalg.norm(dirs, axis=1, keepdims=True)
    F = float(e["load_kg"]) * GRAVITY_M_S2 * dirs[np.arange(len(idx)) % len(dirs)]
    X = predict_deflection_m(jacobian_m(robot, q), F, 1.0 / np.asarray(e["k_Nm_rad"], float))
    X_mm = X * 1e3
    if noise:
        X_mm = X_mm + rng.normal(0.0, float(lt["noise_mm"]), X_mm.shape)
    counters: dict[str, int] = {}
    names = []
    for g in sub["group"]:
        counters[g] = counters.get(g, 0) + 1
        names.append(f"{g}_{counters[g]:02d}")
    df = pd.DataFrame({"pose": names, "role": sub["role"]})
    for j in range(robot.n_joints):
        df[f"q{j + 1}_deg"] = np.rad2deg(q[:, j])
    for i, c in enumerate(("Fx_N", "Fy_N", "Fz_N")):
        df[c] = F[:, i]
    for i, c in enumerate(("dx_mm", "dy_mm", "dz_mm")):
        df[c] = X_mm[:, i]
    return df


def write_robot_file(config: Mapping[str, Any], name: str, path: str | Path) -> Path:
    """Write ``stiffness/<robot>.yaml`` (data contract, kind ``robot``)."""
    spec = robot_entry(config, name)["robot"]
    out = {k: spec[k] for k in ("name", "convention", "length_unit", "angle_unit")}
    out["joints"] = [{k: float(j.get(k, 0.0)) for k in ("a", "alpha", "d", "theta_offset")}
                     for j in spec["joints"]]
    tool = spec.get("tool", [0, 0, 0])
    out["tool"] = (tool if isinstance(tool, Mapping)  # the tool frame {xyz_mm, rpy_deg}
                   else [float(v) for v in tool])
    path = Path(path)
    with atomic_path(path) as tmp:
        Path(tmp).write_text("# robot file (kind robot), written by robomill.synth.loadtests\n"
                             + yaml.safe_dump(out, sort_keys=False))
    return path


def write_load_tests(config: Mapping[str, Any], name: str, path: str | Path) -> Path:
    """Simulate and write ``stiffness/load_tests_<robot>.csv``."""
    df = simulate_load_tests(config, name)
    path = Path(path)
    with atomic_path(path) as tmp:
        df.to_csv(tmp, index=False, float_format="%.8g")
    return path


def truth(config: Mapping[str, Any], cell: Any) -> xr.Dataset:
    """Planted joint stiffness of every load-test robot (``stiffness_k_Nm_rad``)."""
    entries = robots(config)
    if not entries:
        return xr.Dataset()
    n = max(len(e["k_Nm_rad"]) for e in entries)
    k = np.full((len(entries), n), np.nan)
    for i, e in enumerate(entries):
        k[i, :len(e["k_Nm_rad"])] = e["k_Nm_rad"]
    return xr.Dataset(
        {"stiffness_k_Nm_rad": (("stiffness_robot", "stiffness_joint"), k,
                                {"units": "N m/rad", "long_name": "planted joint stiffness"})},
        coords={"stiffness_robot": ("stiffness_robot", [e["name"] for e in entries],
                                    {"units": "1", "long_name": "load-test robot"}),
                "stiffness_joint": ("stiffness_joint", np.arange(1, n + 1),
                                    {"units": "1", "long_name": "joint number"})})
