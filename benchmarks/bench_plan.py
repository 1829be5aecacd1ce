"""Chapter 7 benchmark: the planner's candidate grid — 20 placements × 12 rotations
about the tool axis × 200 spindle speeds, every prediction with its interval — against the
package's single-tool zero-order solver called once per pose (nominal lobes only), measured on
a sample of the poses in the same run and scaled to the grid. The goal: ≤ 60 s on 2
cores."""

from __future__ import annotations

import os
import time
from pathlib import Path

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import yaml  # noqa: E402

from robomill.chatter import CuttingModel, ModeXY, tool_from_modes, zoa_lobes  # noqa: E402
from robomill.kinematics import robot_from_mapping  # noqa: E402
from robomill.plan.measured import Measured  # noqa: E402
from robomill.plan.predict import Cell, predict_grid  # noqa: E402
from robomill.plan.request import parse_request  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
MODES = pd.DataFrame({  # thesis-like robot modes (20-72 Hz), base-frame shapes
    "f_n_hz": [20.0, 35.0, 60.0, 67.0, 70.0, 72.0],
    "zeta": [0.04, 0.035, 0.03, 0.025, 0.025, 0.03],
    "k_modal_N_m": [8.0e5, 1.2e6, 1.5e6, 1.1e6, 1.0e6, 2.0e6],
    "shape_x": [0.29, 0.94, 0.18, 0.89, 0.36, 0.10],
    "shape_y": [0.94, 0.19, 0.37, 0.45, 0.91, 0.30],
    "shape_z": [0.19, 0.28, 0.91, 0.09, 0.18, 0.95]})
COEFFS = pd.DataFrame({"name": ["Ktc", "Krc", "Kac", "Kte", "Kre", "Kae"],
                       "value": [796.0, 167.0, 222.0, 27.7, 30.8, 6.7]})
COEFFS["ci_low"], COEFFS["ci_high"] = COEFFS["value"] * 0.99, COEFFS["value"] * 1.01
K = np.array([1.0e6, 8.0e5, 4.0e5, 5.7e4, 5.1e4, 3.0e4])
JOINTS = pd.DataFrame({"joint": np.arange(1, 7), "k_Nm_rad": K, "ci95_low_Nm_rad": 0.95 * K,
                       "ci95_high_Nm_rad": 1.05 * K, "observable": True})


def run(out_dir: str | Path) -> list[dict]:
    cfg = yaml.safe_load((REPO / "config.yaml").read_text())
    robot = robot_from_mapping(cfg["cell"]["robot"])
    cell = Cell(robot, np.asarray(cfg["cell"]["tool_rotation"], float),
                np.deg2rad(cfg["cell"]["q_home_deg"]), np.array([700.0, -50.0, 200.0]))
    req = parse_request({
        "kind": "plan", "operation": {"length_mm": 40, "directions": ["px"]},
        "tool": {"diameter_mm": 6, "flutes": 2},
        "placement": {"box": {"min_mm": [600, -150, 200], "max_mm": [800, 50, 200],
                              "n": [5, 4, 1]}},
        "rotations_deg": {"min": -55, "max": 55, "n": 12},
        "spindle_rpm": {"min": 10000, "max": 30000, "n": 200},
        "depth_mm": [0.2], "feed_mm_s": [5.0]}, "bench")
    m = Measured(modes=MODES, coefficients=COEFFS, joints=JOINTS)
    t0 = time.perf_counter()
    ds = predict_grid(req, m, cell)
    grid_s = time.perf_counter() - t0
    n_pose = int(ds["reachable"].size)
    # baseline: the single-tool solver once per pose (sample of poses, scaled to the grid)
    cut = CuttingModel(2, 796e6, 167.0 / 796.0, 0.0, np.pi)
    sample = 12
    t0 = time.perf_counter()
    for i in range(sample):
        k = MODES["k_modal_N_m"].to_numpy() * (1 + 0.01 * i)
        tool = tool_from_modes([ModeXY(f, z, kk, (sx, sy)) for f, z, kk, sx, sy in zip(
            MODES["f_n_hz"], MODES["zeta"], k, MODES["shape_x"], MODES["shape_y"],
            strict=True)])
        zoa_lobes(tool, cut, req.spindle_rpm)
    base_s = (time.perf_counter() - t0) / sample * n_pose
    rows = [{"benchmark": "plan", "metric": "candidate grid 20 placements x 12 rotations x "
             "200 speeds, every prediction with its interval", "value": grid_s, "unit": "s",
             "baseline": base_s, "ratio": base_s / grid_s,
             "note": f"{n_pose} poses; goal <= 60 s ({'met' if grid_s <= 60 else 'NOT met'}); "
                     f"baseline: zoa_lobes once per pose, nominal lobes only ({sample} poses "
                     "timed, scaled)"}]
    pd.DataFrame(rows).to_csv(Path(out_dir) / "plan.csv", index=False)
    return rows
