"""Linear tool models and the milling directional matrix (conventions: package docstring).

The regenerative milling model of every method in this package is

.. math:: \\dot{\\mathbf s} = A\\mathbf s + B\\,\\mathbf R,\\qquad \\mathbf d = C\\mathbf s,
          \\qquad \\mathbf R(t) = a\\,W(t)\\,[\\mathbf d(t) - \\mathbf d(t-\\tau)]

with ``d = (x, y)`` the tool-tip displacement in the cutting frame, ``R`` the cutting force on
the tool, ``a`` the axial depth, τ = 60/(N n) the tooth period and W(t) the directional matrix
(Shagniev 2019 chip and force equations; Altintas 2012 eq. 3.51, there written ½ K_t A(t)).

**The axial force.** The chip h = Δx sin φ + Δy cos φ also drives the axial force
F_z = K_ac a h on each engaged tooth (Altintas 2012 §2.4), and a mode with a shape
component along the tool axis feels it: with :attr:`CuttingModel.Ka` = K_ac/K_tc set, W(t)
gains the axial row K_t K_a (sin φ, cos φ) (3 × 2), and a tool whose modes have three shape
components (feed, normal, axis) takes R = (F_x, F_y, F_z) through B (n × 3) while the chip
still reads the in-plane d = C s. The in-plane response to the axial force, G_{xy,z}, closes
the axial force's regenerative loop; the axial displacement changes no chip. Every solver
of the package takes either form (:func:`conform_rows` matches W's rows to a tool's inputs).

**The edge force's switching** (:class:`EdgeSwitching`, optional). The edge force acts only
while a tooth cuts (Altintas 2012 eq. 2.25). Where the chip c sin φ vanishes at an edge φ_b of
the engagement (sin φ_b = 0: a slot's entry and exit, up milling's entry, down milling's
exit), Δ moves the zero of h by δφ = −gᵀ(φ_b)Δ/(c cos φ_b), so the edge force's impulse per
tooth pass changes by a e(φ_b) gᵀ(φ_b) Δ/(c |cos φ_b| Ω) — a term of R proportional to Δ like
the chip's, and of size K_e/c against K_c, so it matters most at thin chips. As a tooth-period
mean it adds γ N/(2π) Σ_b e gᵀ/(c |cos φ_b|) to W̄ (slot: −γ N/(π c) ((0, K_te), (0, K_re))),
and to the semi-discretization's interval means an impulse in the step holding φ_b. γ = ½:
the tooth cannot cut outside its engagement window, so only the side whose contact shortens
answers, the describing function of a half-wave switch (Gelb & Vander Velde 1968). The
linearisation holds while |gᵀΔ| ≪ c; past that the switch saturates (a tooth whose chip
offset exceeds c leaves the cut).

Gelb & Vander Velde 1968: Gelb, A.; Vander Velde, W. E. *Multiple-Input Describing Functions
and Nonlinear System Design*. McGraw-Hill, 1968.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class ModeXY:
    """A tool-tip mode in the cutting frame: natural frequency, damping ratio, modal stiffness
    and shape (x, y) or (x, y, z), z along the tool axis (the receptance contribution is
    φ_xy φᵀ / (k (1 − r² + 2jζr)), r = ω/ω_n: the in-plane response to a force in every axis
    the shape gives; module docstring)."""

    f_hz: float
    zeta: float
    k_N_m: float
    shape: tuple[float, ...] = (1.0, 0.0)

    @property
    def m_kg(self) -> float:
        """Modal mass k / ω_n²."""
        return self.k_N_m / (2 * np.pi * self.f_hz) ** 2


@dataclass(frozen=True)
class LinearTool:
    """State-space model of the tool tip: ṡ = A s + B R, d = C s (d: the in-plane 2-vector
    x, y; R: the force, x, y or x, y, z as B's columns)."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    modes: tuple[ModeXY, ...] = ()
    """The modes a modal tool was built from (:func:`tool_from_modes`); empty otherwise."""

    @property
    def n_states(self) -> int:
        return self.A.shape[0]

    @property
    def n_inputs(self) -> int:
        """Force components the tool takes: 2 (in-plane) or 3 (with the axial force)."""
        return self.B.shape[1]

    def frf(self, f_hz: np.ndarray) -> np.ndarray:
        """Receptance G(jω), shape ``(2, n_inputs, len(f))`` [m/N] (the in-plane response to
        each force component): of a modal tool the one modal sum
        (:func:`robomill.chatter.coupling.receptance`), else C (jωI − A)⁻¹ B."""
        f = np.atleast_1d(np.asarray(f_hz, float))
        if self.modes:
            from robomill.chatter.coupling import receptance

            m = self.modes
            shapes = np.zeros((len(m), self.n_inputs))
            for r, x in enumerate(m):
                shapes[r, :len(x.shape)] = x.shape
            G = receptance(f, [[x.f_hz for x in m]], [x.zeta for x in m],
                           [[x.k_N_m for x in m]], shapes[None])[0]
            return np.moveaxis(G, 0, -1)
        lam, V = np.linalg.eig(self.A)
        CV = self.C @ V
        VB = np.linalg.solve(V, self.B)
        resp = 1.0 / (2j * np.pi * f[:, None] - lam[None, :])  # (nf, ns)
        return np.einsum("ik,fk,kj->ijf", CV, resp, VB)

    def natural_frequencies_hz(self) -> np.ndarray:
        """Damped natural frequencies of the oscillatory poles (Hz, ascending, unique)."""
        lam = np.linalg.eigvals(self.A)
        f = np.abs(lam.imag[lam.imag > 1e-9]) / (2 * np.pi)
        return np.unique(np.round(f, 9))

    def is_stable(self) -> bool:
        return bool(np.all(np.linalg.eigvals(self.A).real < 0))


def tool_from_modes(modes: Iterable[ModeXY]) -> LinearTool:
    """Modal superposition as state space: q̈_r + 2ζ_rω_r q̇_r + ω_r² q_r = φ_rᵀR / m_r,
    d = Σ φ_r,xy q_r (Altintas 2012 eq. 3.34 per mode). States (q_1, q̇_1, q_2, q̇_2, …).
    Three inputs (R = F_x, F_y, F_z) when any mode has an axial shape component (the others
    0 along the axis), else two."""
    modes = list(modes)
    if not modes:
        raise ValueError("a tool model needs at least one mode")
    d = max(len(m.shape) for m in modes)
    if d not in (2, 3):
        raise ValueError(f"a mode shape has 2 (x, y) or 3 (x, y, z) components, got {d}")
    n = 2 * len(modes)
    A = np.zeros((n, n))
    B = np.zeros((n, d))
    C = np.zeros((2, n))
    for r, m in enumerate(modes):
        w = 2 * np.pi * m.f_hz
        phi = np.zeros(d)
        phi[:len(m.shape)] = np.asarray(m.shape, float)
        i = 2 * r
        A[i, i + 1] = 1.0
        A[i + 1, i] = -(w**2)
        A[i + 1, i + 1] = -2 * m.zeta * w
        B[i + 1] = phi / m.m_kg
        C[:, i] = phi[:2]
    return LinearTool(A, B, C, tuple(modes))


def conform_rows(W: np.ndarray, n_inputs: int) -> np.ndarray:
    """A directional matrix ``(..., 2|3, 2)`` with as many rows as a tool has force inputs:
    the axial row dropped for an in-plane tool (no mode feels it), a zero axial row added for
    a cut without an axial coefficient."""
    W = np.asarray(W)
    rows = W.shape[-2]
    if rows == n_inputs:
        return W
    if rows == 3 and n_inputs == 2:
        return W[..., :2, :]
    if rows == 2 and n_inputs == 3:
        return np.concatenate([W, np.zeros(W.shape[:-2] + (1, 2))], axis=-2)
    raise ValueError(f"a directional matrix of {rows} rows for a tool of {n_inputs} inputs")


def modes_from_xy_lists(x: Iterable[dict], y: Iterable[dict]) -> list[ModeXY]:
    """Case-schema modes (``{f_hz, zeta, k_N_m}`` per direction, summed) as :class:`ModeXY`."""
    out = [ModeXY(float(m["f_hz"]), float(m["zeta"]), float(m["k_N_m"]), (1.0, 0.0)) for m in x]
    out += [ModeXY(float(m["f_hz"]), float(m["zeta"]), float(m["k_N_m"]), (0.0, 1.0)) for m in y]
    return out


def immersion_angles(radial_immersion: float, milling: str) -> tuple[float, float]:
    """Entry and exit angles (φ_st, φ_ex) [rad] for radial immersion a_e/D and up/down milling
    (Altintas 2012 §3.2: up φ_st = 0, φ_ex = acos(1 − 2a_e/D); down φ_st = acos(2a_e/D − 1),
    φ_ex = π)."""
    r = float(radial_immersion)
    if not 0 < r <= 1:
        raise ValueError(f"radial_immersion must be in (0, 1], got {r}")
    if milling == "up":
        return 0.0, float(np.arccos(1 - 2 * r))
    if milling == "down":
        return float(np.arccos(2 * r - 1)), float(np.pi)
    raise ValueError(f"milling must be 'up' or 'down', got {milling!r}")


@dataclass(frozen=True)
class EdgeSwitching:
    """The linearised switching of the edge force where the chip vanishes (module docstring):
    edge coefficients per unit depth K_te, K_re, K_ae [N/m], the feed per tooth c [m] and the
    gain γ (½: a half-wave switch)."""

    Kte_N_m: float
    Kre_N_m: float
    chip_m: float
    gain: float = 0.5
    Kae_N_m: float = 0.0

    def __post_init__(self):
        if not (np.isfinite(self.chip_m) and self.chip_m > 0):
            raise ValueError(f"the feed per tooth must be positive, got {self.chip_m} m")

    def impulses(self, phi_st: float, phi_ex: float, n_rows: int
                 ) -> list[tuple[float, int, np.ndarray]]:
        """(φ_b, +1 at the entry / −1 at the exit, γ e gᵀ/(c |cos φ_b|) ``(n_rows, 2)``) of
        each engagement edge where the chip c sin φ vanishes; ``n_rows`` 3: e with the axial
        edge force K_ae, which switches with the same chip."""
        out = []
        for phi, side in ((phi_st, 1), (phi_ex, -1)):
            s, c = np.sin(phi), np.cos(phi)
            if abs(s) > 1e-9:
                continue
            kt, kr = self.Kte_N_m, self.Kre_N_m
            e = [-kt * c - kr * s, kt * s - kr * c] + ([self.Kae_N_m] if n_rows == 3 else [])
            out.append((float(phi), side,
                        self.gain * np.outer(e, [s, c]) / (self.chip_m * abs(c))))
        return out


@dataclass(frozen=True)
class CuttingModel:
    """Linear cutting-force model: N teeth, K_t [N/m²], K_r = K_rc/K_tc, engagement φ_st…φ_ex,
    and optionally K_a = K_ac/K_tc: then every directional matrix has the axial row (3 × 2;
    module docstring), else it is the planar 2 × 2; and optionally the edge force's switching
    (:class:`EdgeSwitching`), which the mean and interval-mean matrices then hold (the
    zero-order lobes and the semi-discretization; the spectral elements take no impulse)."""

    teeth: int
    Kt_N_m2: float
    Kr: float
    phi_st: float
    phi_ex: float
    Ka: float | None = field(default=None, kw_only=True)
    edge: EdgeSwitching | None = field(default=None, kw_only=True)

    @classmethod
    def from_immersion(cls, teeth: int, Kt_N_m2: float, Kr: float, radial_immersion: float,
                       milling: str, Ka: float | None = None) -> CuttingModel:
        return cls(int(teeth), float(Kt_N_m2), float(Kr),
                   *immersion_angles(radial_immersion, milling),
                   Ka=None if Ka is None else float(Ka))

    @property
    def n_rows(self) -> int:
        """Rows of the directional matrices: 3 with the axial force, else 2."""
        return 2 if self.Ka is None else 3

    def w(self, phi: np.ndarray) -> np.ndarray:
        """Directional matrix of one engaged tooth at angle φ, ``(..., n_rows, 2)`` [N/m²]:
        R = a w(φ) Δ with h = Δx sin φ + Δy cos φ [Shagniev 2019]; the axial row
        K_t K_a (sin φ, cos φ) [Altintas 2012 §2.4]."""
        s, c = np.sin(phi), np.cos(phi)
        kt, kr = self.Kt_N_m2, self.Kr
        rows = [np.stack([-s * (c + kr * s), -c * (c + kr * s)], -1),
                np.stack([s * (s - kr * c), c * (s - kr * c)], -1)]
        if self.Ka is not None:
            rows.append(self.Ka * np.stack([s, c], -1))
        return kt * np.stack(rows, -2)

    def _antiderivative(self, phi: np.ndarray) -> np.ndarray:
        """∫ w(φ) dφ in closed form, ``(..., n_rows, 2)``."""
        s2, c2 = np.sin(2 * phi), np.cos(2 * phi)
        kr = self.Kr
        xx = c2 / 4 - kr * (phi / 2 - s2 / 4)
        xy = -(phi / 2 + s2 / 4) + kr * c2 / 4
        yx = (phi / 2 - s2 / 4) + kr * c2 / 4
        yy = -c2 / 4 - kr * (phi / 2 + s2 / 4)
        rows = [np.stack([xx, xy], -1), np.stack([yx, yy], -1)]
        if self.Ka is not None:
            rows.append(self.Ka * np.stack([-np.cos(phi), np.sin(phi)], -1))
        return self.Kt_N_m2 * np.stack(rows, -2)

    def _engaged_integral(self, pa: np.ndarray, pb: np.ndarray) -> np.ndarray:
        """∫_{pa}^{pb} g(φ) w(φ) dφ for one tooth, with pa in [0, 2π) and pb − pa < 2π."""
        total = np.zeros(np.shape(pa) + (self.n_rows, 2))
        for shift in (0.0, 2 * np.pi):
            lo = np.clip(pa, self.phi_st + shift, self.phi_ex + shift)
            hi = np.clip(pb, self.phi_st + shift, self.phi_ex + shift)
            total += self._antiderivative(hi) - self._antiderivative(lo)
        return total

    def mean_matrix(self) -> np.ndarray:
        """Average over a tooth period of Σ_j g w(φ_j): W̄ = N/(2π) ∫_{φst}^{φex} w dφ
        (Altintas & Budak 1995 zero-order term; = N K_t α / (4π) in Altintas' notation), plus
        γ N/(2π) Σ_b e gᵀ/(c |cos φ_b|) with the edge force's switching (module docstring)."""
        W = self.teeth / (2 * np.pi) * (self._antiderivative(np.array(self.phi_ex))
                                        - self._antiderivative(np.array(self.phi_st)))
        for _, _, E in self._impulses():
            W = W + self.teeth / (2 * np.pi) * E
        return W

    def _impulses(self) -> list[tuple[float, int, np.ndarray]]:
        return ([] if self.edge is None
                else self.edge.impulses(self.phi_st, self.phi_ex, self.n_rows))

    def interval_means(self, m: int) -> np.ndarray:
        """Exact averages of W(t) = Σ_j g(φ_j) w(φ_j) over the m equal sub-intervals of one
        tooth period (φ_j = Ωt + 2πj/N), ``(m, n_rows, 2)``: the piecewise-constant coefficient
        of the semi-discretization (Insperger & Stépán 2004 eq. 8); with the edge force's
        switching, its impulse γ e gᵀ/(c |cos φ_b|) in the step that holds φ_b on its cutting
        side (so that the steps still average to :meth:`mean_matrix`)."""
        dphi = 2 * np.pi / self.teeth / m
        start = np.arange(m) * dphi
        out = np.zeros((m, self.n_rows, 2))
        for j in range(self.teeth):
            pa = np.mod(start + 2 * np.pi * j / self.teeth, 2 * np.pi)
            out += self._engaged_integral(pa, pa + dphi)
        for phi, side, E in self._impulses():  # once per tooth period, on its cutting side
            u = np.mod(phi, 2 * np.pi / self.teeth) / dphi
            i = int(np.floor(u + 1e-9)) if side > 0 else int(np.ceil(u - 1e-9)) - 1
            out[i % m] += E
        return out / dphi

    def instantaneous(self, phi0: np.ndarray) -> np.ndarray:
        """W at cutter angle φ₀ of tooth 0 (sum over teeth with engagement g),
        ``(..., n_rows, 2)``; not defined with the edge switching's impulses."""
        if self.edge is not None:
            raise ValueError("the edge force's switching is an impulse, which the "
                             "instantaneous matrix (the spectral elements) cannot hold: "
                             "use the zero-order lobes or the semi-discretization")
        phi0 = np.asarray(phi0, float)
        out = np.zeros(phi0.shape + (self.n_rows, 2))
        for j in range(self.teeth):
            p = np.mod(phi0 + 2 * np.pi * j / self.teeth, 2 * np.pi)
            g = (p > self.phi_st) & (p < self.phi_ex)
            out += np.where(g[..., None, None], self.w(p), 0.0)
        return out


LOBE_PARAMETERS = {
    "tool, cut": "Tool model and cutting model.",
    "spindle_rpm": "Speeds [rpm].",
    "depth_max_m": "Largest depth searched; speeds stable up to it get ``nan``.",
    "f_ref_hz": "Reference frequency per speed for naming the chatter frequency of a multiplier\n"
                "(default: the tool's most flexible natural frequency).",
}
"""The numpydoc entries the lobe solvers (ZOA, SDM, SEM) share, written once."""


def lobe_parameters(func):
    """Decorator: expand each line ``{lobe: name; name…}`` of ``func``'s docstring into the
    numpydoc entries :data:`LOBE_PARAMETERS` of those names, at that line's indentation."""
    if not func.__doc__:
        return func
    lines = []
    for line in func.__doc__.split("\n"):
        text = line.strip()
        if text.startswith("{lobe:") and text.endswith("}"):
            indent = line[: len(line) - len(line.lstrip())]
            for name in (n.strip() for n in text[6:-1].split(";")):
                lines.append(indent + name)
                lines += [f"{indent}    {d}" for d in LOBE_PARAMETERS[name].split("\n")]
        else:
            lines.append(line)
    func.__doc__ = "\n".join(lines)
    return func
