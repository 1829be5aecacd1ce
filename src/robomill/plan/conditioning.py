"""The stability limit conditioned on the study's own chatter verdicts: a set-membership
update of the critical-depth interval.

**The prior set.** The planner's critical-depth interval
(:func:`robomill.plan.predict.critical_depth_m`) is the envelope of a set of *members* over
the uncertain parameters: the lobes recomputed with each parameter at an end of its interval
in turn (member e: the nominal parameters, the K_r ratio's ends, the joint stiffness' ends,
the modes' ends; a_e(p, n) at pose p and speed n for the nominal tangential coefficient
K_t0), each at every tangential coefficient of the coefficient's interval
[K_t⁻, K_t⁺]. The critical depth of the zero-order lobes is inversely proportional to K_t
(a_lim = −2πΛ_R(1 + κ²)/(N K_t), [Altintas 2012, ch. 4]), so that dimension is exact and
continuous:

    a(e, K_t; p, n) = a_e(p, n) · K_t0 / K_t,    K_t ∈ [K_t⁻, K_t⁺]

and the prior interval is ``[min_e a_e K_t0/K_t⁺, max_e a_e K_t0/K_t⁻]`` (the interval the
planner states without evidence).

**The evidence.** A cut of the study at pose p_i, speed n_i and depth d_i with a verdict
(``results/chatter/verdicts.csv``, combined over its recordings by
:func:`robomill.plan.evidence.verdict_stability`) says where the true limit lies there:
stable ⇒ a_true(p_i, n_i) ≥ d_i, chatter ⇒ a_true(p_i, n_i) ≤ d_i, undetermined ⇒
nothing. Keeping only the members that agree with every verdict (a set-membership update,
[Milanese 1991]) leaves member e the coefficients

    K_t ∈ [K_t⁻, K_t⁺] ∩ [max_chatter K_t0 a_e(i)/d_i,  min_stable K_t0 a_e(i)/d_i]

(empty: the member is rejected), and every candidate's conditioned interval is the envelope
over the surviving (e, K_t):

    low = min_e a_e K_t0 / K_t,e⁺,    high = max_e a_e K_t0 / K_t,e⁻.

A verdict at a speed and pose brackets the limit there between the stable and the chatter
depth; the members carry that bracket to every other candidate through the model.
The nominal is kept where it lies inside the conditioned interval, else moved to its
nearest end.

**A model that contradicts its observations.** When no member agrees with every verdict,
the stated interval cannot hold the truth at some evidence cut whatever the parameters: the
update then keeps the prior interval and says so in one line
(:attr:`StabilityEvidence.note`), which chapter 7 reports with the cuts whose verdict the
prior interval does not admit (``prior_admits`` of ``results/plan/evidence_used.csv``) and
by how much it misses each: ``outside_factor`` = d_i / a⁺(i) for a stable cut above the
interval's highest limit a⁺, a⁻(i) / d_i for a chattering cut below its lowest a⁻, else 1
(the factor by which the critical depth would be off there, whatever the parameters).

References
----------
Altintas 2012: Altintas, Y. *Manufacturing Automation: Metal Cutting Mechanics, Machine Tool
Vibrations, and CNC Design*, 2nd ed. Cambridge University Press, 2012.
Milanese 1991: Milanese, M.; Vicino, A. Optimal estimation theory for dynamic systems with
set membership uncertainty: an overview. *Automatica* **27**(6), 997–1009, 1991.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

EVIDENCE_COLUMNS = ("cut", "verdict", "spindle_rpm", "depth_mm", "a_crit_low_mm",
                    "a_crit_high_mm", "prior_admits", "outside_factor", "used", "why", "source")
"""Columns of ``results/plan/evidence_used.csv``."""


@dataclass(frozen=True)
class StabilityEvidence:
    """The set-membership update of the critical depth (module docstring).

    ``kt_low``/``kt_high`` ``(E,)``: each member's surviving K_t interval (NaN: rejected);
    ``kept`` how many members survive, ``table`` the evidence cuts
    (:data:`EVIDENCE_COLUMNS`), ``note`` one line when no member survives (the prior
    interval is then kept), else ""."""

    kt_low: np.ndarray
    kt_high: np.ndarray
    members: tuple[str, ...] = ()
    table: pd.DataFrame = field(default_factory=lambda: pd.DataFrame(columns=EVIDENCE_COLUMNS))
    note: str = ""

    @property
    def kept(self) -> int:
        return int(np.isfinite(self.kt_low).sum())

    @property
    def n_used(self) -> int:
        return int(self.table["used"].astype(bool).sum()) if len(self.table) else 0

    @property
    def active(self) -> bool:
        """Whether the update changes the intervals: some evidence, some member kept."""
        return self.n_used > 0 and self.kept > 0


def member_kt_ranges(a_members_m: np.ndarray, depth_m: np.ndarray, stable: np.ndarray,
                     kt_nominal: float, kt_low: float, kt_high: float
                     ) -> tuple[np.ndarray, np.ndarray]:
    """Each member's K_t interval that agrees with every verdict (module docstring).

    Parameters
    ----------
    a_members_m
        ``(E, n)`` critical depth [m] of each member at each evidence cut, at ``kt_nominal``.
    depth_m
        ``(n,)`` the cuts' depths [m].
    stable
        ``(n,)`` True: stable, False: chatter.
    kt_nominal, kt_low, kt_high
        K_t0 and the ends of K_t's prior interval (any unit, the same for all three).

    Returns
    -------
    tuple of numpy.ndarray
        ``(E,)`` low and high ends; NaN for a rejected member.
    """
    a = np.asarray(a_members_m, float)
    d = np.asarray(depth_m, float)[None, :]
    st = np.asarray(stable, bool)[None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        bound = kt_nominal * a / d          # a(e, K_t) ≥ d  ⟺  K_t ≤ bound
    bound = np.where(np.isnan(bound), -np.inf, bound)   # no prediction: rejects the member
    hi = np.minimum(kt_high, np.where(st, bound, np.inf).min(1))
    lo = np.maximum(kt_low, np.where(st, -np.inf, bound).max(1))
    ok = lo <= hi
    return np.where(ok, lo, np.nan), np.where(ok, hi, np.nan)


def conditioned_depth(a_members_m: np.ndarray, kt_nominal: float, kt_low: np.ndarray,
                      kt_high: np.ndarray, nominal_m: np.ndarray
                      ) -> dict[str, np.ndarray]:
    """``nominal``, ``low`` and ``high`` critical depth from the surviving members
    (``a_members_m`` ``(E, ...)`` at ``kt_nominal``; ``kt_low``/``kt_high`` ``(E,)`` from
    :func:`member_kt_ranges`, NaN rejected; at least one kept): the envelope of the module
    docstring, the nominal moved into it."""
    keep = np.isfinite(kt_low)
    a = np.asarray(a_members_m, float)[keep]
    shape = (-1,) + (1,) * (a.ndim - 1)
    low = (a * kt_nominal / kt_high[keep].reshape(shape)).min(0)
    high = (a * kt_nominal / kt_low[keep].reshape(shape)).max(0)
    return {"nominal": np.clip(nominal_m, low, high), "low": low, "high": high}


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


def contradiction_note(table: pd.DataFrame) -> str:
    """The one line of a model whose every member contradicts a verdict: how many evidence
    cuts, how many the prior interval does not admit, and the worst of them."""
    v = evidence_values(table, {})
    worst = worst_contradiction(table)
    return (f"stability evidence: no member of the critical-depth interval agrees with the "
            f"verdicts of the {v['n_used']} evidence cuts; {v['n_contradicting']} of them lie "
            f"outside the interval at any parameters{f' (e.g. {worst})' if worst else ''}: "
            "the model contradicts its own observations, the unconditioned interval is kept")


def evidence_values(table: pd.DataFrame, attrs: Mapping) -> dict:
    """What chapter 7 states about the evidence (``results/plan/evidence_used.csv`` and the
    ``stability_*`` attributes of ``candidates.nc``): ``n_verdicts`` (cuts with a verdict),
    ``n_used``, ``n_stable``, ``n_chatter`` (of those used), ``n_left_out`` (undetermined or
    no prediction), ``n_contradicting`` (used, outside the prior interval), ``members``,
    ``members_kept``, ``worst`` (:func:`worst_contradiction`), ``model_error_factor`` (the
    largest ``outside_factor``: by how much the interval would have to stretch, as a factor on
    the critical depth, to admit every verdict; 1 when it admits them) and ``evidence_case``:
    ``conditioned`` (members kept), ``contradicted`` (none kept: the prior interval stays) or
    ``none`` (no verdict entered)."""
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
           "worst": worst_contradiction(table) if len(table) else "",
           "model_error_factor": float(u["outside_factor"].astype(float).max())
           if len(u) else 1.0}
    out["evidence_case"] = ("none" if not out["n_used"] else
                            "conditioned" if out["members_kept"] else "contradicted")
    return out


def study_evidence(rows: Sequence[Mapping], a_members_m: np.ndarray, kt: tuple[float, ...],
                   members: Sequence[str] = (), source: str = "") -> StabilityEvidence:
    """The update from the study's cuts.

    Parameters
    ----------
    rows
        One mapping per cut with a verdict: ``cut``, ``verdict`` (``stable`` | ``chatter`` |
        ``undetermined``), ``spindle_rpm``, ``depth_mm``; ``why`` (optional) a reason the cut
        cannot enter (unreachable: no prediction there).
    a_members_m
        ``(E, n)`` each member's critical depth [m] at each cut, at K_t0 (NaN where none).
    kt
        ``(K_t0, K_t⁻, K_t⁺)``.
    members
        The members' names (``critical_depth_m(..., members=True)["members"]``).
    source
        Where the verdicts come from (``results/chatter/verdicts.csv``).
    """
    k0, klo, khi = (float(x) for x in kt)
    a = np.asarray(a_members_m, float).reshape(-1, len(rows))
    table = []
    for j, r in enumerate(rows):
        d = float(r["depth_mm"])
        col = a[:, j]
        known = col.size > 0 and not np.isnan(col).any()
        lo = float(np.min(col) * k0 / khi) * 1e3 if known else np.nan
        hi = float(np.max(col) * k0 / klo) * 1e3 if known else np.nan
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
                      "used": not why, "why": why, "source": source})
    t = pd.DataFrame(table, columns=list(EVIDENCE_COLUMNS))
    used = t["used"].to_numpy(bool) if len(t) else np.zeros(0, bool)
    E = a.shape[0]
    if not used.any():
        return StabilityEvidence(np.full(E, klo), np.full(E, khi), tuple(members), t)
    lo_e, hi_e = member_kt_ranges(a[:, used], t["depth_mm"].to_numpy(float)[used] * 1e-3,
                                  (t["verdict"] == "stable").to_numpy()[used], k0, klo, khi)
    note = "" if np.isfinite(lo_e).any() else contradiction_note(t)
    return StabilityEvidence(lo_e, hi_e, tuple(members), t, note)
