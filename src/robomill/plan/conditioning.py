"""The stability model conditioned on the study's own chatter verdicts: the members of
:mod:`robomill.plan.stability` weighted by the likelihood of the verdicts.

**The prior.** The stability model's members (a bootstrap of the modes, the joint stiffness,
the cutting coefficients and the prior of the modes above the impact test's band) each give a
critical depth a_m(i) at the study's cut i (its own pose, direction and speed).

**The evidence.** A cut of depth d_i with a verdict (``results/chatter/verdicts.csv``,
combined over its recordings by :func:`robomill.plan.evidence.verdict_stability`) is
predicted stable by member m when a_m(i) > d_i. With the stated verdict error rate ε
(``plan.yaml: stability.verdict_error``) the likelihood of the verdicts is
L_m = Π_i (1 − ε)^[agree] ε^[disagree], and the members' weights are L_m/ΣL
(:func:`robomill.plan.stability.verdict_weights`; Bayesian updating of stability lobes,
[Karandikar et al. 2014]). Unlike a set-membership update, a verdict that every member
contradicts does not empty the set: it multiplies every weight by ε and so changes nothing,
and the table says which cuts the prior interval does not admit (``prior_admits``,
``outside_factor`` = d_i / a⁺(i) for a stable cut above the interval's highest limit,
a⁻(i)/d_i for a chattering cut below its lowest).

Karandikar 2014: Karandikar, J.; Traverso, M.; Abbas, A.; Schmitz, T. Bayesian inference for
milling stability using a random walk approach. *J. Manuf. Sci. Eng.* 136(3), 031015, 2014.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from robomill.plan.stability import VerdictEvidence, p_stable, verdict_weights

EVIDENCE_COLUMNS = ("cut", "verdict", "spindle_rpm", "depth_mm", "a_crit_low_mm",
                    "a_crit_high_mm", "prior_admits", "outside_factor", "used", "why", "source",
                    "a_crit_mm", "p_stable_prior", "p_stable")
"""Columns of ``results/plan/evidence_used.csv``."""


def contradiction_note(table: pd.DataFrame) -> str:
    """One line when the prior interval does not admit some verdicts (else "")."""
    v = evidence_values(table, {})
    if not v["n_contradicting"]:
        return ""
    return (f"stability evidence: {v['n_contradicting']} of the {v['n_used']} evidence cuts "
            f"lie outside the prior interval (e.g. {v['worst']}): the model misses them "
            "whatever its members")


def worst_contradiction(table: pd.DataFrame) -> str:
    """The evidence cut whose verdict lies farthest outside the prior interval, in words
    (``s2_g4_px stable at 0.5 mm where the interval's highest limit is 0.171 mm``); "" when
    the prior interval admits every verdict."""
    used = table[table["used"].astype(str).str.lower().isin(["true", "1"])]
    bad = used[~used["prior_admits"].astype(str).str.lower().isin(["true", "1"])]
    if not len(bad):
        return ""
    r = bad.iloc[int(np.nanargmax(bad["outside_factor"].to_numpy(float)))]
    end, val = (("highest", r["a_crit_high_mm"]) if r["verdict"] == "stable"
                else ("lowest", r["a_crit_low_mm"]))
    return (f"{r['cut']} {r['verdict']} at {r['depth_mm']:g} mm where the interval's {end} "
            f"limit is {val:.3g} mm")


def evidence_values(table: pd.DataFrame, attrs: Mapping) -> dict:
    """What chapter 7 states about the evidence (``results/plan/evidence_used.csv`` and the
    ``stability_*`` attributes of ``candidates.nc``): ``n_verdicts`` (cuts with a verdict),
    ``n_used``, ``n_stable``, ``n_chatter`` (of those used), ``n_left_out`` (undetermined or
    no prediction), ``n_contradicting`` (used, outside the prior interval), ``members``,
    ``members_kept``, ``worst`` (:func:`worst_contradiction`), ``model_error_factor`` (the
    largest ``outside_factor``: by how much the interval would have to stretch, as a factor on
    the critical depth, to admit every verdict; 1 when it admits them),
    ``verdict_error_percent`` and ``evidence_case``: ``conditioned`` (the prior interval
    admits every verdict), ``contradicted`` (some verdicts lie outside it) or ``none`` (no
    verdict entered)."""
    def flag(col):
        return table[col].astype(str).str.lower().isin(["true", "1"]) if len(table) else \
            pd.Series(dtype=bool)

    used = flag("used")
    u = table[used] if len(table) else table
    out = {"n_verdicts": len(table), "n_used": int(used.sum()),
           "n_stable": int((u["verdict"] == "stable").sum()) if len(u) else 0,
           "n_chatter": int((u["verdict"] == "chatter").sum()) if len(u) else 0,
           "n_left_out": int(len(table) - used.sum()),
           "n_contradicting": int((~flag("prior_admits")[used]).sum()) if len(u) else 0,
           "members": int(attrs.get("stability_members", 0)),
           "members_kept": int(attrs.get("stability_members_kept", 0)),
           "verdict_error_percent": 100 * float(attrs.get("stability_verdict_error", np.nan)),
           "worst": worst_contradiction(table) if len(table) else "",
           "model_error_factor": float(u["outside_factor"].astype(float).max())
           if len(u) else 1.0}
    out["evidence_case"] = ("none" if not out["n_used"] else
                            "contradicted" if out["n_contradicting"] else "conditioned")
    return out


def study_evidence(rows: Sequence[Mapping], a_members_m: np.ndarray, level: float,
                   error_rate: float, source: str = "") -> VerdictEvidence:
    """The members' weights from the study's cuts.

    Parameters
    ----------
    rows
        One mapping per cut with a verdict: ``cut``, ``verdict`` (``stable`` | ``chatter`` |
        ``undetermined``), ``spindle_rpm``, ``depth_mm``; ``why`` (optional) a reason the cut
        cannot enter (unreachable: no prediction there).
    a_members_m
        ``(E, n)`` each member's critical depth [m] at each cut (NaN where none).
    level
        The interval's two-sided level.
    error_rate
        The assumed rate of a wrong verdict ε.
    source
        Where the verdicts come from (``results/chatter/verdicts.csv``).
    """
    from robomill.plan.stability import summary

    a = np.asarray(a_members_m, float).reshape(-1, len(rows))
    E = a.shape[0]
    flat = np.full(E, 1.0 / E)
    table = []
    for j, r in enumerate(rows):
        d = float(r["depth_mm"])
        col = a[:, j]
        known = col.size > 0 and not np.isnan(col).any()
        sm = summary(col[:, None], flat, level) if known else None
        lo = float(sm["low"][0]) * 1e3 if known else np.nan
        hi = float(sm["high"][0]) * 1e3 if known else np.nan
        why = str(r.get("why") or "")
        if not why and r["verdict"] == "undetermined":
            why = "verdict undetermined"
        if not why and np.isnan(lo):
            why = "no critical depth predicted at the cut"
        admits = (hi >= d) if r["verdict"] == "stable" else (lo <= d)
        with np.errstate(divide="ignore", invalid="ignore"):
            outside = max(1.0, d / hi if r["verdict"] == "stable" else lo / d)
        table.append({"cut": str(r["cut"]), "verdict": r["verdict"],
                      "spindle_rpm": float(r["spindle_rpm"]), "depth_mm": d,
                      "a_crit_low_mm": lo, "a_crit_high_mm": hi,
                      "prior_admits": bool(admits) if not why else None,
                      "outside_factor": outside if not why else np.nan,
                      "used": not why, "why": why, "source": source,
                      "a_crit_mm": float(col[0]) * 1e3 if known else np.nan,
                      "p_stable_prior": float(p_stable(col, flat, d * 1e-3)) if known
                      else np.nan})
    t = pd.DataFrame(table, columns=list(EVIDENCE_COLUMNS))
    used = t["used"].to_numpy(bool) if len(t) else np.zeros(0, bool)
    w = verdict_weights(a[:, used], t["depth_mm"].to_numpy(float)[used] * 1e-3,
                        (t["verdict"] == "stable").to_numpy()[used], error_rate)
    if len(t):
        t["p_stable"] = [float(p_stable(a[:, j], w, d * 1e-3)) if u else np.nan
                         for j, (d, u) in enumerate(zip(t["depth_mm"], used, strict=True))]
    return VerdictEvidence(w, t, float(error_rate))
