"""Sensitivity of the hexapod's open-loop motion to actuator force errors (Rybak n.d.,
§ sensitivity): the drift map gathered from the per-actuator shards with its first-order
slopes, the force accuracy a position tolerance needs, and how far the map is from
antisymmetry. Pure functions on the map (the runs themselves:
:func:`robomill.hexapod.motion.force_error_drift`). Millimetres, degrees, percent.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    import pandas as pd


def gather_sensitivity(shards: Sequence[Any]) -> Any:
    """Concatenate per-actuator shards into the ``actuator × force_error_pct`` map; adds the
    first-order slopes (mm and deg per % of force error, least squares through zero)."""
    import xarray as xr

    ds = xr.concat(list(shards), dim="actuator").sortby("actuator")
    e = ds["force_error_pct"]
    for name, unit, long in (("drift_components_mm", "mm/%", "position drift per % error"),
                             ("rotvec_deg", "deg/%", "rotation per % error")):
        slope = (ds[name] * e).sum("force_error_pct") / (e**2).sum()
        ds[name.replace("_mm", "").replace("_deg", "") + "_per_pct"] = slope.assign_attrs(
            units=unit, long_name=f"first-order {long}")
    ds.attrs = dict(shards[0].attrs)
    return ds


#: position tolerances [mm] for which :func:`force_accuracy_requirement` states the force
#: accuracy needed (the chapter's table; results/hexapod/force_accuracy.csv)
FORCE_ACCURACY_TOLERANCES_MM = (0.005, 0.01, 0.05, 0.1)


def force_accuracy_requirement(sensitivity: Any, actuator_force_N: float,
                               tolerances_mm: Sequence[float] = FORCE_ACCURACY_TOLERANCES_MM
                               ) -> pd.DataFrame:
    """Force accuracy an open-loop move needs to end within a position tolerance.

    To first order the vertical move's final drift is linear in an actuator's force error,
    ``d = s_i · e`` with ``s_i = |Σ_e d_i(e) e / Σ_e e²|`` mm per % (the slope
    ``drift_components_per_pct`` of :func:`gather_sensitivity`, least squares through zero).
    A tolerance ``δ`` on the final position therefore needs every actuator's force right to
    ``e_max = δ / max_i s_i`` %, i.e. ``e_max / 100 · Γ`` newton for an actuator force ``Γ``
    (Rybak n.d., § sensitivity: "a small error in the force loop gives a large path error").

    Parameters
    ----------
    sensitivity
        The gathered map (``results/hexapod/sensitivity.nc``).
    actuator_force_N
        The actuator force of the move (``forces.nc::vertical_force_N`` at the start).
    tolerances_mm
        Position tolerances δ [mm].

    Returns
    -------
    DataFrame
        One row per tolerance: ``position_tolerance_mm``, ``force_accuracy_pct``,
        ``force_accuracy_mN``, ``worst_actuator``, ``drift_mm_per_pct`` (the worst slope),
        ``duration_s`` (of the move).
    """
    import pandas as pd

    tol = np.asarray(tolerances_mm, float)
    if tol.ndim != 1 or tol.size == 0 or not np.all(tol > 0):
        raise ValueError(f"tolerances_mm must be positive, got {tolerances_mm!r}")
    if not actuator_force_N > 0:
        raise ValueError(f"actuator_force_N must be positive, got {actuator_force_N!r}")
    slope = np.linalg.norm(np.asarray(sensitivity["drift_components_per_pct"].values), axis=-1)
    worst = int(np.argmax(slope))
    pct = tol / slope[worst]
    return pd.DataFrame({
        "position_tolerance_mm": tol,
        "force_accuracy_pct": pct,
        "force_accuracy_mN": pct / 100 * float(actuator_force_N) * 1e3,
        "worst_actuator": int(sensitivity["actuator"].values[worst]),
        "drift_mm_per_pct": float(slope[worst]),
        "duration_s": float(sensitivity.attrs.get("duration_s", np.nan)),
    })


def drift_antisymmetry(sensitivity: Any) -> tuple[float, float] | None:
    """How far the drift map is from first-order antisymmetry.

    For the smallest error ``e`` present with both signs, ``max_i |d_i(+e) + d_i(−e)| /
    |d_i(+e)|`` (zero for a map linear in the error). Returns ``(e, fraction)``, or None
    when no error is present with both signs.
    """
    e = np.asarray(sensitivity["force_error_pct"].values, float)
    both = e[(e > 0) & np.isin(-e, e)]
    if both.size == 0:
        return None
    ep = float(both.min())
    pair = sensitivity["drift_components_mm"]
    plus = pair.sel(force_error_pct=ep).values
    minus = pair.sel(force_error_pct=-ep).values
    frac = np.linalg.norm(plus + minus, axis=-1) / np.linalg.norm(plus, axis=-1)
    return ep, float(frac.max())
