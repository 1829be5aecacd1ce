"""Spectral-element (Chebyshev collocation) stability of the regenerative milling model, with
exact free flight, a per-speed discretization-error estimate and refinement to an accuracy.

The periodic delay-differential equation of :mod:`robomill.chatter.model`,

.. math:: \\dot{\\mathbf s} = (A + a B W(t) C)\\,\\mathbf s - a B W(t)\\, C\\,\\mathbf s(t-\\tau),

has a delay equal to its period τ, so the delayed output at a time point is the output at the
same point of the previous period (Insperger & Stépán 2004). One period is split at every
tooth entry and exit (where W(t) jumps) into segments:

* **free flight** (no tooth engaged, W = 0): the exact transition e^{A Δt};
* **cutting**: W(t) is smooth (sums of sin/cos) and the segment is cut into spectral elements,
  each with p + 1 Chebyshev–Gauss–Lobatto nodes; the state is a polynomial of degree p on the
  element, continuous between elements, and the equation is collocated at nodes 1 … p
  (Khasawneh & Mann 2011, IJNME 87, "A spectral element approach for the stability of delay
  systems"; Trefethen 2000, *Spectral Methods in MATLAB*, ch. 6 for the differentiation
  matrix). On element e, with S_e the states at nodes 1 … p, s_0 the state at its first
  node and d_e^{old} = C s at the same nodes one period earlier:

  .. math:: (D_{11} \\otimes I - \\mathrm{diag}(A + aBW_iC))\\,S_e
            = -(D_{10} \\otimes I)\\,s_0 - \\mathrm{diag}(aBW_i)\\,d_e^{old}

Because the delayed values sit exactly on the nodes, the delay needs no interpolation; the
only discretization error is the collocation error, which falls spectrally (faster than any
power of 1/p) since W is smooth inside each element. The monodromy matrix maps
(s at the period start, d at every collocation node) over one period; its size is
n_s + 2·p·(number of elements) — for the benchmark of Insperger & Stépán (2004) 2 + 2p,
against n_s + 2m = 322 for the first-order semi-discretization with m = 160.

Critical depth: a geometric scan of :data:`N_SCAN` depths (as
:func:`robomill.chatter.lobes_sdm.critical_depth`, so unstable islands above a stable band are
caught at the scan resolution), joined — warm start — by a fine bracket around the
neighbouring speed's depth, all in one batched eigenvalue call; the first crossing of
ρ(Φ(a)) = 1 by batched bracketing and linear interpolation; then the same at order
p + ``P_STEP`` from that root. |a(p + P_STEP) − a(p)| plus the root tolerance is the error
estimate of the value reported (the finer one, so the estimate is conservative for a
spectrally convergent method); p grows until the estimate meets the relative ``accuracy``.
The depth-independent pieces (free-flight exponentials, collocation matrices) are built once
per speed and order and reused for every depth.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.linalg

from robomill.chatter.lobes_sdm import (
    classify_multiplier,
    multiplier_frequency_hz,
    reference_frequencies_hz,
)
from robomill.chatter.model import CuttingModel, LinearTool, conform_rows, lobe_parameters

NODES = 8
"""Starting collocation order p per element (p + 1 Chebyshev–Gauss–Lobatto nodes)."""
P_STEP = 2
"""Order added for the error estimate and at each refinement."""
P_MAX = 48
"""Largest order tried; a speed whose estimate still misses the accuracy keeps its estimate."""
CYCLES_PER_ELEMENT = 1.0
"""Elements per cutting segment: at most this many periods of the fastest tool mode each."""
N_SCAN = 32
"""Depths of the geometric scan for the first unstable bracket (a ratio of 1.2 between
neighbours: on the benchmark 16 depths miss the narrow flip lobe at 10 900 rpm, 24 do not)."""
ACCURACY = 0.005
"""Default relative accuracy of the critical depth (``chatter.accuracy``)."""


@lru_cache(maxsize=64)
def cheb(p: int) -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev–Gauss–Lobatto nodes x_j = −cos(πj/p) on [−1, 1] (ascending) and the
    differentiation matrix D with (Df)(x_i) = f'(x_i) for polynomials of degree ≤ p
    (Trefethen 2000, program ``cheb``, with the node order reversed)."""
    if p < 1:
        raise ValueError(f"collocation order must be >= 1, got {p}")
    j = np.arange(p + 1)
    x = -np.cos(np.pi * j / p)
    c = np.where((j == 0) | (j == p), 2.0, 1.0) * (-1.0) ** j
    dx = x[:, None] - x[None, :]
    D = np.outer(c, 1.0 / c) / (dx + np.eye(p + 1))
    D -= np.diag(D.sum(axis=1))
    x.setflags(write=False)  # cached: shared by every caller
    D.setflags(write=False)
    return x, D


def segments(cut: CuttingModel, spindle_rpm: float) -> list[tuple[float, float, tuple[int, ...]]]:
    """One tooth period split at every tooth entry and exit: ``(t_start_s, t_end_s,
    engaged_teeth)`` in time order (engaged_teeth empty: free flight). The edge force's
    switching (:class:`~robomill.chatter.model.EdgeSwitching`), an impulse at an engagement
    edge, has no place in these segments: refused."""
    if cut.edge is not None:
        raise ValueError("the edge force's switching is an impulse, which the spectral "
                         "elements cannot hold: use the zero-order lobes or the "
                         "semi-discretization")
    omega = 2 * np.pi * float(spindle_rpm) / 60.0
    theta_p = 2 * np.pi / cut.teeth  # phase of tooth 0 over one tooth period
    cuts = [0.0, theta_p]
    for j in range(cut.teeth):
        for edge in (cut.phi_st, cut.phi_ex):
            th = np.mod(edge - 2 * np.pi * j / cut.teeth, 2 * np.pi)
            if 0.0 < th < theta_p:
                cuts.append(float(th))
    cuts = np.unique(np.round(np.array(cuts), 14))
    out = []
    for a, b in zip(cuts[:-1], cuts[1:], strict=True):
        if b - a < 1e-12 * theta_p:
            continue
        mid = 0.5 * (a + b)
        eng = tuple(j for j in range(cut.teeth)
                    if cut.phi_st < np.mod(mid + 2 * np.pi * j / cut.teeth, 2 * np.pi)
                    < cut.phi_ex)
        out.append((a / omega, b / omega, eng))
    return out


def _expm(A: np.ndarray, t_s: float) -> np.ndarray:
    """e^{A t} through the eigen-decomposition (modal state matrices are diagonalizable);
    scipy's Padé ``expm`` when the eigenvector basis is ill-conditioned."""
    lam, V = np.linalg.eig(A)
    if np.linalg.cond(V) < 1e8:
        return ((V * np.exp(lam * t_s)) @ np.linalg.inv(V)).real
    return scipy.linalg.expm(A * t_s)


def _block_diag(blocks: np.ndarray) -> np.ndarray:
    """Block-diagonal matrix of a stack ``(p, r, c)`` -> ``(p r, p c)``."""
    p, r, c = blocks.shape
    out = np.zeros((p, r, p, c))
    out[np.arange(p), :, np.arange(p), :] = blocks
    return out.reshape(p * r, p * c)


def _w_engaged(cut: CuttingModel, phi0: np.ndarray, teeth: tuple[int, ...]) -> np.ndarray:
    """W at tooth-0 angles φ₀ summed over a fixed set of engaged teeth (one-sided at the
    segment ends, where g jumps), ``(len(phi0), n_rows, 2)``."""
    out = np.zeros(np.shape(phi0) + (cut.n_rows, 2))
    for j in teeth:
        out += cut.w(phi0 + 2 * np.pi * j / cut.teeth)
    return out


@dataclass
class SpeedOperator:
    """The depth-independent pieces of the period map at one speed and order p: the exact
    free-flight transitions and, per element, the collocation matrices, so that each depth
    costs one solve per element and one eigenvalue problem."""

    tool: LinearTool
    tau_s: float
    p: int
    steps: list
    """``("free", e^{AΔt})`` or ``("elem", K0, L1, Rd, D10k, Cp)``: M(a) = K0 − a L1 with
    K0 = D11 ⊗ I − I ⊗ A and L1 = diag(B W_i C); Rd = diag(B W_i) (delayed outputs);
    D10k = D10 ⊗ I (first node); Cp = I ⊗ C (outputs at the nodes)."""
    n_elem: int

    @property
    def dim(self) -> int:
        return self.tool.n_states + 2 * self.p * self.n_elem

    def monodromy(self, depths_m: np.ndarray) -> np.ndarray:
        """Φ(a) for each depth, ``(len(depths), dim, dim)``; state (s at the period start,
        d = C s at the nodes 1 … p of every element)."""
        n, p = self.tool.n_states, self.p
        a = np.atleast_1d(np.asarray(depths_m, float))
        na, dim = a.size, self.dim
        cur = np.zeros((na, n, dim))
        cur[:, :, :n] = np.eye(n)
        rows_d = []
        col = n
        for kind, *data in self.steps:
            if kind == "free":
                cur = data[0] @ cur
                continue
            K0, L1, Rd, D10k, Cp = data
            M = K0[None] - a[:, None, None] * L1[None]
            rhs = -(D10k @ cur)
            rhs[:, :, col:col + 2 * p] -= a[:, None, None] * Rd[None]
            S = np.linalg.solve(M, rhs)  # (na, p n, dim)
            rows_d.append(Cp @ S)
            cur = S[:, -n:]
            col += 2 * p
        return np.concatenate([cur, *rows_d], axis=1)

    def spectral_radius(self, depths_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """ρ(Φ(a)) and the critical multiplier for each depth."""
        mu = np.linalg.eigvals(self.monodromy(depths_m))
        idx = np.argmax(np.abs(mu), axis=-1)
        crit = np.take_along_axis(mu, idx[:, None], -1)[:, 0]
        return np.abs(crit), crit


def elements_per_segment(tool: LinearTool, duration_s: float) -> int:
    """Elements in a cutting segment: each spans at most :data:`CYCLES_PER_ELEMENT` periods of
    the tool's fastest natural frequency (so p stays small where the segment is long)."""
    f_max = float(np.max(tool.natural_frequencies_hz(), initial=0.0))
    return max(1, int(np.ceil(duration_s * f_max / CYCLES_PER_ELEMENT)))


def speed_operator(tool: LinearTool, cut: CuttingModel, spindle_rpm: float,
                   p: int = NODES) -> SpeedOperator:
    """Build the period map pieces of :class:`SpeedOperator` at one spindle speed."""
    x, D = cheb(p)
    n = tool.n_states
    tau = 60.0 / (cut.teeth * float(spindle_rpm))
    omega = 2 * np.pi * float(spindle_rpm) / 60.0
    eye = np.eye(n)
    steps, n_elem = [], 0
    for t0, t1, teeth in segments(cut, spindle_rpm):
        if not teeth:
            steps.append(("free", _expm(tool.A, t1 - t0)))
            continue
        ne = elements_per_segment(tool, t1 - t0)
        edges = np.linspace(t0, t1, ne + 1)
        for ea, eb in zip(edges[:-1], edges[1:], strict=True):
            h = eb - ea
            Dt = D * (2.0 / h)
            t_nodes = ea + (x[1:] + 1.0) * 0.5 * h
            W = conform_rows(_w_engaged(cut, omega * t_nodes, teeth), tool.n_inputs)
            BW = np.einsum("ik,pkl->pil", tool.B, W)  # (p, n, 2)
            K0 = np.kron(Dt[1:, 1:], eye) - np.kron(np.eye(p), tool.A)
            L1, Rd = _block_diag(BW @ tool.C), _block_diag(BW)
            steps.append(("elem", K0, L1, Rd, np.kron(Dt[1:, :1], eye),
                          np.kron(np.eye(p), tool.C)))
            n_elem += 1
    return SpeedOperator(tool, tau, p, steps, n_elem)


def sem_spectral_radius(tool: LinearTool, cut: CuttingModel, spindle_rpm: float,
                        depths_m: np.ndarray, p: int = NODES) -> tuple[np.ndarray, np.ndarray]:
    """Spectral radius ρ(Φ) and the critical multiplier μ for each depth (ρ < 1: stable)."""
    return speed_operator(tool, cut, spindle_rpm, p).spectral_radius(depths_m)


GRID_ROOT_POINTS = 3
"""Depths per batched evaluation of the root search (the bracket shrinks 4× per call)."""


def _grid_root(op: SpeedOperator, lo: float, hi: float, xtol_rel: float,
               rho_lo: float | None = None, rho_hi: float | None = None) -> float:
    """The first crossing of ρ(a) = 1 in [lo, hi] by batched bracketing: each call evaluates
    :data:`GRID_ROOT_POINTS` depths inside the bracket (one batched eigenvalue problem) and
    keeps the sub-interval of the first unstable one, until the bracket is below
    2·``xtol_rel``·hi; then linear interpolation of ρ − 1 inside it (the result stays in the
    bracket, so its error is below the bracket width). NaN when [lo, hi] has no unstable
    depth (ends included)."""
    if rho_lo is None or rho_hi is None:
        grid = np.linspace(lo, hi, GRID_ROOT_POINTS + 2)
        rho, _ = op.spectral_radius(grid)
        bad = np.nonzero(rho >= 1.0)[0]
        if bad.size == 0:
            return float("nan")
        j = int(bad[0])
        if j == 0:
            return float(lo)
        lo, hi, rho_lo, rho_hi = grid[j - 1], grid[j], rho[j - 1], rho[j]
    while hi - lo > 2 * xtol_rel * hi:
        grid = np.linspace(lo, hi, GRID_ROOT_POINTS + 2)[1:-1]
        rho, _ = op.spectral_radius(grid)
        bad = np.nonzero(rho >= 1.0)[0]
        if bad.size == 0:
            lo, rho_lo = grid[-1], rho[-1]
        else:
            j = int(bad[0])
            if j > 0:
                lo, rho_lo = grid[j - 1], rho[j - 1]
            hi, rho_hi = grid[j], rho[j]
    w = (1.0 - rho_lo) / (rho_hi - rho_lo) if rho_hi > rho_lo else 0.5
    return float(lo + min(max(w, 0.0), 1.0) * (hi - lo))


def _scan_root(op: SpeedOperator, depth_max_m: float, n_scan: int, xtol_rel: float,
               extra_m: np.ndarray | None = None) -> float:
    """Geometric scan of ``n_scan`` depths from ``depth_max_m``/300 to ``depth_max_m`` (with
    ``extra_m`` depths added: the warm start's fine bracket around the neighbouring speed's
    depth), all in one batch, for the first unstable one; then :func:`_grid_root` in the
    bracket below it (NaN: stable up to ``depth_max_m``)."""
    scan = np.geomspace(depth_max_m / 300.0, depth_max_m, n_scan)
    if extra_m is not None:
        extra = np.asarray(extra_m, float)
        scan = np.unique(np.concatenate([scan, extra[(extra > 0) & (extra < depth_max_m)]]))
    rho, _ = op.spectral_radius(scan)
    bad = np.nonzero(rho >= 1.0)[0]
    if bad.size == 0:
        return float("nan")
    j = int(bad[0])
    if j == 0:  # unstable at the smallest depth scanned: bracket down to zero depth
        rho0 = float(op.spectral_radius([0.0])[0][0])
        return _grid_root(op, 0.0, scan[0], xtol_rel, rho0, rho[0])
    return _grid_root(op, scan[j - 1], scan[j], xtol_rel, rho[j - 1], rho[j])


def _near_root(op: SpeedOperator, a0: float, depth_max_m: float, n_scan: int,
               xtol_rel: float, width: float) -> float:
    """The same speed at a finer order: the root in the bracket a0(1 ± width) around the
    coarser order's root (widened once to 4×; the coarser order's island structure is
    trusted), a full scan when it holds no crossing."""
    for w in (width, 4 * width):
        lo, hi = a0 * (1 - w), min(a0 * (1 + w), depth_max_m)
        grid = np.linspace(lo, hi, GRID_ROOT_POINTS + 2)
        rho, _ = op.spectral_radius(grid)
        bad = np.nonzero(rho >= 1.0)[0]
        if bad.size and bad[0] > 0:
            j = int(bad[0])
            return _grid_root(op, grid[j - 1], grid[j], xtol_rel, rho[j - 1], rho[j])
    return _scan_root(op, depth_max_m, n_scan, xtol_rel)


WARM_WIDTH = 0.05
"""Warm start: depths at a0(1 + WARM_WIDTH·{−1, −½, 0, ½, 1}) around the neighbouring speed's
critical depth a0 join the scan, so a lobe that continues from the neighbour is bracketed to
±2.5 % at once (and a narrow one the scan alone would step over is kept)."""


@dataclass
class CriticalDepth:
    """Critical depth at one speed with its error estimate."""

    a_crit_m: float
    error_m: float
    mu: complex
    p: int


def critical_depth(tool: LinearTool, cut: CuttingModel, spindle_rpm: float, *,
                   depth_max_m: float, accuracy: float = ACCURACY, p0: int = NODES,
                   n_scan: int = N_SCAN, guess_m: float | None = None) -> CriticalDepth:
    """Smallest unstable axial depth at one speed, refined until its estimated relative
    discretization error meets ``accuracy``.

    Parameters
    ----------
    tool, cut
        Tool and cutting models.
    spindle_rpm
        Spindle speed [rpm].
    depth_max_m
        Largest depth searched (nan if stable up to it).
    accuracy
        Target relative error of the critical depth (0.005 = 0.5 %).
    p0
        Starting collocation order.
    n_scan
        Depths of the geometric scan that finds the first unstable bracket.
    guess_m
        Critical depth at a neighbouring speed (warm start): a fine bracket around it joins
        the scan (:data:`WARM_WIDTH`).

    Returns
    -------
    CriticalDepth
        ``a_crit_m`` from order p + P_STEP, ``error_m`` = |a(p + P_STEP) − a(p)| + the root
        tolerance, ``mu`` the critical multiplier just above the boundary, ``p`` the finer
        order used.
    """
    if not 0 < accuracy < 1:
        raise ValueError(f"accuracy must be in (0, 1), got {accuracy}")
    xtol = accuracy / 20.0
    p = int(p0)
    op = speed_operator(tool, cut, spindle_rpm, p)
    extra = (guess_m * (1 + WARM_WIDTH * np.linspace(-1.0, 1.0, 5))
             if guess_m is not None and np.isfinite(guess_m) else None)
    a_lo = _scan_root(op, depth_max_m, n_scan, xtol, extra)
    while True:
        op_hi = speed_operator(tool, cut, spindle_rpm, p + P_STEP)
        if not np.isfinite(a_lo):
            # stable to depth_max at order p: confirm at the finer order
            a_hi = _scan_root(op_hi, depth_max_m, n_scan, xtol)
            if not np.isfinite(a_hi):
                _, mu = op_hi.spectral_radius([depth_max_m])
                return CriticalDepth(float("nan"), float("nan"), complex(mu[0]), p + P_STEP)
        else:
            a_hi = _near_root(op_hi, a_lo, depth_max_m, n_scan, xtol,
                              width=max(2 * accuracy, 10 * xtol))
        err = abs(a_hi - a_lo) + 2 * xtol * a_hi if np.isfinite(a_lo) else float("inf")
        if err <= accuracy * a_hi or p + P_STEP >= P_MAX:
            _, mu = op_hi.spectral_radius([a_hi * (1 + xtol)])
            return CriticalDepth(a_hi, err if np.isfinite(err) else float("nan"),
                                 complex(mu[0]), p + P_STEP)
        p, op, a_lo = p + P_STEP, op_hi, a_hi


@lobe_parameters
def sem_lobes(tool: LinearTool, cut: CuttingModel, spindle_rpm: np.ndarray, *,
              depth_max_m: float, accuracy: float = ACCURACY, p0: int = NODES,
              n_scan: int = N_SCAN, f_ref_hz: np.ndarray | None = None, progress=None,
              warm_start: bool = True) -> dict[str, np.ndarray]:
    """Spectral-element lobe diagram on a speed grid, each depth with its error estimate.

    Parameters
    ----------
    {lobe: tool, cut; spindle_rpm; depth_max_m}
    accuracy
        Target relative error per speed (refinement of p until it is met).
    p0, n_scan
        Starting order and scan size (:func:`critical_depth`).
    {lobe: f_ref_hz}
    warm_start
        Start each speed's search from the neighbouring speed's depth.

    Returns
    -------
    dict with arrays over the speeds: ``a_crit_m``, ``error_m`` (estimated |a − a_∞|),
    ``chatter_hz``, ``kind`` (fold, flip, hopf or ''), ``p`` (collocation order used).
    """
    n_t = np.atleast_1d(np.asarray(spindle_rpm, float))
    f_ref = reference_frequencies_hz(tool, n_t.size, f_ref_hz)
    out = {"a_crit_m": np.full(n_t.shape, np.nan), "error_m": np.full(n_t.shape, np.nan),
           "chatter_hz": np.full(n_t.shape, np.nan), "kind": np.full(n_t.shape, "", object),
           "p": np.zeros(n_t.shape, int)}
    guess = None
    for i, n in enumerate(n_t):
        if progress is not None:
            progress(i / len(n_t))
        r = critical_depth(tool, cut, n, depth_max_m=depth_max_m, accuracy=accuracy, p0=p0,
                           n_scan=n_scan, guess_m=guess if warm_start else None)
        out["a_crit_m"][i], out["error_m"][i], out["p"][i] = r.a_crit_m, r.error_m, r.p
        if np.isfinite(r.a_crit_m):
            out["kind"][i] = classify_multiplier(r.mu)
            out["chatter_hz"][i] = multiplier_frequency_hz(r.mu, 60.0 / (cut.teeth * n),
                                                           f_ref[i])
        guess = r.a_crit_m
    out["kind"] = out["kind"].astype(str)
    return out
