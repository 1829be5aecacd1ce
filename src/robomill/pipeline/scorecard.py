"""The reproduction scorecard: every number the source documents print, beside ours.

The checks live in ``robomill/data/scorecard.yaml``. Each names the source number by its key
in ``robomill/data/references.yaml`` (value, unit and citation live there once, read by
:mod:`robomill.references`) and a *locator* of our value in an artefact,
``<path>::<column or variable>[<key>=<value>,…]@<agg>``:

* ``results/modal/modes.csv::f_n_hz[mode=3]`` — one cell of a table;
* ``results/forces/peaks.csv::dominant_hz@median`` — an aggregate over a column
  (``min, max, mean, median`` of the values present, an empty (NaN) one left out; ``count``
  and ``frac_in(a,b)`` of all rows);
* ``results/hexapod/sensitivity.nc::drift_mm[actuator=1,force_error_pct=1.0]`` — a netCDF
  variable at a selection.

``ours`` is always read from the artefact (never typed in); the verdict compares it with the
source value within the stated tolerance; ``reason`` explains every miss.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import yaml

from robomill import references

_LOC = re.compile(r"^(?P<path>[^:]+)::(?P<field>[\w.]+)(?:\[(?P<sel>[^\]]*)\])?"
                  r"(?:@(?P<agg>\w+)(?:\((?P<args>[^)]*)\))?)?$")


def _value(text: str) -> Any:
    try:
        return float(text) if any(c in text for c in ".eE") else int(text)
    except ValueError:
        return text


def parse_locator(locator: str) -> dict[str, Any]:
    m = _LOC.match(locator.strip())
    if not m:
        raise ValueError(f"bad locator {locator!r}: expected path::field[key=value]@agg")
    sel = {}
    if m["sel"]:
        for item in m["sel"].split(","):
            k, _, v = item.partition("=")
            sel[k.strip()] = _value(v.strip())
    args = [float(a) for a in m["args"].split(",")] if m["args"] else []
    return {"path": m["path"], "field": m["field"], "sel": sel, "agg": m["agg"], "args": args}


def _aggregate(values: np.ndarray, agg: str | None, args: list[float]) -> float:
    values = np.asarray(values, dtype=float).ravel()
    if agg is None:
        if values.size != 1:
            raise ValueError(f"locator selects {values.size} values; add a selection or @agg")
        return float(values[0])
    if agg == "frac_in":
        lo, hi = args
        return float(np.mean((values >= lo) & (values <= hi)))
    if agg in ("min", "max", "mean", "median"):  # an empty value (no peak) is not a value
        values = values[~np.isnan(values)]
        if values.size == 0:
            return float("nan")
    funcs = {"min": np.min, "max": np.max, "mean": np.mean, "median": np.median,
             "count": np.size}
    return float(funcs[agg](values))


def read_locator(locator: str, root: str | Path = ".") -> float:
    """The value a locator points at, read from the artefact under ``root``."""
    loc = parse_locator(locator)
    path = Path(root) / loc["path"]
    if path.suffix == ".csv":
        df = pd.read_csv(path)
        for k, v in loc["sel"].items():
            df = df[df[k] == v]
        if loc["field"] not in df.columns:
            raise LookupError(f"{locator}: no column {loc['field']!r} in this run")
        values = df[loc["field"]].to_numpy()
    else:
        import xarray as xr

        with xr.open_dataset(path, engine="h5netcdf") as ds:
            if loc["field"].startswith("attrs."):
                values = np.atleast_1d(ds.attrs[loc["field"].removeprefix("attrs.")])
            else:
                da = ds[loc["field"]]
                if loc["sel"]:
                    da = da.sel(loc["sel"])
                values = da.values
    if np.size(values) == 0:
        raise LookupError(f"{locator}: the selection is empty in this run")
    return _aggregate(values, loc["agg"], loc["args"])


def verdict(ours: float, source_value: Any, tolerance: Mapping[str, float] | None) -> bool:
    """Whether ``ours`` reproduces ``source_value``.

    ``source_value`` is a number or ``[low, high]``; ``tolerance`` is ``{rel: r}`` (|Δ| ≤ r·|s|),
    ``{abs: a}``, or ``{factor: f}`` (within a factor f either way).
    """
    if ours is None or (isinstance(ours, float) and math.isnan(ours)):
        return False
    if isinstance(source_value, list | tuple):
        lo, hi = source_value
        pad = (tolerance or {}).get("abs", 0.0)
        return lo - pad <= ours <= hi + pad
    tol = tolerance or {"rel": 0.0}
    if "rel" in tol:
        return abs(ours - source_value) <= tol["rel"] * abs(source_value)
    if "abs" in tol:
        return abs(ours - source_value) <= tol["abs"]
    if "factor" in tol:
        if ours <= 0 or source_value <= 0:
            return False
        return max(ours / source_value, source_value / ours) <= tol["factor"]
    raise ValueError(f"unknown tolerance {tol}")


def _tolerance_text(tol: Mapping[str, float] | None, source_value: Any) -> str:
    if isinstance(source_value, list | tuple):
        return "within range" + (f" ± {tol['abs']}" if tol and "abs" in tol else "")
    if not tol:
        return "exact"
    (k, v), = tol.items()
    return {"rel": f"± {100 * v:g} %", "abs": f"± {v:g}", "factor": f"factor {v:g}"}[k]


def resolve_reference(check: Mapping[str, Any]) -> dict[str, Any]:
    """A check with its source number filled in from references.yaml: ``reference: <key>``
    brings ``source``, ``where``, ``quantity``, ``unit`` and ``source_value``; fields the check
    states itself are kept (a check written in full needs no reference)."""
    out = dict(check)
    if "reference" in check:
        ref = references.reference(check["reference"])
        for field in ("source", "where", "quantity", "unit"):
            out.setdefault(field, ref[field])
        out.setdefault("source_value", ref["value"])
    return out


def load_checks() -> list[dict[str, Any]]:
    text = resources.files("robomill.data").joinpath("scorecard.yaml").read_text()
    return [resolve_reference(c) for c in yaml.safe_load(text)["checks"]]


SCORECARD_COLUMNS = ["source", "where", "quantity", "source_value", "ours", "unit",
                     "tolerance", "verdict", "reason", "artefact"]


def build_scorecard(root: str | Path = ".", checks: list[dict] | None = None, *,
                    thesis_study: bool = True) -> pd.DataFrame:
    """The scorecard table for the artefacts under ``root``; checks whose artefact does not
    exist in this run (a chapter not built) are left out. For a study that is not the
    thesis' design (``thesis_study`` false, :func:`robomill.experiment.is_thesis_study`) the
    thesis' numbers do not apply: only the reference studies' checks (``any_study: true``,
    chapter 6: computed from the configuration alone) remain, possibly none (same columns)."""
    rows = []
    for c in checks if checks is not None else load_checks():
        if not (thesis_study or c.get("any_study")):
            continue
        c = resolve_reference(c)
        sv = c["source_value"]
        if c.get("locator") is None:  # a source number the pipeline does not compute
            rows.append({"source": c["source"], "where": c["where"], "quantity": c["quantity"],
                         "source_value": sv, "ours": np.nan, "unit": c.get("unit", ""),
                         "tolerance": "", "verdict": "not computed",
                         "reason": c.get("reason", ""), "artefact": ""})
            continue
        path = Path(root) / parse_locator(c["locator"])["path"]
        if not path.exists():
            continue  # its chapter is not part of this run
        try:
            ours = read_locator(c["locator"], root)
        except (LookupError, KeyError):
            continue  # e.g. a table cell of a set the run does not have (tiny config)
        ok = verdict(ours, sv, c.get("tolerance"))
        rows.append({
            "source": c["source"], "where": c["where"], "quantity": c["quantity"],
            "source_value": f"{sv[0]:g}–{sv[1]:g}" if isinstance(sv, list) else sv,
            "ours": ours, "unit": c.get("unit", ""),
            "tolerance": _tolerance_text(c.get("tolerance"), sv),
            "verdict": "pass" if ok else "miss",
            "reason": c.get("reason", "") if not ok else c.get("note", ""),
            "artefact": c["locator"],
        })
    return pd.DataFrame(rows, columns=SCORECARD_COLUMNS)


def stage_checks(stage: str) -> list[dict[str, Any]]:
    """The checks whose artefact lies under ``results/<stage>/``."""
    return [c for c in load_checks()
            if (c.get("locator") or "").startswith(f"results/{stage}/")]


def stage_comparisons(stage: str, root: str | Path = ".", *,
                      thesis_study: bool = True) -> list[dict[str, Any]]:
    """The scorecard rows of one stage as a findings artefact's ``comparisons`` (the rows of
    a chapter's "Against the thesis" section, :func:`robomill.findings.comparison_rows`);
    for a study that is not the thesis' design, only the reference studies' rows."""
    from robomill.findings import comparison_rows

    card = build_scorecard(root, stage_checks(stage), thesis_study=thesis_study)
    return comparison_rows(card.to_dict("records"))
