"""The planner's stability model: for given cuts, the critical axial depth as an interval and
its members, and the probability that each cut is stable, learned from the study's verdicts.

This module is the one interface between the plan (and ``robomill predict``) and a stability
theory: :func:`member_depths_m` gives every member's critical depth at given postures, cut
frames and speeds; :func:`verdict_weights` weighs the members by the study's verdicts;
:func:`summary` and :func:`p_stable` turn the weighted members into the interval and the
probability. Replacing the theory touches this module only.

**The model.** The regenerative multi-mode model of milling [Altintas & Budak 1995]: the
tool tip's receptance is the modal sum of every identified mode at the cut's pose (the
impact test's robot modes moved to the pose, :func:`robomill.plan.tooltip.mode_scalings`) and
the spindle/tool modes above the impact test's band, which enter as a stated prior
(:class:`ToolModePrior`); the cut's directional coefficients (immersion, milling mode,
tangential, radial and axial coefficients) and the tooth-period delay. Each mode keeps its
component along the tool axis: the chip also drives the axial force K_ac a h, and the
in-plane response to it closes a regenerative loop of its own (the axial row of the
directional matrix, :mod:`robomill.chatter.model`); a study whose K_ac is not identified
gets the planar model. It is solved by the
zero-order approximation (:func:`robomill.plan.lobes.batch_zoa_lobes`). Its error against
semi-discretization [Insperger & Stépán 2004] is stated by :func:`zoa_error` at the
reference pose (``benchmarks/coupling_vs_lobes.py``). Mode coupling arises inside this model;
the delay-free mode-coupling depth (:func:`robomill.chatter.coupling.coupling_depth`) is a
diagnostic of chapter 4, never a limit here.

**Members.** Member 0 holds the identified values (and the prior's nominal tool modes); the
others are a parametric bootstrap [Efron & Tibshirani 1993]: each mode's f, ζ, k drawn
normal with the standard deviation of its 95 % interval (``modes.csv`` ``*_low``/``*_high``,
σ = (high − low)/(2·1.96)), the joint stiffness along the same z between its ends, K_t and
K_r (and K_ac, drawn after every other draw so that the others stay those of the planar
model) drawn normal from the coefficients' confidence intervals (a_lim ∝ 1/K_t exactly at
fixed K_r/K_t and K_ac/K_t), and the tool modes drawn log-uniform over the prior's ranges.

**Learning from verdicts.** A member m predicting a_m(i) at the study's cut i of depth d_i
predicts stable when a_m(i) > d_i. With a stated verdict error rate ε (a recording judged
wrongly), the likelihood of the study's verdicts v_i is

.. math:: L_m = \\prod_i (1-ε)^{[\\hat v_{m,i} = v_i]}\\, ε^{[\\hat v_{m,i} \\ne v_i]}

and each member's weight is L_m / Σ L (Bayesian updating of stability lobes, [Karandikar
et al. 2014], on a bootstrap prior). The probability that a cut of depth d is stable is the
weighted share of members with a_m > d; the interval is the weighted central ``level``
range of a_m.

**Extrapolation.** A member's deviation from the nominal, log(a_m/a_0), is multiplied by the
candidate's widening factor w ≥ 1 (:mod:`robomill.plan.extrapolation`: 1 inside what the
study covered, growing with the distance outside): the probability and the interval widen
with the distance from the evidence, never as a cliff.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from robomill.chatter.model import CuttingModel
from robomill.plan.lobes import batch_zoa_lobes

NO_CHATTER_M = 10.0
"""A critical depth beyond this [m] is reported as +inf (no chatter at any depth a tool cuts)."""

Z95 = 1.959963984540054
"""Normal quantile of a two-sided 95 % interval (the identification intervals' level)."""


@dataclass(frozen=True)
class ToolModePrior:
    """A mode above the impact test's band, stated as a prior: ranges of its natural
    frequency [Hz], damping ratio and modal stiffness [N/m] (each member draws log-uniform
    inside them; the nominal is the geometric middle) and its unit shape (base frame)."""

    f_hz: tuple[float, float]
    zeta: tuple[float, float]
    k_N_m: tuple[float, float]
    shape: tuple[float, float, float]

    def nominal(self) -> tuple[float, float, float]:
        return tuple(float(np.sqrt(lo * hi)) for lo, hi in (self.f_hz, self.zeta, self.k_N_m))


@dataclass(frozen=True)
class StabilitySettings:
    """``plan.yaml: stability``: members of the bootstrap, the verdicts' error rate, the
    seed of the draws and the prior of the modes above the impact test's band."""

    members: int = 24
    verdict_error: float = 0.05
    seed: int = 20240601
    tool_modes: tuple[ToolModePrior, ...] = ()


@dataclass(frozen=True)
class Members:
    """The parameters of E members (member 0 the nominal): robot/impact-test modes ``f_hz``,
    ``zeta``, ``k_N_m`` ``(E, M)`` with unit ``shapes`` ``(M, 3)``; ``joint_z`` ``(E,)`` the
    joint stiffness' standard-normal draw; ``kt_N_mm2``, ``kr`` ``(E,)``; the tool modes
    ``tool_f_hz``, ``tool_zeta``, ``tool_k_N_m`` ``(E, T)`` with ``tool_shapes`` ``(T, 3)``;
    ``ka`` ``(E,)`` K_ac/K_tc (None: K_ac not identified, the planar model)."""

    f_hz: np.ndarray
    zeta: np.ndarray
    k_N_m: np.ndarray
    shapes: np.ndarray
    joint_z: np.ndarray
    kt_N_mm2: np.ndarray
    kr: np.ndarray
    tool_f_hz: np.ndarray
    tool_zeta: np.ndarray
    tool_k_N_m: np.ndarray
    tool_shapes: np.ndarray
    ka: np.ndarray | None = None

    @property
    def n(self) -> int:
        return len(self.kt_N_mm2)


def _sigma(nom, lo, hi):
    """Standard deviation of a 95 % interval (0 where not given)."""
    s = (np.asarray(hi, float) - np.asarray(lo, float)) / (2 * Z95)
    return np.where(np.isfinite(s) & (s > 0), s, 0.0) * np.ones_like(np.asarray(nom, float))


def draw_members(measured, settings: StabilitySettings) -> Members | None:
    """The members (module docstring); None without modes or coefficients."""
    from robomill.plan.measured import coefficient_bounds
    from robomill.plan.tooltip import modes_arrays

    if not (measured.has("modes") and measured.has("coefficients")):
        return None
    fn, zeta, k, shapes = modes_arrays(measured.modes)
    if fn.size == 0:
        return None
    lo, hi = modes_arrays(measured.modes, "_low"), modes_arrays(measured.modes, "_high")
    cb = coefficient_bounds(measured.coefficients)
    E = max(int(settings.members), 1)
    rng = np.random.default_rng(int(settings.seed))
    z = rng.standard_normal((E, 3, fn.size))
    z[0] = 0.0

    def draw(nom, s, zz):
        return np.maximum(nom[None] + s[None] * zz, 0.05 * nom[None])

    f = draw(fn, _sigma(fn, lo[0], hi[0]), z[:, 0])
    ze = draw(zeta, _sigma(zeta, lo[1], hi[1]), z[:, 1])
    kk = draw(k, _sigma(k, lo[2], hi[2]), z[:, 2])
    zj = rng.standard_normal(E)
    zk = rng.standard_normal((E, 2))
    zj[0], zk[0] = 0.0, 0.0
    kt0, kr0 = cb["nominal"].Ktc, cb["nominal"].Krc
    kt = np.maximum(kt0 + _sigma(kt0, cb["low"].Ktc, cb["high"].Ktc) * zk[:, 0], 0.05 * kt0)
    krc = np.maximum(kr0 + _sigma(kr0, cb["low"].Krc, cb["high"].Krc) * zk[:, 1], 0.0)
    T = len(settings.tool_modes)
    tf, tz, tk = np.zeros((E, T)), np.zeros((E, T)), np.zeros((E, T))
    tshape = np.zeros((T, 3))
    for j, pr in enumerate(settings.tool_modes):
        u = rng.uniform(size=(E, 3))
        # log-uniform draws, the nominal (member 0) at the geometric middle
        tf[:, j] = np.exp(np.log(pr.f_hz[0]) + u[:, 0] * np.log(pr.f_hz[1] / pr.f_hz[0]))
        tz[:, j] = np.exp(np.log(pr.zeta[0]) + u[:, 1] * np.log(pr.zeta[1] / pr.zeta[0]))
        tk[:, j] = np.exp(np.log(pr.k_N_m[0]) + u[:, 2] * np.log(pr.k_N_m[1] / pr.k_N_m[0]))
        tf[0, j], tz[0, j], tk[0, j] = pr.nominal()
        s = np.asarray(pr.shape, float)
        tshape[j] = s / np.linalg.norm(s)
    ka = None
    kac0 = cb["nominal"].Kac
    if np.isfinite(kac0):
        za = rng.standard_normal(E)
        za[0] = 0.0
        kac = np.maximum(kac0 + _sigma(kac0, cb["low"].Kac, cb["high"].Kac) * za, 0.0)
        ka = kac / kt
    return Members(f, ze, kk, shapes, zj, kt, krc / kt, tf, tz, tk, tshape, ka)


POSE_FREQUENCY_FACTOR = 1.5
"""How far a pose may move a robot mode's frequency (× or ÷; a stiffness ratio up to 2.25)
on the chatter-frequency grid: the grid depends on the members alone, so one pose's critical
depth is the same in any batch."""


def _frequency_grid(members: Members, per_bandwidth: float = 8.0) -> np.ndarray:
    """Chatter frequencies for every member: a log-spaced backbone from 0.3 times the lowest
    mode to 3 times the highest of the impact test's and 1.5 times the highest of the
    prior's (the prior's stiff modes reach no lobe beyond), and over each group of modes (the
    impact test's, moved with the pose; the prior's) a linear grid over the group's range
    across members and poses (±20 %) with ``per_bandwidth`` points per half-power bandwidth
    2ζf of its sharpest mode. On the default study's poses the critical depths lie within
    0.4 % of a 13 000-point grid's (median 10⁻⁵). Where the tooth frequency lies within a few
    per cent of a mode's, the lobe squeezed between them is resolved coarsely (a third off at
    one speed in a planted one-mode test): no robot mode of a milling study comes near its
    tooth frequency, a spindle mode can."""
    s = POSE_FREQUENCY_FACTOR
    groups = [(members.f_hz.min() * 0.8 / s, members.f_hz.max() * 1.2 * s,
               float(np.min(members.zeta * members.f_hz)))]
    if members.tool_f_hz.size:
        groups.append((members.tool_f_hz.min() * 0.8, members.tool_f_hz.max() * 1.2,
                       float(np.min(members.tool_zeta * members.tool_f_hz))))
    lo = min(g[0] for g in groups)
    hi = max(g[1] for g in groups)
    top = max(3 * groups[0][1] / 1.2, 1.5 * hi / 1.2 if len(groups) > 1 else 0.0)
    grids = [np.geomspace(0.3 * lo / 0.8, top, 800)]
    for a, b, zf in groups:
        n = int(np.clip((b - a) / (2 * max(zf, 1e-9)) * per_bandwidth, 50, 4000))
        grids.append(np.linspace(a, b, n))
    return np.unique(np.concatenate(grids))


def member_modes(members: Members, scalings: dict[str, np.ndarray], frames: np.ndarray,
                 which: slice | None = None
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Every mode of the members (``which``: a subset) at B poses: natural frequencies,
    damping ratios and modal stiffnesses ``(E, B, M + T)`` (the robot modes moved to each pose
    by the stiffness ratios ``scalings`` of :func:`robomill.plan.tooltip.mode_scalings`, keys
    ``nominal`` and optionally ``low``/``high``, ``(B, M)``, between whose ends each member's
    ``joint_z`` interpolates, and the frequency by √(stiffness ratio / mass ratio), the mass
    ratio its ``mass`` where the cell documents the robot's masses, else 1; then the tool
    modes) and their shapes ``(B, M + T, 3)`` in the cut frames ``(B, 3, 3)`` (columns feed,
    normal, axis; the in-plane model takes the first two)."""
    idx = np.arange(members.n)[which if which is not None else slice(None)]
    s_nom = scalings["nominal"]
    B = s_nom.shape[0]
    E = idx.size
    robot = np.einsum("mi,bid->bmd", members.shapes, frames)                  # (B, M, 3)
    tool = np.einsum("ti,bid->btd", members.tool_shapes, frames)              # (B, T, 3)
    shape = np.concatenate([robot, tool], 1)
    zj = members.joint_z[idx][:, None, None]                                   # (E, 1, 1)
    s_hi = scalings.get("high", s_nom)[None]
    s_lo = scalings.get("low", s_nom)[None]
    sc = s_nom[None] + (np.abs(zj) / Z95) * (np.where(zj > 0, s_hi, s_lo) - s_nom[None])
    sc = np.maximum(sc, 1e-6)                                                  # (E, B, M)
    T = members.tool_f_hz.shape[1]
    mass = np.asarray(scalings.get("mass", np.ones_like(s_nom)), float)[None]  # (1, B, M)
    fn = np.concatenate([members.f_hz[idx][:, None] * np.sqrt(sc / mass),
                         np.broadcast_to(members.tool_f_hz[idx][:, None], (E, B, T))], 2)
    kk = np.concatenate([members.k_N_m[idx][:, None] * sc,
                         np.broadcast_to(members.tool_k_N_m[idx][:, None], (E, B, T))], 2)
    zz = np.broadcast_to(np.concatenate([members.zeta[idx], members.tool_zeta[idx]], 1)[:, None],
                         fn.shape)
    return fn, zz, kk, shape


def member_cut(members: Members, e: int, *, flutes: int, entry_rad: float, exit_rad: float,
               kt_N_mm2: float | None = None) -> CuttingModel:
    """Member ``e``'s cutting model (its K_r and K_a; K_t its own, or ``kt_N_mm2``: the
    depths scale as 1/K_t, :func:`member_depths_m`)."""
    kt = float(members.kt_N_mm2[e] if kt_N_mm2 is None else kt_N_mm2)
    ka = None if members.ka is None else float(members.ka[e])
    return CuttingModel(int(flutes), kt * 1e6, float(members.kr[e]), float(entry_rad),
                        float(exit_rad), Ka=ka)


def member_depths_m(members: Members, scalings: dict[str, np.ndarray], frames: np.ndarray,
                    spindle_rpm: np.ndarray, *, flutes: int, entry_rad: float,
                    exit_rad: float, which: slice | None = None) -> np.ndarray:
    """Critical depth ``(E, B, S)`` [m] of the members (``which``: a subset) at B poses
    (robot-mode stiffness ratios ``scalings`` from :func:`robomill.plan.tooltip.mode_scalings`,
    keys ``nominal`` and optionally ``low``/``high``, ``(B, M)``), cut frames ``(B, 3, 3)``
    (columns feed, normal, axis) and speeds ``(S,)`` (zero-order lobes on the modes of
    :func:`member_modes`, with the axial force where K_ac is identified; +inf where no lobe
    reaches a speed)."""
    idx = np.arange(members.n)[which if which is not None else slice(None)]
    fn, zz, kk, shape = member_modes(members, scalings, frames, which)
    E, B = fn.shape[:2]
    f_grid = _frequency_grid(members)
    kt0 = float(members.kt_N_mm2[0])
    cuts = [member_cut(members, e, flutes=flutes, entry_rad=entry_rad, exit_rad=exit_rad,
                       kt_N_mm2=kt0) for e in idx]
    W = np.stack([c.mean_matrix() for c in cuts])                              # (E, 2|3, 2)
    n_modes, d = fn.shape[-1], W.shape[1]
    a = batch_zoa_lobes(fn.reshape(E * B, n_modes), zz.reshape(E * B, n_modes),
                        kk.reshape(E * B, n_modes),
                        np.broadcast_to(shape[None, ..., :d],
                                        (E,) + shape.shape[:-1] + (d,)).reshape(E * B,
                                                                                n_modes, d),
                        cuts[0], np.atleast_1d(spindle_rpm), f_hz=f_grid,
                        mean_matrix=np.repeat(W, B, axis=0))
    a = a.reshape(E, B, -1)
    # a branch grazing u = 0 gives astronomically deep limits: no chatter at any depth
    a = np.where(a > NO_CHATTER_M, np.inf, a)
    return a * (kt0 / members.kt_N_mm2[idx])[:, None, None]


def widen_members(a_members: np.ndarray, widening: np.ndarray | float) -> np.ndarray:
    """Members' deviations from the nominal (member 0) in log depth multiplied by the
    widening factor (module docstring); ``widening`` broadcasts against ``a_members[0]``."""
    a = np.asarray(a_members, float)
    w = np.asarray(widening, float)
    if np.all(w == 1.0):
        return a
    with np.errstate(divide="ignore", invalid="ignore"):
        dev = np.log(a / a[:1])
        out = a[:1] * np.exp(dev * w)
    return np.where(np.isfinite(dev), out, a)


def verdict_weights(a_at_cuts_m: np.ndarray, depth_m: np.ndarray, stable: np.ndarray,
                    error_rate: float) -> np.ndarray:
    """Normalized member weights ``(E,)`` from verdicts (module docstring): ``a_at_cuts_m``
    ``(E, n)`` each member's critical depth at the n judged cuts, ``depth_m`` ``(n,)``,
    ``stable`` ``(n,)`` bool. No judged cut: equal weights."""
    a = np.asarray(a_at_cuts_m, float)
    E = a.shape[0]
    if a.size == 0 or a.shape[1] == 0:
        return np.full(E, 1.0 / E)
    eps = float(np.clip(error_rate, 1e-9, 0.5))
    agree = (a > np.asarray(depth_m, float)[None]) == np.asarray(stable, bool)[None]
    logl = np.where(agree, np.log1p(-eps), np.log(eps)).sum(1)
    w = np.exp(logl - logl.max())
    return w / w.sum()


def p_stable(a_members_m: np.ndarray, weights: np.ndarray, depth_m) -> np.ndarray:
    """Weighted share of members with a critical depth above ``depth_m``; ``a_members_m``
    ``(E, ...)`` broadcasts against ``depth_m``."""
    a = np.asarray(a_members_m, float)
    w = np.asarray(weights, float).reshape((-1,) + (1,) * (a.ndim - 1))
    return np.sum(w * (a > np.asarray(depth_m, float)), axis=0)


def weighted_quantile(a_members: np.ndarray, weights: np.ndarray, q: float) -> np.ndarray:
    """The weighted q-quantile over axis 0 (the smallest member value whose cumulative
    weight reaches q)."""
    a = np.asarray(a_members, float)
    order = np.argsort(a, axis=0)
    srt = np.take_along_axis(a, order, 0)
    cw = np.cumsum(np.asarray(weights, float)[order], axis=0)
    i = np.argmax(cw >= q - 1e-12, axis=0)
    return np.take_along_axis(srt, i[None], 0)[0]


def summary(a_members_m: np.ndarray, weights: np.ndarray, level: float) -> dict[str, np.ndarray]:
    """``nominal`` (member 0, held inside the interval), ``low``/``high`` (the weighted
    central ``level`` range of the members)."""
    lo = weighted_quantile(a_members_m, weights, (1 - level) / 2)
    hi = weighted_quantile(a_members_m, weights, 1 - (1 - level) / 2)
    return {"nominal": np.clip(a_members_m[0], lo, hi), "low": lo, "high": hi}


@dataclass(frozen=True)
class VerdictEvidence:
    """The study's verdicts as the members' weights: ``weights`` ``(E,)``, ``table`` one row
    per cut with a verdict (:data:`EVIDENCE_COLUMNS`), the error rate assumed."""

    weights: np.ndarray
    table: pd.DataFrame = field(default_factory=pd.DataFrame)
    error_rate: float = 0.05

    @property
    def n_used(self) -> int:
        return int(self.table["used"].astype(bool).sum()) if len(self.table) else 0

    @property
    def effective_members(self) -> float:
        """Kish's effective number of members, (Σw)²/Σw²."""
        w = self.weights
        return float(w.sum() ** 2 / np.sum(w**2))


def zoa_error(members: Members, scalings: dict, frame: np.ndarray, spindle_rpm, *,
              flutes: int, entry_rad: float, exit_rad: float) -> float:
    """Largest relative difference of the zero-order critical depth of the nominal member
    against semi-discretization (:func:`robomill.chatter.lobes_sdm.sdm_lobes`) at one pose
    ``frame`` ``(3, 3)`` (``scalings`` ``(1, M)``) over ``spindle_rpm``: the stated error
    of the solver."""
    from robomill.chatter.lobes_sdm import sdm_lobes
    from robomill.chatter.model import ModeXY, tool_from_modes

    rpm = np.atleast_1d(np.asarray(spindle_rpm, float))
    a_zoa = member_depths_m(members, scalings, frame[None], rpm, flutes=flutes,
                            entry_rad=entry_rad, exit_rad=exit_rad, which=slice(0, 1))[0, 0]
    fn, zz, kk, shape = member_modes(members, scalings, frame[None], slice(0, 1))
    cut = member_cut(members, 0, flutes=flutes, entry_rad=entry_rad, exit_rad=exit_rad)
    modes = [ModeXY(float(f), float(z), float(k), tuple(float(v) for v in sh[:cut.n_rows]))
             for f, z, k, sh in zip(fn[0, 0], zz[0, 0], kk[0, 0], shape[0], strict=True)]
    fin = a_zoa[np.isfinite(a_zoa)]
    depth_max = 3.0 * float(fin.max()) if fin.size else 0.1
    a_sdm = np.asarray(sdm_lobes(tool_from_modes(modes), cut, rpm, depth_max_m=depth_max)[0],
                       float)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.abs(a_zoa / a_sdm - 1)
    rel = rel[np.isfinite(rel)]
    return float(rel.max()) if rel.size else float("nan")
