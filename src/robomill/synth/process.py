"""The cut itself: one closed-loop milling process per cut, which every instrument samples.

A lab's dynamometer, tracker and profilometer all look at one physical cut; so do the
simulators here. :func:`simulate_cut` integrates, for one cut of the virtual study, the
cutting process and the structure together, each step's force moving the tool and the tool's
motion changing the next chip (regeneration):

* **chip** of tooth j at cutter angle φ_j (clockwise from the cross-feed axis, Altintas 2012
  §2.2; the previous tooth at the same angle is tooth j + 1, one tooth period τ earlier):

  .. math:: h_j(t) = c \\sin φ_j + w_j(t) − W(t − τ), \\quad
            w_j = d_x \\sin φ_j + d_y \\cos φ_j + ρ_j

  with d the tool's displacement in the cut frame (x feed, y cross-feed, z up: the structure's
  vibration and static deflection plus the gear trains' path error), ρ_j the tooth's radial
  run-out and W the surface the previous tooth left at that angle. A tooth whose chip is
  h ≤ 0 has left the cut: it removes nothing, and the surface it leaves for the next tooth is
  the old one, one feed per tooth further back (``W(t) = W(t − τ) − c sin φ``; the multiple
  regeneration of Tlusty, which a linear model does not have); a cutting tooth leaves
  ``W(t) = w_j(t)``;
* **force** on the tool (Altintas 2012, eq. 2.25, edge terms included, only while the tooth
  cuts), at the axial depth the tool's axial motion leaves, ``a = max(a₀ − d_z, 0)``:

  .. math:: F_t = κ a(K_{tc} h + K_{te}),\\ F_r = κ a(K_{rc} h + K_{re}),\\
            F_a = κ a(K_{ac} h + K_{ae}),\\
            F_x = Σ −F_t \\cos φ − F_r \\sin φ,\\ F_y = Σ F_t \\sin φ − F_r \\cos φ,\\ F_z = Σ F_a

  κ = 1 + σξ per tooth pass (ξ standard normal): the process noise of the material and the
  chip formation (``synth.process.coefficient_scatter``, *assumed*), the broadband excitation a
  stable cut damps and an unstable one grows from;
* **the robot's own excitation**: its servos and motors shake the arm whether it cuts or
  not (torque ripple, servo noise): a white force of ``synth.process.servo_force_N`` per axis
  (band 0–1 kHz, *assumed*) drives the modes beside the cutting force; the dynamometer, under
  the workpiece, does not measure it (it sees the arm's vibration only through the chip);
* **structure**: the modes of the robot at the cut's pose and of the spindle and tool
  (:func:`robomill.synth.structure.modes_at`), d = Σ φ_r η_r + path error, each modal
  coordinate an oscillator η̈ + 2ζω η̇ + ω² η = φ_rᵀF / m_r advanced exactly over a step
  with the force held (zero-order hold). The run starts at the static deflection under the
  mean force.

The integration step is ``synth.process.oversample`` steps per dynamometer sample (the
delayed surface interpolated linearly between steps; the force held over a step is the mean
over ``synth.process.substeps`` cutter angles within it, so that a tooth entering or leaving
the cut between steps counts by its share); the force is then low-pass filtered (FIR,
cut-off ``synth.dynamometer.anti_alias_fraction`` × fs: the acquisition's anti-alias filter)
and decimated to the dynamometer's rate (the displacement, smooth, is decimated as it is).
The whole cut is
integrated (``experiment.cut_length_mm`` at the cut's feed), or a prefix of it that is
exactly the whole cut's start (:meth:`SimulatedCut.span`). The integration is seeded per cut
(``[seed, 7, crc32(cut)]``). The virtual cell integrates each cut once and stores it
(:mod:`robomill.synth.cutstate`); every instrument samples that stored cut.
"""

from __future__ import annotations

import dataclasses
import zlib
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numba
import numpy as np

from robomill.chatter.modal_timedomain import modal_steps

STREAM = 7
"""Stream number of the closed-loop process in the per-cut random generators."""
SERVO_FS_HZ = 2000.0
"""Rate of the robot's own white excitation (``synth.process.servo_force_N``): band 0–1 kHz."""


@dataclass(frozen=True)
class SimulatedCut:
    """One cut as it happened on the virtual cell (SI units, cut frame x feed, y cross, z up).

    ``t_s`` ``(n,)`` at ``fs_hz``; ``force_N`` ``(n, 3)`` on the tool; ``deflection_m``
    ``(n, 3)`` the structure's displacement (static + dynamic, without the gear path error);
    ``path_error_m`` ``(n, 3)`` the gear trains' TCP error (mean over the cut removed);
    ``frame`` the rotation base ← cut frame; ``teeth_out`` the fraction of the deep tooth
    passages (sin φ > 1/2) whose chip was ≤ 0 (the tooth left the cut: chatter's mark)."""

    cut_id: str
    fs_hz: float
    t_s: np.ndarray
    force_N: np.ndarray
    deflection_m: np.ndarray
    path_error_m: np.ndarray
    frame: np.ndarray
    feed_mm_s: float
    tooth_hz: float
    modes: tuple
    teeth_out: float
    n_full: int = 0
    """Samples of the whole cut (``t_s`` may hold a prefix)."""
    filter_lag: int = 0
    """Group delay of the force's anti-alias filter [samples]: a prefix's last ``filter_lag``
    force samples hold the one before them (the filter has not seen past the prefix)."""
    path_grid_m: np.ndarray | None = None
    """The gear trains' path error on its own grid ``(m, 3)`` [m, cut frame] (what
    ``path_error_m`` interpolates), with its step ``path_dt_s`` [s]."""
    path_dt_s: float = 0.0

    def s_mm(self) -> np.ndarray:
        """Path abscissa of every sample [mm] (constant feed)."""
        return self.t_s * self.feed_mm_s

    def tool_displacement_base_m(self) -> np.ndarray:
        """Deflection + path error in base axes ``(n, 3)`` [m]."""
        return (self.deflection_m + self.path_error_m) @ self.frame.T

    def span(self, length_mm: float | None) -> SimulatedCut:
        """The cut as :func:`simulate_cut` gives it over its first ``length_mm`` (None: the
        whole cut), taken from this longer simulation: the same samples (the integration and
        the filters are causal), the force's last ``filter_lag`` samples held as a prefix's
        are (``teeth_out`` stays the count over this simulation). Raises ``ValueError`` where
        this simulation is shorter than that span."""
        n = span_samples(self.n_full, self.feed_mm_s, self.fs_hz, self.filter_lag, length_mm)
        if n > self.t_s.size:
            raise ValueError(f"cut {self.cut_id}: {n} samples asked of a simulation of "
                             f"{self.t_s.size} (expected a span within the simulated one)")
        if n == self.t_s.size:
            return self
        force = self.force_N[:n].copy()
        if self.filter_lag:
            force[-self.filter_lag:] = force[-self.filter_lag - 1]
        return dataclasses.replace(self, t_s=self.t_s[:n], force_N=force,
                                   deflection_m=self.deflection_m[:n],
                                   path_error_m=self.path_error_m[:n])


def span_samples(n_full: int, feed_mm_s: float, fs_hz: float, filter_lag: int,
                 length_mm: float | None) -> int:
    """Samples :func:`simulate_cut` integrates for the first ``length_mm`` of a cut of
    ``n_full`` samples (None: all): the span and the force filter's delay run past it."""
    if length_mm is None:
        return int(n_full)
    return min(int(n_full), int(np.ceil(float(length_mm) / feed_mm_s * fs_hz))
               + 2 * int(filter_lag) + 1)


def path_error_at_m(t_s: np.ndarray, path_grid_m: np.ndarray, path_dt_s: float) -> np.ndarray:
    """The gear trains' path error ``(n, 3)`` [m] at times ``t_s``, linear between the
    grid's points (step ``path_dt_s``), held beyond its end."""
    u = np.clip(t_s / path_dt_s, 0, path_grid_m.shape[0] - 1)
    grid = np.arange(path_grid_m.shape[0])
    return np.column_stack([np.interp(u, grid, path_grid_m[:, i]) for i in range(3)])




@numba.njit(cache=True)
def _integrate(k0, n, dt, substeps, omega, phase0, teeth, phst, phex, c, a0, coef, kappa,
               runout, Phi, Gam, shape, eta, W, delay, path, path_dt, servo, servo_dt,
               cutting, F_out, d_out, counts):
    """Advance the closed loop ``n`` steps from global step ``k0`` (state ``eta`` and the
    surface ring ``W`` (L, teeth) carried between calls); write the force and the structure's
    displacement of every step into ``F_out``/``d_out``; count deep passages and teeth out.

    The force held over a step is the mean of the force at ``substeps`` equally spaced cutter
    angles within it (the displacement held): a tooth entering or leaving the cut between two
    steps then contributes its share of the step, not all or nothing, which keeps the edge
    force's jumps from aliasing into lines of the record. ``servo`` ``(m, 3)`` is the robot's
    own excitation on a grid of ``servo_dt`` (linear in between): it drives the modes with the
    cutting force but is not part of ``F_out`` (the dynamometer does not see it). Without
    ``cutting`` no tooth touches material (an air pass)."""
    M = Phi.shape[0]
    L = W.shape[0]
    two_pi = 2.0 * np.pi
    npath = path.shape[0]
    nservo = servo.shape[0]
    inv_s = 1.0 / substeps
    for i in range(n):
        k = k0 + i
        t = k * dt
        dx = 0.0
        dy = 0.0
        dz = 0.0
        for r in range(M):
            dx += shape[r, 0] * eta[r, 0]
            dy += shape[r, 1] * eta[r, 0]
            dz += shape[r, 2] * eta[r, 0]
        d_out[i, 0] = dx
        d_out[i, 1] = dy
        d_out[i, 2] = dz
        u = t / path_dt
        p0 = min(int(u), npath - 2)
        w1 = min(u - p0, 1.0)
        dx += (1 - w1) * path[p0, 0] + w1 * path[p0 + 1, 0]
        dy += (1 - w1) * path[p0, 1] + w1 * path[p0 + 1, 1]
        dz += (1 - w1) * path[p0, 2] + w1 * path[p0 + 1, 2]
        a = a0 - dz
        if a < 0.0:
            a = 0.0
        Fx = 0.0
        Fy = 0.0
        Fz = 0.0
        dphi = omega * dt * inv_s  # cutter rotation per sub-step
        cd = np.cos(dphi)
        sd = np.sin(dphi)
        for j in range(teeth if cutting else 0):
            turns0 = (omega * t + phase0 + two_pi * j / teeth) / two_pi
            base = np.floor(turns0)
            phi = (turns0 - base) * two_pi
            sp = np.sin(phi)
            cp = np.cos(phi)
            jp = (j + 1) % teeth
            for sub in range(substeps):
                if sub > 0:  # rotate (sin, cos) by one sub-step
                    sp, cp = sp * cd + cp * sd, cp * cd - sp * sd
                    phi += dphi
                    if phi >= two_pi:
                        phi -= two_pi
                        base += 1.0
                w = dx * sp + dy * cp + runout[j]
                if phi > phst and phi < phex:
                    pos = k + sub * inv_s - delay  # the previous tooth's passage, in steps
                    i0 = int(np.floor(pos))
                    fr = pos - i0
                    if i0 >= 0:
                        Wp = (1.0 - fr) * W[i0 % L, jp] + fr * W[(i0 + 1) % L, jp]
                    else:
                        Wp = w - runout[j] + runout[jp]
                    h = c * sp + w - Wp
                    if sub == 0:
                        deep = sp > 0.5
                        if deep:
                            counts[0] += 1
                        if h > 0.0:
                            W[k % L, j] = w
                        else:
                            W[k % L, j] = Wp - c * sp
                            if deep:
                                counts[1] += 1
                    if h > 0.0:
                        pas = min(int(base) * teeth + j, kappa.size - 1)
                        kap = kappa[pas]
                        Ft = kap * a * (coef[0] * h + coef[3])
                        Fr = kap * a * (coef[1] * h + coef[4])
                        Fa = kap * a * (coef[2] * h + coef[5])
                        Fx += inv_s * (-Ft * cp - Fr * sp)
                        Fy += inv_s * (Ft * sp - Fr * cp)
                        Fz += inv_s * Fa
                elif sub == 0:
                    W[k % L, j] = w
        F_out[i, 0] = Fx
        F_out[i, 1] = Fy
        F_out[i, 2] = Fz
        u = t / servo_dt
        s0 = min(int(u), nservo - 2)
        w1 = min(u - s0, 1.0)
        Fx += (1 - w1) * servo[s0, 0] + w1 * servo[s0 + 1, 0]
        Fy += (1 - w1) * servo[s0, 1] + w1 * servo[s0 + 1, 1]
        Fz += (1 - w1) * servo[s0, 2] + w1 * servo[s0 + 1, 2]
        for r in range(M):
            f = shape[r, 0] * Fx + shape[r, 1] * Fy + shape[r, 2] * Fz
            e0 = Phi[r, 0, 0] * eta[r, 0] + Phi[r, 0, 1] * eta[r, 1] + Gam[r, 0] * f
            e1 = Phi[r, 1, 0] * eta[r, 0] + Phi[r, 1, 1] * eta[r, 1] + Gam[r, 1] * f
            eta[r, 0] = e0
            eta[r, 1] = e1


def warm_kernels() -> None:
    """Call :func:`_integrate` once on a tiny input of the types :func:`simulate_cut` passes
    (compiles it, or loads it from the cache; :func:`robomill.kernels.ready`)."""
    M, L, teeth = 1, 4, 2
    F = np.zeros((3, 3))
    d = np.zeros((3, 3))
    _integrate(0, 2, 1e-5, 2, 100.0, 0.0, teeth, 0.0, np.pi, 1e-5, 1e-4, np.ones(6),
               np.ones(4), np.zeros(teeth), np.zeros((M, 2, 2)), np.zeros((M, 2)),
               np.zeros((M, 3)), np.zeros((M, 2)), np.zeros((L, teeth)), 1.5,
               np.zeros((3, 3)), 1.0, np.zeros((3, 3)), 1.0, True, F[1:], d[1:],
               np.zeros(2, np.int64))


def _decimator(fs_hz: float, down: int, fraction: float):
    """FIR low-pass (cut-off ``fraction`` × fs, Hamming, 24 taps per output sample) for the
    ``down``-fold decimation from ``down`` × fs to fs."""
    import scipy.signal

    return scipy.signal.firwin(24 * down + 1, fraction * fs_hz, fs=down * fs_hz)


def path_error_cut_m(cell, cut, config: Mapping[str, Any], length_mm: float,
                     frame: np.ndarray) -> tuple[np.ndarray, float]:
    """Gear trains' TCP error along the cut in the cut frame [m] on a grid of
    ``synth.dynamometer.path_step_mm`` (mean removed: the tool frame is calibrated to the block
    before cutting, thesis §2.1), and that grid's step in time [s] at the cut's feed."""
    from scipy.interpolate import CubicSpline

    s = config["synth"]["dynamometer"]
    step = float(s["path_step_mm"])
    s_ik = np.linspace(0.0, length_mm, int(s["ik_points"]))
    spline = CubicSpline(s_ik, cell.joint_path_rad(cut, s_ik), axis=0)
    s_fine = np.arange(0.0, length_mm + 2 * step, step)
    e = cell.tcp_error_mm(spline(np.clip(s_fine, 0.0, length_mm)))
    e -= e.mean(axis=0)
    return np.ascontiguousarray(1e-3 * e @ frame), step / cut.feed_mm_s


def _simulate(cell, cut, config: Mapping[str, Any], cutting: bool,
              length_mm: float | None = None) -> SimulatedCut:
    import scipy.signal

    from robomill.experiment import cut_process, feed_direction
    from robomill.forces.model import (
        CuttingCoefficients,
        cut_frame,
        engagement_angles_rad,
        mean_milling_forces,
    )
    from robomill.kernels import ready
    from robomill.synth.structure import modes_at

    ready(__name__)  # the kernel compiled once per environment (robomill.kernels)
    proc_cfg = config["synth"]["process"]
    dyn = config["synth"]["dynamometer"]
    rng = np.random.default_rng([cell.seed, STREAM, zlib.crc32(cut.id.encode())])
    proc = cut_process(cut, cell.experiment)
    teeth, rpm = int(proc["flutes"]), float(proc["spindle_rpm"])
    fs = float(dyn["fs_hz"])
    down = int(proc_cfg["oversample"])
    dt = 1.0 / (down * fs)
    L_mm = float(cell.experiment["cut_length_mm"])
    duration = L_mm / cut.feed_mm_s
    fir = _decimator(fs, down, float(dyn["anti_alias_fraction"]))
    lag = (fir.size - 1) // 2 // down
    n_full = int(round(duration * fs))
    # a prefix of the cut (exact: the filter's delay is run past it)
    n_out = span_samples(n_full, float(cut.feed_mm_s), fs, lag, length_mm)
    frame = cut_frame(feed_direction(cut))
    # the structure at the cut's pose (middle of the cut), in the cut frame
    q_mid = cell.joint_path_rad(cut, np.array([0.5 * L_mm]))[0]
    modes = modes_at(cell, q_mid)
    f_hz = np.array([m.f_hz for m in modes])
    zeta = np.array([m.zeta for m in modes])
    k = np.array([m.k_N_m for m in modes])
    shape = np.ascontiguousarray(np.array([m.shape for m in modes]) @ frame)
    Phi, Gam = modal_steps(f_hz, zeta, k, dt)
    coeffs = CuttingCoefficients.from_mapping(cell.cutting)
    st, ex = engagement_angles_rad(proc["radial_immersion"], proc["milling"])
    c_m = 1e-3 * float(proc["feed_per_tooth_mm"])
    a0_m = 1e-3 * float(cut.depth_mm) if cutting else 0.0
    F0 = mean_milling_forces(1e3 * c_m, 1e3 * a0_m, coeffs, flutes=teeth, entry_rad=st,
                             exit_rad=ex)
    eta = np.zeros((len(modes), 2))
    eta[:, 0] = (shape @ F0) / k  # start at the static deflection under the mean force
    coef = np.array([coeffs.Ktc * 1e6, coeffs.Krc * 1e6, coeffs.Kac * 1e6,
                     coeffs.Kte * 1e3, coeffs.Kre * 1e3, coeffs.Kae * 1e3])
    omega = 2 * np.pi * rpm / 60.0
    tau = 60.0 / (teeth * rpm)
    n_pass = int(np.ceil(duration / tau)) + 4 * teeth
    phase0 = float(rng.uniform(0, 2 * np.pi))
    kappa = np.clip(1.0 + float(proc_cfg["coefficient_scatter"])
                    * rng.standard_normal(n_pass), 0.0, None)
    runout = np.zeros(teeth)
    r_um = [float(x) for x in proc_cfg["runout_um"]]
    runout[:min(teeth, len(r_um))] = r_um[:teeth]
    runout *= 1e-6
    path, path_dt = path_error_cut_m(cell, cut, config, L_mm, frame)
    servo_rng = np.random.default_rng([cell.seed, STREAM, zlib.crc32(cut.id.encode()), 1])
    servo = float(proc_cfg["servo_force_N"]) * servo_rng.standard_normal(
        (int(np.ceil(duration * SERVO_FS_HZ)) + 2, 3))
    delay = tau / dt
    W = np.zeros((int(np.floor(delay)) + 3, teeth))
    chunk = max(int(dyn["chunk_samples"]), 1024) * down
    n_in = n_out * down
    force = np.empty((n_out, 3))
    defl = np.empty((n_out, 3))
    counts = np.zeros(2, np.int64)
    m_prev = 0
    P = -(-(fir.size - 1) // down) * down  # history kept before each chunk (whole outputs)
    F_buf = np.empty((P + chunk, 3))
    d_buf = np.empty((P + chunk, 3))
    o = 0
    for k0 in range(0, n_in, chunk):
        m = min(chunk, n_in - k0)
        if k0:
            F_buf[:P], d_buf[:P] = F_buf[m_prev:m_prev + P], d_buf[m_prev:m_prev + P]
        _integrate(k0, m, dt, int(proc_cfg["substeps"]), omega, phase0, teeth, float(st),
                   float(ex), c_m, a0_m, coef, kappa, runout, Phi, Gam, shape, eta, W,
                   delay, path, path_dt, servo, 1.0 / SERVO_FS_HZ, bool(cutting),
                   F_buf[P:], d_buf[P:], counts)
        if not k0:  # at rest before the first sample: the filters start settled
            F_buf[:P], d_buf[:P] = F_buf[P], d_buf[P]
        m_prev = m
        # FIR low-pass and keep every down-th sample (polyphase), output j at input P + j·down
        lo, hi = P // down, (P + m - 1) // down + 1
        force[o:o + hi - lo] = scipy.signal.upfirdn(fir, F_buf[:P + m], down=down,
                                                    axis=0)[lo:hi]
        defl[o:o + hi - lo] = d_buf[P:P + m:down]  # smooth (the modes < 5 kHz): no filter
        o += hi - lo
    # the force FIR's group delay ((taps − 1)/2 input steps = whole output samples): shift back
    if lag:
        force[:-lag] = force[lag:].copy()
        force[-lag:] = force[-lag - 1]
    t = np.arange(n_out) / fs
    out = float(counts[1]) / counts[0] if counts[0] else 0.0
    return SimulatedCut(cut_id=cut.id, fs_hz=fs, t_s=t, force_N=force, deflection_m=defl,
                        path_error_m=path_error_at_m(t, path, path_dt), frame=frame,
                        feed_mm_s=float(cut.feed_mm_s), tooth_hz=1.0 / tau,
                        modes=tuple(modes), teeth_out=out, n_full=n_full, filter_lag=lag,
                        path_grid_m=path, path_dt_s=float(path_dt))


def simulate_cut(cell, cut, config: Mapping[str, Any], *, cutting: bool = True,
                 length_mm: float | None = None) -> SimulatedCut:
    """The closed-loop cut ``cut`` on the virtual cell (module docstring), over its first
    ``length_mm`` (None: the whole cut; a prefix is the same as the whole cut's start).

    ``cutting=False``: the same path with the cutting force switched off (an air pass: the
    robot moves along the cut's path without material; the gear path error and the arm's
    vibration under its own servo excitation remain, no static deflection).
    The virtual cell calls this once per cut and stores the result
    (:func:`robomill.synth.cutstate.write_cut_state`); the instruments read that."""
    return _simulate(cell, cut, config, bool(cutting), length_mm)
