"""The binding interval of a production plan, and how much a learn round narrowed it.

The production plan's binding cut is its largest-removal-rate cut (rank 1). Of the
predictions the request constrains (:data:`robomill.plan.choose.CONSTRAINT_VARS`), the one
that binds it is the one that stops a larger removal rate: at the cut's pose and speed, the
next larger depth of the request's grid (else the next larger feed) breaks it, by the largest
relative excess where several break. Where no larger depth or feed breaks one (the cut is at
the grid's end), it is the one whose pessimistic end lies closest to its limit. Both in the
limit's units relative to the limit:

    slack = (p_pess − L) / |L|   (a lower limit: the stability margin)
    slack = (L − p_pess) / |L|   (an upper limit: deflection, waviness, force)

(the excess is −slack at the larger cut).

Its **binding interval** is that prediction's interval at the binding cut, ``[low, high]``,
of width ``w = high − low`` (the level of ``plan.interval_level``). A learn round (the cuts
of ``purpose: learn`` run, their raw folder added to ``data.raw_dirs``) narrows it by

    narrowing = 1 − w_after / w_before

measured on the same prediction at the same cut: the earlier plan's binding prediction at its
binding cut (the grid point ``i_placement, i_rotation, i_direction, spindle_rpm, depth_mm,
feed_mm_s`` stored in its ``binding.csv``), before and after, so that neither a change of which
constraint binds nor a move of the binding cut passes for a narrowing (``width_same_cut``: the
after width there; the new binding cut's own interval is stated beside it).

Beside it, whatever prediction binds, the **stability interval at the binding cut**: the
critical depth's interval ``[a_crit_low_mm, a_crit_high_mm]`` there (the stability model's
weighted members, :mod:`robomill.plan.stability`; the interval a learn round's verdicts
narrow, :mod:`robomill.plan.learn`), and its narrowing at the same grid point,
``a_crit_narrowing`` = 1 − ``a_crit_width_same_cut_mm`` / the earlier plan's
``a_crit_width_mm``, both widths from the same candidates' variables.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr

from robomill.errors import RawDataError
from robomill.plan.choose import CONSTRAINT_VARS
from robomill.plan.request import PlanRequest

COLUMNS = ("when", "purpose", "cut", "constraint", "prediction", "limit", "low", "high",
           "width", "pessimistic", "slack", "binds", "study_cuts", "raw_folders", "narrowing",
           "i_placement", "i_rotation", "i_direction", "spindle_rpm", "depth_mm", "feed_mm_s",
           "width_same_cut", "a_crit_low_mm", "a_crit_high_mm", "a_crit_width_mm",
           "a_crit_width_same_cut_mm", "a_crit_narrowing")
"""Columns of ``results/plan/binding.csv``."""


def interval_names(checked: str) -> tuple[str, str]:
    """The low and high variables of the prediction whose pessimistic end is ``checked``
    (``stability_margin_low`` → ``stability_margin_low``, ``stability_margin_high``)."""
    if "_low" in checked:
        return checked, checked.replace("_low", "_high", 1)
    return checked.replace("_high", "_low", 1), checked


def _value(ds: xr.Dataset, name: str, row: pd.Series) -> float:
    """Variable ``name`` of the candidates at the chosen cut ``row`` (its grid indices)."""
    v = ds[name]
    at = {d: int(row[f"i_{d}"]) for d in ("placement", "rotation", "direction") if d in v.dims}
    at.update({d: float(row[d]) for d in ("spindle_rpm", "depth_mm", "feed_mm_s")
               if d in v.dims})
    pos = {d: at[d] for d in ("placement", "rotation", "direction") if d in at}
    lab = {d: at[d] for d in ("spindle_rpm", "depth_mm", "feed_mm_s") if d in at}
    return float(v.isel(pos).sel(lab).values)


def _slacks(ds: xr.Dataset, req: PlanRequest, row: pd.Series) -> dict[str, float]:
    """Relative slack of each constrained prediction's pessimistic end at ``row``."""
    out = {}
    for key, (name, kind, _) in CONSTRAINT_VARS.items():
        lim = req.constraints.get(key)
        if lim is None or name not in ds:
            continue
        pess = _value(ds, name, row)
        out[key] = ((pess - lim) if kind == "min" else (lim - pess)) / max(abs(float(lim)),
                                                                          1e-12)
    return out


def limiting_constraint(ds: xr.Dataset, req: PlanRequest, row: pd.Series
                        ) -> tuple[str, str] | None:
    """The constraint the next larger depth (else feed) of the grid breaks at ``row``'s pose
    and speed, by the largest relative excess, and where (``depth_mm=0.3``); None where no
    larger one breaks any."""
    for dim in ("depth_mm", "feed_mm_s"):
        if dim not in ds.coords:
            continue
        grid = np.asarray(ds[dim].values, float)
        larger = grid[grid > float(row[dim]) + 1e-12]
        if not larger.size:
            continue
        nxt = row.copy()
        nxt[dim] = float(larger.min())
        broken = {k: -v for k, v in _slacks(ds, req, nxt).items() if np.isfinite(v) and v < 0}
        if broken:
            return max(broken, key=broken.get), f"{dim}={nxt[dim]:g}"
    return None


def binding_interval(ds: xr.Dataset, req: PlanRequest, row: pd.Series,
                     constraint: str | None = None) -> dict[str, object]:
    """The binding prediction's interval at the production plan's binding cut ``row`` (a row
    of the chosen table, with its ``i_placement``/``i_rotation``/``i_direction`` indices):
    the constraint a larger removal rate breaks (:func:`limiting_constraint`), else the one
    with the least slack, or the given ``constraint`` (the earlier plan's, for a narrowing
    measured on the same prediction); ``binds`` says which. Empty without a constrained
    prediction."""
    binds = "given"
    if constraint is None:
        found = limiting_constraint(ds, req, row)
        constraint, binds = found if found else (None, "closest to its limit")
    best = None
    for key, (name, kind, what) in CONSTRAINT_VARS.items():
        lim = req.constraints.get(key)
        if lim is None or name not in ds or (constraint and key != constraint):
            continue
        lo_name, hi_name = interval_names(name)
        if lo_name not in ds or hi_name not in ds:
            continue
        pess = _value(ds, name, row)
        slack = ((pess - lim) if kind == "min" else (lim - pess)) / max(abs(float(lim)), 1e-12)
        lo, hi = _value(ds, lo_name, row), _value(ds, hi_name, row)
        cand = {"cut": str(row["cut"]), "constraint": key, "prediction": what,
                "limit": float(lim), "low": lo, "high": hi, "width": hi - lo,
                "pessimistic": pess, "slack": float(slack), "binds": binds,
                **{f"i_{d}": int(row[f"i_{d}"]) for d in ("placement", "rotation", "direction")
                   if pd.notna(row.get(f"i_{d}"))},
                **{d: float(row[d]) for d in ("spindle_rpm", "depth_mm", "feed_mm_s")
                   if pd.notna(row.get(d))}}
        if best is None or cand["slack"] < best["slack"]:
            best = cand
    if best:
        best.update(stability_at(ds, row))
    return best or {}


def stability_at(ds: xr.Dataset, row: pd.Series) -> dict[str, float]:
    """The critical depth's interval at ``row``'s grid point (``a_crit_low_mm``,
    ``a_crit_high_mm``, ``a_crit_width_mm``; NaN without a stability prediction)."""
    try:
        lo, hi = _value(ds, "a_crit_low_mm", row), _value(ds, "a_crit_high_mm", row)
    except (KeyError, IndexError, ValueError):
        lo = hi = float("nan")
    return {"a_crit_low_mm": lo, "a_crit_high_mm": hi, "a_crit_width_mm": hi - lo}


def same_cut_width(ds: xr.Dataset, req: PlanRequest, before: pd.DataFrame | None
                   ) -> float:
    """The width now of the earlier plan's binding prediction at its binding cut (the grid
    point its ``binding.csv`` stores); NaN without one, or where that point is not on this
    plan's grid (another request)."""
    if before is None or before.empty:
        return float("nan")
    b = before.iloc[-1]
    need = [f"i_{d}" if d in ("placement", "rotation", "direction") else d
            for d in ("placement", "rotation", "direction", "spindle_rpm", "depth_mm",
                      "feed_mm_s") if d in ds.dims]
    if not need or not all(k in b.index and pd.notna(b[k]) for k in need):
        return float("nan")
    b = b.copy()
    for d in ("spindle_rpm", "depth_mm", "feed_mm_s"):  # on this grid, else another request
        if d in ds.dims:  # (the CSV keeps 6 significant digits: the grid value it rounds)
            grid = np.asarray(ds[d].values, float)
            near = np.isclose(grid, float(b[d]), rtol=1e-5)
            if not near.any():
                return float("nan")
            b[d] = float(grid[np.argmax(near)])
    try:
        got = binding_interval(ds, req, b, str(b["constraint"]))
    except (KeyError, IndexError, ValueError):
        return float("nan")
    return float(got["width"]) if got else float("nan")


def same_cut_stability_width(ds: xr.Dataset, req: PlanRequest, before: pd.DataFrame | None
                             ) -> float:
    """The width now [mm] of the critical depth's interval at the earlier plan's binding cut
    (as :func:`same_cut_width`); NaN where that cut is not on this grid."""
    if before is None or before.empty or not np.isfinite(same_cut_width(ds, req, before)):
        return float("nan")
    b = before.iloc[-1].copy()
    for d in ("spindle_rpm", "depth_mm", "feed_mm_s"):
        if d in ds.dims:
            grid = np.asarray(ds[d].values, float)
            b[d] = float(grid[np.argmax(np.isclose(grid, float(b[d]), rtol=1e-5))])
    return float(stability_at(ds, b)["a_crit_width_mm"])


def binding_table(now: dict[str, object], purpose: str, study_cuts: int, raw_folders: int,
                  before: pd.DataFrame | None = None) -> pd.DataFrame:
    """``results/plan/binding.csv``: the row ``now`` (this plan's binding interval, with
    ``width_same_cut`` from :func:`same_cut_width`) and, where an earlier plan's
    ``binding.csv`` is given, its ``now`` row as ``before``; ``narrowing``
    1 − width_same_cut / w_before on the row ``now`` (NaN without an earlier plan or its
    binding cut on this grid)."""
    rows = []
    narrowing = np.nan
    if before is not None and not before.empty:
        b = before.iloc[-1].to_dict()
        b.update({"when": "before", "narrowing": np.nan})
        rows.append(b)
        w_same = float(now.get("width_same_cut", np.nan))
        if np.isfinite(w_same) and float(b["width"]) > 0:
            narrowing = 1.0 - w_same / float(b["width"])
        a_same = float(now.get("a_crit_width_same_cut_mm", np.nan))
        a_before = float(b.get("a_crit_width_mm", np.nan))
        if np.isfinite(a_same) and np.isfinite(a_before) and a_before > 0:
            now = {**now, "a_crit_narrowing": 1.0 - a_same / a_before}
    rows.append({"when": "now", "purpose": purpose, **now, "study_cuts": int(study_cuts),
                 "raw_folders": int(raw_folders), "narrowing": narrowing})
    return pd.DataFrame(rows).reindex(columns=list(COLUMNS))


def read_before(path: str | Path) -> pd.DataFrame:
    """An earlier plan's ``binding.csv`` (config ``plan.binding_before``).

    Raises
    ------
    RawDataError
        One line when the file cannot be read or lacks the columns of :data:`COLUMNS`.
    """
    try:
        t = pd.read_csv(path)
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise RawDataError(path, f"cannot read ({' '.join(str(exc).split())})",
                           where="plan.binding_before",
                           expected="results/plan/binding.csv of an earlier plan") from None
    missing = [c for c in ("constraint", "width", "low", "high") if c not in t]
    if missing or t.empty:
        raise RawDataError(path, f"no binding interval (missing {', '.join(missing) or 'rows'})",
                           where="plan.binding_before",
                           expected="results/plan/binding.csv of an earlier plan")
    return t


def binding_values(table: pd.DataFrame) -> dict[str, object]:
    """What chapter 7 states about the binding interval (``binding.csv``): this plan's
    binding prediction, cut, interval and width, the study's cuts and raw folders; with an
    earlier plan's row its interval and width and the narrowing [%]. ``binding_case``:
    ``narrowed`` (an earlier plan's row, same prediction), ``changed`` (an earlier row whose
    prediction no longer is the one measured), ``now`` (no earlier plan) or ``none`` (no
    constrained prediction at the binding cut). The critical depth's interval at the earlier
    binding cut, before and now at the same cut (``a_crit_narrowing_pct``), with
    ``stability_case``: ``binds`` (the stability constraint binds), ``beside`` (another
    prediction binds: the stability interval is the one a learn round's verdicts narrow) or
    ``none`` (no earlier plan or no critical depth there)."""
    now = table[table["when"] == "now"]
    if now.empty or not isinstance(now["constraint"].iloc[-1], str):
        return {"binding_case": "none"}
    r = now.iloc[-1]
    out = {k: r[k] for k in ("purpose", "cut", "constraint", "prediction")}
    out.update({k: float(r[k]) for k in ("low", "high", "width", "limit")})
    out.update({"study_cuts": int(r["study_cuts"]), "raw_folders": int(r["raw_folders"])})
    for k in ("a_crit_low_mm", "a_crit_high_mm", "a_crit_width_mm"):
        out[k] = float(r[k]) if k in r.index and pd.notna(r[k]) else float("nan")
    out["stability_case"] = "none"
    before = table[table["when"] == "before"]
    if before.empty:
        out["binding_case"] = "now"
        return out
    b = before.iloc[-1]
    out.update({"before_low": float(b["low"]), "before_high": float(b["high"]),
                "before_width": float(b["width"]), "before_cut": b["cut"],
                "width_same_cut": float(r.get("width_same_cut", np.nan)),
                "before_study_cuts": int(b["study_cuts"]),
                "before_constraint": b["constraint"]})
    if np.isfinite(float(r["narrowing"])):
        out["narrowing_pct"] = 100.0 * float(r["narrowing"])
        out["binding_case"] = "narrowed"
    else:
        out["binding_case"] = "changed"
    def num(row, key):
        return float(row[key]) if key in row.index and pd.notna(row[key]) else float("nan")

    if np.isfinite(num(b, "a_crit_width_mm")) and np.isfinite(num(r, "a_crit_narrowing")):
        out.update({"before_a_crit_low_mm": num(b, "a_crit_low_mm"),
                    "before_a_crit_high_mm": num(b, "a_crit_high_mm"),
                    "before_a_crit_width_mm": num(b, "a_crit_width_mm"),
                    "a_crit_width_same_cut_mm": num(r, "a_crit_width_same_cut_mm"),
                    "a_crit_narrowing_pct": 100.0 * num(r, "a_crit_narrowing")})
        out["stability_case"] = ("binds" if b["constraint"] in ("min_stability_margin",
                                                                "min_p_stable")
                                 else "beside")
    return out
