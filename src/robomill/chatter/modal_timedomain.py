"""Shagniev 2019's regenerative cut on a modal tool: the time-domain check of a predicted stability.

The chip and force law are the seed's (Shagniev, Shanshin & Burdakov 2019; the conventions of
:mod:`robomill.chatter`): tooth j at cutter angle φ_j = Ω t + 2π j/N cuts while
φ_st < φ_j < φ_ex with chip thickness

    h_j = c sin φ_j + Δx sin φ_j + Δy cos φ_j,   Δ = d(t) − d(t − τ),   h_j ≥ 0

(c the feed per tooth, τ = 60/(N n) the tooth period, d the tool-tip displacement in the cut
frame: x feed, y normal), and with the edge terms of Altintas 2012 eq. 2.25

    F_t = a (K_tc κ h + K_te),  F_r = a (K_rc κ h + K_re),  F_a = a (K_ac h + K_ae),
    F_x = Σ −F_t cos φ − F_r sin φ,   F_y = Σ F_t sin φ − F_r cos φ,   F_z = Σ F_a

(κ = 1 + σ ξ a per-pass cutting-coefficient scatter, as the Shagniev 2019 simulation's
``Kt_noise_fraction``: the broadband excitation a stable cut damps and an unstable one grows
from). Instead of the seed's arm–suspension structure the tool is a sum of modes
(f_r, ζ_r, k_r, in-plane shape φ_r), d = Σ φ_r η_r, each modal coordinate an oscillator
η̈ + 2ζω η̇ + ω² η = φ_rᵀF / m_r (m_r = k_r/ω_r²), advanced exactly over a step with the force
held (zero-order hold; the delay is a whole number of steps). The run starts at the static
deflection under the mean force (no entry transient).

The planner's critical depth is the smaller of the regenerative lobes and the mode-coupling
depth (:mod:`robomill.plan.lobes`); the check runs the cut twice, with Tlusty's overlap factor
μ = 1 (the seed's regenerative chip) and μ = 0 (the delay-free chip of mode coupling), and
calls it stable when the vibration grows in neither run (:func:`stability_verdict`).

The delay-free run has the linear chip (``linear_chip``: every tooth inside its engagement
cuts h of either sign). Mode coupling is a linear mechanism (Tlusty; the planner's
mode-coupling depth is the eigenvalue limit of the linear delay-free system), and a delay-free
chip carries no memory of the surface: a tooth that leaves the cut there leaves no uncut
material for the next one, so the seed's h ≥ 0 clipping would make that run a different,
unphysical model. At the thesis' feeds per tooth (1–11 µm) that clipping acts at vibrations
of a fraction of a micrometre near the entry and exit (where c sin φ → 0): it can hold a
delay-free run that grows in its linear model to no growth, and kick one that decays into a
limit cycle with teeth out of the cut. The regenerative run keeps the seed's
chip: the surface it cuts is the one the previous tooth left.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from robomill.chatter.detection import chatter_indicator


@dataclass(frozen=True)
class ModalCut:
    """One cut to simulate: the tool's modes in the cut frame and the process (SI units).

    ``shape_xy`` ``(M, 2)`` in-plane mode shapes (feed, normal); coefficients in N/m² (cutting)
    and N/m (edge)."""

    f_hz: np.ndarray
    zeta: np.ndarray
    k_N_m: np.ndarray
    shape_xy: np.ndarray
    spindle_rpm: float
    teeth: int
    entry_rad: float
    exit_rad: float
    feed_per_tooth_m: float
    depth_m: float
    Ktc_N_m2: float
    Krc_N_m2: float
    Kac_N_m2: float
    Kte_N_m: float = 0.0
    Kre_N_m: float = 0.0
    Kae_N_m: float = 0.0
    overlap: float = 1.0
    """Tlusty's overlap factor μ in Δ = d(t) − μ d(t − τ) − (1 − μ) d̄: 1 regenerative
    [Shagniev 2019], 0 the delay-free chip of mode coupling (the surface does not carry the
    vibration; d̄ the static deflection under the mean force, which only shifts the path)."""
    linear_chip: bool = False
    """False: the seed's chip, a tooth whose h ≤ 0 cuts nothing (it has left the cut). True:
    every tooth between entry and exit cuts its chip h of either sign, the force linear in
    the vibration: the model whose eigenvalues the lobes and the mode-coupling depth are
    (the delay-free check run; module docstring)."""

    @property
    def tooth_hz(self) -> float:
        return self.teeth * self.spindle_rpm / 60.0


def modal_steps(f_hz: np.ndarray, zeta: np.ndarray, k_N_m: np.ndarray, dt_s: float
                ) -> tuple[np.ndarray, np.ndarray]:
    """Exact one-step transition of each modal oscillator under a held force: Φ ``(M, 2, 2)``
    = e^{A dt} and Γ ``(M, 2)`` = A⁻¹(Φ − I) b, state (η, η̇), A = [[0, 1], [−ω², −2ζω]],
    b = (0, 1/m) (ω² /k)."""
    from scipy.linalg import expm

    w = 2 * np.pi * np.asarray(f_hz, float)
    Phi = np.empty((w.size, 2, 2))
    Gam = np.empty((w.size, 2))
    for r, (wr, zr, kr) in enumerate(zip(w, np.asarray(zeta, float), np.asarray(k_N_m, float),
                                         strict=True)):
        A = np.array([[0.0, 1.0], [-wr**2, -2 * zr * wr]])
        P = expm(A * dt_s)
        Phi[r] = P
        Gam[r] = np.linalg.solve(A, (P - np.eye(2)) @ np.array([0.0, wr**2 / kr]))
    return Phi, Gam


@numba.njit(cache=True)
def _run(Phi, Gam, shape, eta, n_steps, m_delay, dt, omega, teeth, phst, phex, c, a,
         coef, kt_pass, overlap, d0x, d0y, linear, rec_every, rec, f_ext):
    """Advance every mode ``n_steps``; record (Fx, Fy, Fz, Δx, Δy, teeth out of the cut,
    teeth deep in the cut) every ``rec_every`` steps (a tooth is deep in the cut where
    sin φ > 1/2; out of it where its chip is then ≤ 0). ``linear``: a tooth between entry
    and exit cuts whatever the sign of its chip (the count of teeth with h ≤ 0 is kept).
    ``f_ext`` ``(n_ext, 2)``: an external in-plane force on the tool at each step (step k
    takes row min(k, n_ext − 1)); it moves the modes and is not recorded."""
    M = Phi.shape[0]
    n_ext = f_ext.shape[0]
    hx = np.empty(n_steps + 1)
    hy = np.empty(n_steps + 1)
    two_pi = 2.0 * np.pi
    nrec = 0
    for k in range(n_steps):
        dx = 0.0
        dy = 0.0
        for r in range(M):
            dx += shape[r, 0] * eta[r, 0]
            dy += shape[r, 1] * eta[r, 0]
        hx[k] = dx
        hy[k] = dy
        if k >= m_delay:
            ddx = dx - overlap * hx[k - m_delay] - (1.0 - overlap) * d0x
            ddy = dy - overlap * hy[k - m_delay] - (1.0 - overlap) * d0y
        else:
            ddx = dx - d0x
            ddy = dy - d0y
        t = k * dt
        Fx = 0.0
        Fy = 0.0
        Fz = 0.0
        out = 0.0
        deep = 0.0
        for j in range(teeth):
            turns = (omega * t + two_pi * j / teeth) / two_pi
            phi = (turns - np.floor(turns)) * two_pi
            if phi > phst and phi < phex:
                sp = np.sin(phi)
                cp = np.cos(phi)
                h = c * sp + ddx * sp + ddy * cp
                if sp > 0.5:
                    deep += 1.0
                    if h <= 0.0:
                        out += 1.0
                if h > 0.0 or linear:
                    pas = min(int(np.floor(turns)) * teeth + j, kt_pass.size - 1)
                    kap = kt_pass[pas]
                    Ft = a * (coef[0] * kap * h + coef[3])
                    Fr = a * (coef[1] * kap * h + coef[4])
                    Fa = a * (coef[2] * h + coef[5])
                    Fx += -Ft * cp - Fr * sp
                    Fy += Ft * sp - Fr * cp
                    Fz += Fa
        ke = min(k, n_ext - 1)
        for r in range(M):
            f = shape[r, 0] * (Fx + f_ext[ke, 0]) + shape[r, 1] * (Fy + f_ext[ke, 1])
            e0 = Phi[r, 0, 0] * eta[r, 0] + Phi[r, 0, 1] * eta[r, 1] + Gam[r, 0] * f
            e1 = Phi[r, 1, 0] * eta[r, 0] + Phi[r, 1, 1] * eta[r, 1] + Gam[r, 1] * f
            eta[r, 0] = e0
            eta[r, 1] = e1
        if k % rec_every == 0:
            rec[nrec, 0] = Fx
            rec[nrec, 1] = Fy
            rec[nrec, 2] = Fz
            rec[nrec, 3] = ddx
            rec[nrec, 4] = ddy
            rec[nrec, 5] = out
            rec[nrec, 6] = deep
            nrec += 1
    return nrec


def warm_kernels() -> None:
    """Run a tiny cut (compiles :func:`_run`, or loads it from the cache;
    :func:`robomill.kernels.ready`)."""
    cut = ModalCut(np.array([50.0]), np.array([0.05]), np.array([1e7]), np.array([[0.0, 1.0]]),
                   30000.0, 2, 0.0, np.pi, 1e-5, 5e-4, 796e6, 168e6, 222e6)
    _simulate_modal_cut(cut, duration_s=1e-3, steps_per_tooth=8)


def simulate_modal_cut(cut: ModalCut, *, duration_s: float, steps_per_tooth: int = 32,
                       Kt_noise_fraction: float = 0.005, noise_seed: int = 0,
                       record_every: int = 1, excitation_N: float = 0.0,
                       excitation_band_hz: float = 1000.0) -> dict[str, np.ndarray | float]:
    """The cut's force and regenerative displacement over ``duration_s``.

    ``excitation_N``: the structure's own excitation besides the cut (servo noise, motor
    ripple), a white force on the tool along each in-plane axis with that standard deviation,
    low-passed to ``excitation_band_hz`` (4th-order Butterworth, zero phase), drawn from
    ``noise_seed``'s own stream; 0 (default) adds none.

    Returns ``t_s``, ``force_N`` ``(n, 3)`` (cut frame, on the tool), ``delta_m`` ``(n, 2)``,
    ``teeth_out`` and ``teeth_deep`` (per sample: teeth with sin φ > 1/2 whose chip is ≤ 0, and
    all teeth with sin φ > 1/2) and ``fs_hz`` (the record's rate).

    Examples
    --------
    Without vibration the mean force is Altintas 2012 eq. 2.25:

    >>> from robomill.forces import CuttingCoefficients, mean_milling_forces
    >>> cut = ModalCut(np.array([50.0]), np.array([0.05]), np.array([1e12]),
    ...                np.array([[0.0, 1.0]]), 30000.0, 2, 0.0, np.pi, 1e-5, 5e-4,
    ...                796e6, 168e6, 222e6, 27.7e3, 30.8e3, 6.7e3)
    >>> F = simulate_modal_cut(cut, duration_s=0.02, steps_per_tooth=2048,
    ...                        Kt_noise_fraction=0.0)["force_N"].mean(0)
    >>> ref = mean_milling_forces(0.01, 0.5, CuttingCoefficients(796, 168, 222, 27.7, 30.8, 6.7))
    >>> bool(np.allclose(F, ref, rtol=2e-3))
    True
    """
    from robomill.kernels import ready

    ready(__name__)  # the kernel compiled once per environment (robomill.kernels)
    return _simulate_modal_cut(cut, duration_s=duration_s, steps_per_tooth=steps_per_tooth,
                               Kt_noise_fraction=Kt_noise_fraction, noise_seed=noise_seed,
                               record_every=record_every, excitation_N=excitation_N,
                               excitation_band_hz=excitation_band_hz)


def white_force_N(n: int, dt_s: float, sigma_N: float, band_hz: float, seed: int
                  ) -> np.ndarray:
    """``(n, 2)`` independent white forces low-passed to ``band_hz`` (4th-order Butterworth,
    zero phase, :func:`scipy.signal.sosfiltfilt`), each scaled to standard deviation
    ``sigma_N``; ``(1, 2)`` zeros where ``sigma_N`` is 0."""
    if not sigma_N > 0:
        return np.zeros((1, 2))
    from scipy.signal import butter, sosfiltfilt

    w = np.random.default_rng([int(seed), 1]).standard_normal((int(n), 2))
    if band_hz < 0.5 / dt_s:
        w = sosfiltfilt(butter(4, float(band_hz), fs=1.0 / dt_s, output="sos"), w, axis=0)
    return np.ascontiguousarray(w * (float(sigma_N) / w.std(0)))


def _simulate_modal_cut(cut: ModalCut, *, duration_s: float, steps_per_tooth: int = 32,
                        Kt_noise_fraction: float = 0.005, noise_seed: int = 0,
                        record_every: int = 1, excitation_N: float = 0.0,
                        excitation_band_hz: float = 1000.0) -> dict[str, np.ndarray | float]:
    tau = 60.0 / (cut.teeth * cut.spindle_rpm)
    m = int(steps_per_tooth)
    dt = tau / m
    n = int(np.ceil(duration_s / dt))
    fn, k = np.asarray(cut.f_hz, float), np.asarray(cut.k_N_m, float)
    shape = np.ascontiguousarray(np.asarray(cut.shape_xy, float).reshape(-1, 2))
    Phi, Gam = modal_steps(fn, cut.zeta, k, dt)
    from robomill.forces import CuttingCoefficients, mean_milling_forces

    coeffs = CuttingCoefficients(cut.Ktc_N_m2 * 1e-6, cut.Krc_N_m2 * 1e-6, cut.Kac_N_m2 * 1e-6,
                                 cut.Kte_N_m * 1e-3, cut.Kre_N_m * 1e-3, cut.Kae_N_m * 1e-3)
    F0 = mean_milling_forces(cut.feed_per_tooth_m * 1e3, cut.depth_m * 1e3, coeffs,
                             flutes=cut.teeth, entry_rad=cut.entry_rad, exit_rad=cut.exit_rad)
    eta = np.zeros((fn.size, 2))
    eta[:, 0] = (shape @ F0[:2]) / k                    # static deflection under the mean force
    n_pass = int(np.ceil(duration_s / tau)) + 2 * cut.teeth + 2
    xi = np.random.default_rng(int(noise_seed)).standard_normal(n_pass)
    kt_pass = np.clip(1.0 + float(Kt_noise_fraction) * xi, 0.0, None)
    coef = np.array([cut.Ktc_N_m2, cut.Krc_N_m2, cut.Kac_N_m2, cut.Kte_N_m, cut.Kre_N_m,
                     cut.Kae_N_m])
    every = int(record_every)
    rec = np.zeros((n // every + 1, 7))
    d0 = shape.T @ eta[:, 0]
    nrec = _run(Phi, Gam, shape, eta, n, m, dt, 2 * np.pi * cut.spindle_rpm / 60.0,
                int(cut.teeth), float(cut.entry_rad), float(cut.exit_rad),
                float(cut.feed_per_tooth_m), float(cut.depth_m), coef, kt_pass,
                float(cut.overlap), float(d0[0]), float(d0[1]), bool(cut.linear_chip), every,
                rec, white_force_N(n, dt, excitation_N, excitation_band_hz, noise_seed))
    rec = rec[:nrec]
    return {"t_s": np.arange(nrec) * dt * every, "force_N": rec[:, :3], "delta_m": rec[:, 3:5],
            "teeth_out": rec[:, 5], "teeth_deep": rec[:, 6], "fs_hz": 1.0 / (dt * every)}


def vibration_growth(record: dict) -> float:
    """Growth of the regenerative displacement Δ: the RMS of Δ (its mean removed) over the last
    third of the run over its RMS over the middle third (the first third holds the entry
    transient); +inf where the run diverged. About e^{σT/3} for a vibration growing at rate σ
    over a run of T, about 1 for a stationary one."""
    D = np.asarray(record["delta_m"], float)
    if not np.all(np.isfinite(D)):
        return float("inf")
    n = len(D) // 3
    mid, last = D[n:2 * n], D[2 * n:]
    rms = [np.sqrt(np.mean(np.sum((x - x.mean(0)) ** 2, 1))) for x in (mid, last)]
    return float(rms[1] / rms[0]) if rms[0] > 0 else float("inf")


@dataclass(frozen=True)
class Verdict:
    """The time-domain outcome of one cut."""

    stable: bool
    growth_regenerative: float
    """:func:`vibration_growth` of the regenerative run (μ = 1)."""
    growth_coupling: float
    """:func:`vibration_growth` of the delay-free run (μ = 0, mode coupling)."""
    chatter_hz: float
    """Frequency of chapter 4's indicator line over the last third of the faster-growing run."""
    indicator_N: float
    """That line's amplitude [N]."""
    out_of_cut_fraction: float
    """Over the last third of the regenerative run (the seed's chip), the share of teeth deep in
    the cut (sin φ > 1/2) whose chip was ≤ 0 (the tool jumping out of the cut: a saturated
    vibration)."""
    mean_force_N: np.ndarray
    """Mean force over the last two thirds of the regenerative run ``(3,)`` (cut frame, on the
    tool)."""


def stability_verdict(regenerative: dict, coupling: dict, tooth_hz: float, *,
                      band_hz: tuple[float, float], harmonic_halfwidth_hz: float,
                      growth_ratio: float, max_out_of_cut_fraction: float = 0.05) -> Verdict:
    """Chatter or not from the two runs of :func:`simulate_modal_cut` (overlap μ = 1 with the
    seed's chip, and μ = 0 with the linear chip: the two mechanisms whose smaller critical
    depth the planner predicts, :func:`robomill.plan.predict.critical_depth_m`): stable when
    the vibration grows less than ``growth_ratio`` times between the middle and the last third
    of both runs (:func:`vibration_growth`) and the teeth stay in the cut in the regenerative
    run (at most ``max_out_of_cut_fraction`` of the teeth deep in the cut leave it over the last
    third: a vibration that grew and saturated early). The teeth of the delay-free run are not
    counted: its chip is linear (nothing saturates it, an unstable run grows) and a tooth
    leaving a delay-free cut has no physical meaning (module docstring). The frequency and
    amplitude of chapter 4's indicator (:func:`chatter_indicator`: the largest line of the
    resultant in-plane force in ``band_hz`` away from the tooth-passing harmonics) over the
    last third of the faster-growing run are reported beside."""
    g = (vibration_growth(regenerative), vibration_growth(coupling))
    worst = regenerative if g[0] >= g[1] else coupling
    F = np.asarray(worst["force_N"], float)
    R = np.hypot(F[:, 0], F[:, 1])[2 * (len(F) // 3):]
    amp, f = (chatter_indicator(R, float(worst["fs_hz"]), tooth_hz, tuple(band_hz),
                                harmonic_halfwidth_hz) if np.all(np.isfinite(R))
              else (float("inf"), float("nan")))
    F1 = np.asarray(regenerative["force_N"], float)
    k = 2 * (len(F1) // 3)
    deep = float(np.sum(regenerative["teeth_deep"][k:]))
    out = float(np.sum(regenerative["teeth_out"][k:])) / deep if deep > 0 else float("nan")
    stable = max(g) < growth_ratio and not out > max_out_of_cut_fraction
    return Verdict(stable=bool(stable), growth_regenerative=g[0],
                   growth_coupling=g[1], chatter_hz=float(f), indicator_N=float(amp),
                   out_of_cut_fraction=out, mean_force_N=F1[len(F1) // 3:].mean(0))
