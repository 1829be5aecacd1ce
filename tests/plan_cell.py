"""The default cell as the planner sees it, and a table of cutting coefficients with narrow
intervals: the common ground of the planner's unit tests (one direction measured, extrapolation)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import yaml

from robomill.kinematics import robot_from_mapping
from robomill.plan.predict import Cell

REFERENCE_POINT_MM = (650.0, 0.0, 200.0)


def default_cell(config_path: str = "config.yaml") -> Cell:
    """The planner's :class:`Cell` of ``config.yaml``'s robot, tool rotation and home posture,
    with its reference pose at :data:`REFERENCE_POINT_MM`."""
    with open(config_path) as f:
        cfg = yaml.safe_load(f)["cell"]
    return Cell(robot_from_mapping(cfg["robot"]), np.asarray(cfg["tool_rotation"], float),
                np.deg2rad(cfg["q_home_deg"]), np.array(REFERENCE_POINT_MM))


def coefficients(ktc: float = 800.0, krc: float = 240.0, *, rel: float = 0.01) -> pd.DataFrame:
    """A force fit's table (``name``, ``value``, ``ci_low``, ``ci_high``): the given cutting
    coefficients [N/mm²], fixed edge and axial ones, each interval ±``rel`` of the value."""
    rows = [("Ktc", ktc), ("Krc", krc), ("Kac", 200.0), ("Kte", 25.0), ("Kre", 30.0),
            ("Kae", 6.0)]
    return pd.DataFrame({"name": [r[0] for r in rows], "value": [r[1] for r in rows],
                         "ci_low": [r[1] * (1 - rel) for r in rows],
                         "ci_high": [r[1] * (1 + rel) for r in rows]})
