"""Why an out-of-sample prediction missed: each planned cut's outcome that fell outside its
stated interval (``check.csv``: ``in_sample`` false, ``held`` false), with the evidence the
run's own files give and what the prediction did not model (``results/plan/misses.csv``).

A plan that is wrong somewhere is a finding: the explanation says which part of the
prediction the outcome contradicts, from evidence only, never from planted parameters:

* **extrapolated**: the cut lies outside what the study measured (``plan.csv``
  ``extrapolation_reason``); its interval was widened by ``interval_widening``
  (:mod:`robomill.plan.extrapolation`) and still missed;
* **chatter**: the cut was judged to chatter (the run's ``results/chatter/verdicts.csv``) at a
  frequency inside or outside the band the impact test measured (``candidates.nc`` attribute
  ``modal_band_hz``): outside it, the lobes were computed without the mode that chattered;
  a chattering cut's force, deflection and waviness are those of a vibrating chip, which no
  static prediction models;
* **deflection**: with the same cut's force inside its interval, the miss is the tool tip's
  compliance (the outcome's ratio to the prediction is the compliance's ratio): the static
  model C(q) F̄ (:mod:`robomill.plan.tooltip`) carries the modes measured at the test's pose,
  moved by the joint model, and no dynamic deflection of the loaded pass; with the force
  outside its interval, the deflection follows the force;
* **force**: the mean force outside the prediction interval of the coefficient regression
  (:mod:`robomill.forces.prediction`), which assumes the linear chip model (Altintas 2012
  eq. 2.25) with the study's scatter between cuts;
* **waviness**: the gear lines' amplitudes were identified on the study's tracker runs and
  moved to the cut's pose through the Jacobian; the tracker read another amplitude;
* **stability** predicted stable and chattered (or the reverse): the critical depth's
  interval carries the modes', coefficients' and joint stiffness' uncertainty, not a mode or a
  process the study did not measure.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

COLUMNS = ("cut", "quantity", "predicted", "low", "high", "outcome", "ratio", "beyond",
           "causes", "explanation")


def _truthy(s: pd.Series) -> pd.Series:
    return s.astype(str).str.lower().isin(["true", "1", "1.0"])


def _row(frame: pd.DataFrame | None, cut: str) -> dict | None:
    if frame is None or "cut" not in frame:
        return None
    hit = frame[frame["cut"].astype(str) == cut]
    return None if hit.empty else hit.iloc[0].to_dict()


def _band_phrase(f_hz: float, band: tuple[float, float] | None) -> str:
    if band is None or not np.isfinite(f_hz):
        return ""
    lo, hi = band
    if f_hz > hi:
        return (f", above the {lo:.0f}–{hi:.0f} Hz the impact test measured: a mode the lobes "
                "did not have")
    if f_hz < lo:
        return f", below the {lo:.0f}–{hi:.0f} Hz the impact test measured"
    return (f", inside the {lo:.0f}–{hi:.0f} Hz the impact test measured: a measured mode's "
            "limit lower than its interval allowed")


def explain_misses(check: pd.DataFrame, plan: pd.DataFrame | None = None,
                   verdicts: pd.DataFrame | None = None,
                   modal_band_hz: tuple[float, float] | None = None) -> pd.DataFrame:
    """One row per out-of-sample miss of ``check`` (module docstring): ``cut, quantity,
    predicted, low, high, outcome``, ``ratio`` (outcome / predicted), ``beyond`` (``above``
    or ``below`` the interval; for stability the outcome: ``chatter`` or ``stable``),
    ``causes`` (``;``-joined codes: extrapolated, chatter, compliance, force, model) and
    ``explanation`` (one sentence from the evidence). ``plan``: ``plan.csv``; ``verdicts``:
    the planned run's ``results/chatter/verdicts.csv``."""
    if check is None or check.empty:
        return pd.DataFrame(columns=list(COLUMNS))
    oos = check[~_truthy(check["in_sample"]) & check["held"].astype(str).str.lower()
                .eq("false")]
    rows = []
    for r in oos.itertuples(index=False):
        cut, qty = str(r.cut), str(r.quantity)
        pred, out = float(r.predicted), float(r.outcome)
        ratio = out / pred if pred else np.nan
        causes, parts = [], []
        p = _row(plan, cut) or {}
        if str(p.get("extrapolation", "")).lower() in ("true", "1"):
            causes.append("extrapolated")
            parts.append(f"the cut lies outside what the study measured "
                         f"({p.get('extrapolation_reason', '')}), its interval widened "
                         f"{float(p.get('interval_widening', 1.0)):.3g}×")
        v = None
        if verdicts is not None and "cut" in verdicts:
            sel = verdicts[verdicts["cut"].astype(str) == cut]
            ch = sel[sel["verdict"] == "chatter"]
            v = ch.iloc[0].to_dict() if len(ch) else None
        if v is not None:
            f = float(v.get("chatter_hz", np.nan))
            causes.append("chatter")
            parts.append(f"the cut chattered at {f:.0f} Hz{_band_phrase(f, modal_band_hz)}")
        if qty == "stability":
            beyond = "stable" if out >= 0.5 else "chatter"
            if v is None:
                causes.append("model")
                parts.append("the critical depth's interval carries the measured modes', "
                             "the coefficients' and the joints' uncertainty only")
        else:
            beyond = "above" if out > float(r.high) else "below"
            if qty.startswith("deflection") and v is None:
                frow = check[(check["cut"].astype(str) == cut) & (check["quantity"] == "force")]
                if len(frow) and str(frow.iloc[0]["held"]).lower() == "true":
                    causes.append("compliance")
                    along = "normal to the wall" if "normal" in qty else "along the tool axis"
                    f_out, f_pred = (float(frow.iloc[0][k]) for k in ("outcome", "predicted"))
                    parts.append(
                        f"the force was inside its interval ({f_out:.3g} N against "
                        f"{f_pred:.3g} N), so the tool tip's compliance {along}"
                        f" was {ratio:.2g}× the model's: the static C(q)F̄ carries the modes "
                        "measured at the test's pose, moved by the joint model, and no dynamic "
                        "deflection of the loaded pass")
                elif len(frow):
                    causes.append("force")
                    parts.append("the force missed its interval too, and the deflection "
                                 "follows it")
            elif qty == "force" and v is None:
                causes.append("model")
                parts.append(f"the mean force was {ratio:.3g}× the prediction, outside the "
                             "coefficient regression's scatter between the study's cuts "
                             "(linear chip model)")
            elif qty == "waviness" and v is None:
                causes.append("model")
                parts.append(f"the tracker read {ratio:.3g}× the gear lines' amplitude "
                             "identified on the study's runs and moved to this pose by the "
                             "Jacobian")
        text = "; ".join(parts) + "."
        rows.append({"cut": cut, "quantity": qty, "predicted": pred, "low": float(r.low),
                     "high": float(r.high), "outcome": out, "ratio": ratio, "beyond": beyond,
                     "causes": ";".join(causes), "explanation": text[:1].upper() + text[1:]})
    return pd.DataFrame(rows, columns=list(COLUMNS))
