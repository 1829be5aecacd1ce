"""Stiffness of the robot along the cuts of the experiment: per cut along its feed, its
in-plane normal and the tool axis, and the chapter's slot table beside the waviness of
Table 2.1 (thesis §5, Yi 2025).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from robomill.kinematics import SerialRobot
from robomill.stiffness.model import (
    directional_stiffness_N_m,
    jacobian_m,
    translational_compliance_m_N,
)


def cut_stiffness_table(robot: SerialRobot, compliance: np.ndarray, cuts,
                        q_mid_rad: np.ndarray) -> pd.DataFrame:
    """Joint-model stiffness of the cell's robot at the middle of every cut, along the cut's
    feed, its in-plane normal and the tool axis (:func:`robomill.experiment.cut_axes`).

    The translational compliance C = J diag(c) Jᵀ ([Yi 2025, eq. 3]; only the joints' elastic
    deflection) gives the stiffness along a unit direction u as 1 / (uᵀ C u)
    (:func:`directional_stiffness_N_m`). Any design: the direction comes from ``direction``
    or ``direction_deg``.

    Parameters
    ----------
    robot
        The cell's robot (``cell.yaml: robot``).
    compliance
        Joint compliances c_i [rad/(N·m)]
        (:func:`~robomill.stiffness.model.compliance_from_table`).
    cuts
        :class:`robomill.experiment.Cut` objects.
    q_mid_rad
        ``(len(cuts), n)`` posture at each cut's middle.

    Returns
    -------
    pandas.DataFrame
        One row per cut: ``cut``, ``k_feed_N_m``, ``k_normal_N_m``, ``k_axial_N_m``.
    """
    from robomill.experiment import cut_axes

    rows = []
    for cut, q in zip(cuts, np.asarray(q_mid_rad, float), strict=True):
        C = translational_compliance_m_N(jacobian_m(robot, q), compliance)
        k = directional_stiffness_N_m(C, cut_axes(cut))
        rows.append({"cut": cut.id, "k_feed_N_m": k[0], "k_normal_N_m": k[1],
                     "k_axial_N_m": k[2]})
    return pd.DataFrame(rows, columns=["cut", "k_feed_N_m", "k_normal_N_m", "k_axial_N_m"])


def slot_stiffness_table(slots: pd.DataFrame, waviness: pd.DataFrame) -> pd.DataFrame:
    """Mean directional stiffness per model and slot direction beside the mean waviness.

    Parameters
    ----------
    slots
        ``results/stiffness/slots.csv``-like table: ``model, direction, k_feed_N_m,
        k_normal_N_m, k_axial_N_m`` per slot pose.
    waviness
        Table 2.1 (``results/surface/table_2_1_waviness_rms.csv``, index ``segment``),
        columns ``s<set>_<direction>`` [µm].

    Returns
    -------
    pandas.DataFrame
        Index ``(model, direction)``; ``k feed N/µm, k normal N/µm, k axial N/µm`` (means,
        rounded to 3 decimals) and ``waviness RMS µm (Table 2.1, mean)`` (mean over the sets
        and segments of that direction; NaN when Table 2.1 has none).
    """
    mean_k = (slots.groupby(["model", "direction"])[["k_feed_N_m", "k_normal_N_m",
                                                     "k_axial_N_m"]].mean() / 1e6).round(3)
    mean_k.columns = ["k feed N/µm", "k normal N/µm", "k axial N/µm"]
    wq = waviness_by_direction(waviness)
    mean_k["waviness RMS µm (Table 2.1, mean)"] = [
        wq.get(d, np.nan) for d in mean_k.index.get_level_values(1)]
    return mean_k


def waviness_by_direction(waviness: pd.DataFrame,
                          directions: tuple[str, ...] = ("px", "py", "my")) -> dict[str, float]:
    """Mean of Table 2.1's cells per direction (columns ending ``_<direction>``) [µm];
    NaN for a direction without columns."""
    out = {}
    for d in directions:
        vals = waviness[[c for c in waviness.columns if c.endswith("_" + d)]].to_numpy(float)
        out[d] = float(np.nanmean(vals)) if vals.size else float("nan")
    return out


def stiffness_spread_pct(values: pd.Series, a: str = "py", b: str = "my") -> float:
    """Relative difference ``100 (k_a − k_b)/k_b`` [%] of two slot directions' stiffness
    (thesis §5: the ±Y slots share their normal direction); NaN if either is missing."""
    ka, kb = values.get(a, np.nan), values.get(b, np.nan)
    return float(100 * (ka - kb) / kb)
