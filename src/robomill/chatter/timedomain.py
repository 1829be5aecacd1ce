"""Shagniev 2019: the robot–tool–surface system in the time domain (Shagniev, Shanshin & Burdakov
2019, "Control of regenerative self-excited vibrations in the milling process").

Model (Shagniev 2019, system of equations after Fig. 1). Arm mass m, tool mass m_s on an
elastic suspension c_s (which is also the force sensor):

* vertical:   m ÿ + b_y ẏ + c_sy (y − y_s) = F_y − m g,  y_s = y_sf = const (flat surface),
  F_y = PID(ỹ_d − y),  ỹ_d = PID_F(F_sy^d − F_sy),  F_sy = c_sy (y − y_s);
* horizontal: m ẍ + b_x ẋ + c_sx (x − x_s) = F_x,  m_s ẍ_s + b_sx ẋ_s + c_sx (x_s − x) = R_x,
  F_x = PID_v(ẋ_d − ẋ) (and the same in z with ż_d = 0);
* every PID is k_p + k_i/p + k_d N/(1 + N/p) (filtered derivative);
* chip of tooth j: h_j = (S sin φ_j + Δx sin φ_j + Δz cos φ_j) g(φ_j), S = ẋ_d τ, Δ = tool
  vibration now minus one tooth period τ = 60/(N n) ago; R_t = K_t a h, R_r = K_r R_t,
  R_x = Σ −R_t cos φ_j − R_r sin φ_j, R_z = Σ R_t sin φ_j − R_r cos φ_j.

The seed links the axial depth to the vertical force setpoint without giving the relation;
here (assumed) the depth is proportional to the measured suspension force,
a = a_ref F_sy / F_sy^d,ref, so lowering the setpoint by 1 % lowers the depth by 1 % once the
force loop has settled. The chip is clipped at h ≥ 0 (the tooth leaves the cut), which bounds
chatter; near the stability boundary the motion is small and the model is linear.

Integration: classical Runge–Kutta 4 with a fixed step τ/steps_per_tooth (the delayed
vibration at the half step is the mean of the two stored neighbours), compiled with numba.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numba
import numpy as np

from robomill.chatter.model import CuttingModel, LinearTool
from robomill.settings import schema_default

G_M_S2 = 9.81

# state indices
(Y, VY, IY, DY, IF, DF, X, VX, XS, VXS, IX, DX, Z, VZ, ZS, VZS, IZ, DZ) = range(18)
N_STATE = 18


@dataclass(frozen=True)
class SeedParams:
    """Every value of the Shagniev 2019 model; PID gains are assumed (the seed only says
    they give fast, smooth transients)."""

    m_kg: float = 2.0
    m_s_kg: float = 0.2
    b_N_s_m: float = 20.0
    b_s_N_s_m: float = 50.0
    c_s_N_m: float = 2.2e5
    teeth: int = 4
    Kt_N_m2: float = 1.0e9
    Kr: float = 0.6
    phi_st_rad: float = 0.0
    phi_ex_rad: float = float(np.pi / 2)
    feed_m_s: float = 0.01
    force_setpoint_N: float = 40.0
    spindle_rpm: float = 1260.0
    # cutting-coefficient variation per tooth pass (assumed; 0: the ideal, exactly periodic cut)
    Kt_noise_fraction: float = 0.0
    noise_seed: int = 0
    # PIDs (assumed)
    kp_y: float = 2.0e5
    ki_y: float = 9.0e6
    kd_y: float = 1200.0
    N_y: float = 3000.0
    theta_p: float = 1.0e-6
    theta_i: float = 6.0e-5
    theta_d: float = 0.0
    N_f: float = 1000.0
    kp_v: float = 900.0
    ki_v: float = 2.0e5
    kd_v: float = 0.2
    N_v: float = 3000.0

    @classmethod
    def from_config(cls, section: dict) -> SeedParams:
        """From ``chatter.seed.params`` (an unknown key is a ConfigError naming it)."""
        from robomill.settings import dataclass_from_mapping

        return dataclass_from_mapping(cls, section, strict="chatter.seed.params")

    def as_dict(self) -> dict:
        return asdict(self)

    @property
    def tooth_period_s(self) -> float:
        return 60.0 / (self.teeth * self.spindle_rpm)

    @property
    def feed_per_tooth_m(self) -> float:
        return self.feed_m_s * self.tooth_period_s

    def cutting_model(self) -> CuttingModel:
        return CuttingModel(self.teeth, self.Kt_N_m2, self.Kr, self.phi_st_rad, self.phi_ex_rad)


def horizontal_tool(p: SeedParams) -> LinearTool:
    """The seed's horizontal dynamics as a linear tool model for the lobe methods: arm m on the
    velocity PID, tool m_s on the suspension, per direction (x = feed, z = normal), linearized
    about the commanded motion. The PID integral of the velocity error is minus the arm's
    position error, so the states per direction are (x, ẋ, x_s, ẋ_s, derivative filter)."""
    A1 = np.zeros((5, 5))
    m, ms, c, b, bs = p.m_kg, p.m_s_kg, p.c_s_N_m, p.b_N_s_m, p.b_s_N_s_m
    # F = −kp ẋ − ki x + kd N (−ẋ − ξ),  ξ' = N(−ẋ − ξ)
    A1[0, 1] = 1.0
    A1[1, 0] = (-p.ki_v - c) / m
    A1[1, 1] = (-p.kp_v - p.kd_v * p.N_v - b) / m
    A1[1, 2] = c / m
    A1[1, 4] = -p.kd_v * p.N_v / m
    A1[2, 3] = 1.0
    A1[3, 0] = c / ms
    A1[3, 2] = -c / ms
    A1[3, 3] = -bs / ms
    A1[4, 1] = -p.N_v
    A1[4, 4] = -p.N_v
    A = np.zeros((10, 10))
    A[:5, :5] = A1
    A[5:, 5:] = A1
    B = np.zeros((10, 2))
    B[3, 0] = B[8, 1] = 1.0 / ms
    C = np.zeros((2, 10))
    C[0, 2] = C[1, 7] = 1.0
    return LinearTool(A, B, C)


@numba.njit(cache=True)
def _rhs(s, t, dxi, dzi, a_gain, fd, vd, pr, kt_pass, out_R):
    """Right-hand side; dxi, dzi: tool vibration minus its value one tooth period ago."""
    m, ms, b, bs, c = pr[0], pr[1], pr[2], pr[3], pr[4]
    teeth, Kt, Kr, phst, phex = int(pr[5]), pr[6], pr[7], pr[8], pr[9]
    S, omega = pr[10], pr[11]
    kpy, kiy, kdy, Ny, thp, thi, thd, Nf = pr[12], pr[13], pr[14], pr[15], pr[16], pr[17], \
        pr[18], pr[19]
    kpv, kiv, kdv, Nv = pr[20], pr[21], pr[22], pr[23]
    phase0 = pr[24]
    d = np.empty(N_STATE)
    # vertical cascade
    Fsy = c * s[Y]
    eF = fd - Fsy
    yd = thp * eF + thi * s[IF] + thd * Nf * (eF - s[DF])
    ey = yd - s[Y]
    Fy = kpy * ey + kiy * s[IY] + kdy * Ny * (ey - s[DY])
    d[Y] = s[VY]
    d[VY] = (Fy - m * 9.81 - b * s[VY] - c * s[Y]) / m
    d[IY] = ey
    d[DY] = Ny * (ey - s[DY])
    d[IF] = eF
    d[DF] = Nf * (eF - s[DF])
    a = a_gain * Fsy
    if a < 0.0:
        a = 0.0
    # cutting forces
    Rx = 0.0
    Rz = 0.0
    two_pi = 2.0 * np.pi
    for j in range(teeth):
        turns = (omega * t + phase0 + two_pi * j / teeth) / two_pi
        phi = (turns - np.floor(turns)) * two_pi
        if phi > phst and phi < phex:
            # cutting-coefficient variation of this pass of tooth j (material inhomogeneity)
            pas = min(int(np.floor(turns)) * teeth + j, kt_pass.size - 1)
            sp, cp = np.sin(phi), np.cos(phi)
            h = S * sp + dxi * sp + dzi * cp
            if h < 0.0:
                h = 0.0
            Rt = Kt * kt_pass[pas] * a * h
            Rr = Kr * Rt
            Rx += -Rt * cp - Rr * sp
            Rz += Rt * sp - Rr * cp
    out_R[0] = Rx
    out_R[1] = Rz
    out_R[2] = a
    # horizontal x (velocity PID) and z (ż_d = 0)
    for (P, V, PS, VS, I, D, vset, R) in ((X, VX, XS, VXS, IX, DX, vd, Rx),
                                          (Z, VZ, ZS, VZS, IZ, DZ, 0.0, Rz)):
        ev = vset - s[V]
        F = kpv * ev + kiv * s[I] + kdv * Nv * (ev - s[D])
        d[P] = s[V]
        d[V] = (F - b * s[V] - c * (s[P] - s[PS])) / m
        d[PS] = s[VS]
        d[VS] = (R - bs * s[VS] - c * (s[PS] - s[P])) / ms
        d[I] = ev
        d[D] = Nv * (ev - s[D])
    return d


@numba.njit(cache=True)
def _integrate(s, k0, n_steps, dt, msteps, hist_x, hist_z, a_gain, fd, vd, pr, kt_pass, rec,
               every):
    """Advance ``n_steps`` RK4 steps from step index k0; the vibration histories hold
    x_s − ẋ_d t and z_s at every step (index k + msteps for step k). Records (t, ξx, ξz, Rx, Rz,
    a, F_sy) every ``every`` steps into ``rec``; returns the number of records."""
    R = np.zeros(3)
    nrec = 0
    # the stage states as element loops over preallocated arrays, not array expressions: the
    # same operations in the same order (the same bits), half the first compile of a fresh
    # checkout (numba's array-expression and slice-assignment machinery is not built)
    s2 = np.empty(N_STATE)
    s3 = np.empty(N_STATE)
    s4 = np.empty(N_STATE)
    half = 0.5 * dt
    sixth = dt / 6.0
    for i in range(n_steps):
        k = k0 + i
        t = k * dt
        dx0 = hist_x[k + msteps] - hist_x[k]
        dz0 = hist_z[k + msteps] - hist_z[k]
        dxh = 0.5 * (hist_x[k + msteps] + (s[XS] - vd * t)) - 0.5 * (hist_x[k] + hist_x[k + 1])
        dzh = 0.5 * (hist_z[k + msteps] + s[ZS]) - 0.5 * (hist_z[k] + hist_z[k + 1])
        k1 = _rhs(s, t, dx0, dz0, a_gain, fd, vd, pr, kt_pass, R)
        if i % every == 0:
            rec[nrec, 0] = t
            rec[nrec, 1] = s[XS] - vd * t
            rec[nrec, 2] = s[ZS]
            rec[nrec, 3] = R[0]
            rec[nrec, 4] = R[1]
            rec[nrec, 5] = R[2]
            rec[nrec, 6] = pr[4] * s[Y]
            nrec += 1
        for q in range(N_STATE):
            s2[q] = s[q] + half * k1[q]
        k2 = _rhs(s2, t + 0.5 * dt, dxh, dzh, a_gain, fd, vd, pr, kt_pass, R)
        for q in range(N_STATE):
            s3[q] = s[q] + half * k2[q]
        k3 = _rhs(s3, t + 0.5 * dt, dxh, dzh, a_gain, fd, vd, pr, kt_pass, R)
        for q in range(N_STATE):
            s4[q] = s[q] + dt * k3[q]
        # delayed value at t + dt; current value estimated by the Euler predictor
        dx1 = (s4[XS] - vd * (t + dt)) - hist_x[k + 1]
        dz1 = s4[ZS] - hist_z[k + 1]
        k4 = _rhs(s4, t + dt, dx1, dz1, a_gain, fd, vd, pr, kt_pass, R)
        for q in range(N_STATE):
            s[q] = s[q] + sixth * (k1[q] + 2.0 * k2[q] + 2.0 * k3[q] + k4[q])
        hist_x[k + 1 + msteps] = s[XS] - vd * (t + dt)
        hist_z[k + 1 + msteps] = s[ZS]
    return nrec


def _packed(p: SeedParams, dt_s: float) -> np.ndarray:
    """Parameters for the compiled right-hand side. The last one is the spindle-angle offset of
    a quarter step: RK4 evaluates at whole and half steps, so no evaluation point then lies on a
    tooth's entry or exit angle, where floating-point rounding of ω t would count the tooth in
    at one tooth period and out at the next. That non-periodic switching excites the chatter
    mode like white noise (first order in the step; it kept a stable cut's regenerative Δ at a
    few µm instead of letting it decay)."""
    return np.array([p.m_kg, p.m_s_kg, p.b_N_s_m, p.b_s_N_s_m, p.c_s_N_m, p.teeth, p.Kt_N_m2,
                     p.Kr, p.phi_st_rad, p.phi_ex_rad, p.feed_per_tooth_m,
                     2 * np.pi * p.spindle_rpm / 60.0, p.kp_y, p.ki_y, p.kd_y, p.N_y,
                     p.theta_p, p.theta_i, p.theta_d, p.N_f, p.kp_v, p.ki_v, p.kd_v, p.N_v,
                     0.25 * dt_s * 2 * np.pi * p.spindle_rpm / 60.0])


def warm_kernels() -> None:
    """Advance a tiny simulation a few steps (compiles :func:`_integrate` and :func:`_rhs`, or
    loads them from the cache; :func:`robomill.kernels.ready`)."""
    p = SeedParams()
    sim = SeedSimulation(p, 1e-4, steps_per_tooth=8, duration_s=4 * p.tooth_period_s,
                         record_every=1)
    sim._advance(2 * p.tooth_period_s)


class SeedSimulation:
    """Resumable fixed-step simulation of the Shagniev 2019 system.

    Parameters
    ----------
    params
        Model values.
    depth_m
        Axial depth at the initial force setpoint (defines a = depth_m F_sy / F_sy^d).
    steps_per_tooth
        Integration steps per tooth period (the delay is an exact number of steps).
    duration_s
        Longest simulated time (sizes the history buffers).
    record_every
        Keep every k-th step in the record.
    """

    def __init__(self, params: SeedParams, depth_m: float, *,
                 steps_per_tooth: int = schema_default("chatter.seed", "steps_per_tooth"),
                 duration_s: float = 5.0, record_every: int = 4,
                 start_at_contact: bool = True):
        self.p = params
        self.m = int(steps_per_tooth)
        self.dt = params.tooth_period_s / self.m
        self.n_total = int(np.ceil(duration_s / self.dt))
        self.every = int(record_every)
        self.a_gain = depth_m / params.force_setpoint_N
        self.force_setpoint_N = params.force_setpoint_N
        self.pr = _packed(params, self.dt)
        self.kt_pass = self._pass_factors(duration_s)
        self.hist_x = np.zeros(self.n_total + self.m + 2)
        self.hist_z = np.zeros(self.n_total + self.m + 2)
        self.k = 0
        self.rec = np.zeros((self.n_total // self.every + 2, 7))
        self.nrec = 0
        self.s = self._equilibrium(start_at_contact)
        self.hist_x[: self.m + 1] = self.s[XS]
        self.hist_z[: self.m + 1] = self.s[ZS]

    def _pass_factors(self, duration_s: float) -> np.ndarray:
        """K_t factor of every tooth pass, 1 + σ ξ with ξ ~ N(0, 1) seeded (material
        inhomogeneity, run-out and chip-formation scatter lumped; Shagniev 2019 models none, and a
        noise-free cut near the boundary would take arbitrarily long to show chatter). The
        variation is independent from pass to pass, a broadband excitation of the regenerative
        mode, whose stable response stays small and whose unstable growth starts from it."""
        p = self.p
        n_pass = int(np.ceil(duration_s / p.tooth_period_s)) + 2 * p.teeth + 2
        xi = np.random.default_rng(int(p.noise_seed)).standard_normal(n_pass)
        return np.clip(1.0 + float(p.Kt_noise_fraction) * xi, 0.0, None)

    def _equilibrium(self, at_contact: bool) -> np.ndarray:
        """Initial state. Horizontal: at the commanded velocity, no cutting yet. Vertical: at
        first contact (F_sy = 0, the force loop then presses the tool in, so the depth ramps up
        smoothly, Shagniev 2019 "switch to position–force control on contact"), or already at rest
        with F_sy = F_sy^d when ``at_contact`` is false."""
        p = self.p
        s = np.zeros(N_STATE)
        fd = self.force_setpoint_N if not at_contact else 0.0
        s[Y] = fd / p.c_s_N_m
        s[IY] = (fd + p.m_kg * G_M_S2) / p.ki_y  # F_y balances spring and weight
        s[IF] = s[Y] / p.theta_i  # ỹ_d = y
        s[VX] = s[VXS] = p.feed_m_s
        s[DX] = 0.0
        s[IX] = p.b_N_s_m * p.feed_m_s / p.ki_v + p.b_s_N_s_m * p.feed_m_s / p.ki_v
        # arm ahead of the tool by the suspension deflection that drags the damped tool
        s[XS] = 0.0
        s[X] = p.b_s_N_s_m * p.feed_m_s / p.c_s_N_m
        return s

    @property
    def t_s(self) -> float:
        return self.k * self.dt

    def run(self, seconds: float) -> None:
        """Advance by ``seconds`` (rounded to whole steps)."""
        from robomill.kernels import ready

        ready(__name__)  # the kernels compiled once per environment (robomill.kernels)
        self._advance(seconds)

    def _advance(self, seconds: float) -> None:
        n = min(int(round(seconds / self.dt)), self.n_total - self.k)
        if n <= 0:
            return
        need = self.nrec + n // self.every + 2
        if need > self.rec.shape[0]:
            self.rec = np.concatenate([self.rec, np.zeros((need - self.rec.shape[0], 7))])
        got = _integrate(self.s, self.k, n, self.dt, self.m, self.hist_x, self.hist_z,
                         self.a_gain, self.force_setpoint_N, self.p.feed_m_s, self.pr,
                         self.kt_pass, self.rec[self.nrec:], self.every)
        self.nrec += got
        self.k += n

    def record(self) -> dict[str, np.ndarray]:
        """The recorded signals: t_s, xs_vib_m, zs_m, Rx_N, Rz_N, depth_m, Fsy_N."""
        r = self.rec[: self.nrec]
        names = ("t_s", "xs_vib_m", "zs_m", "Rx_N", "Rz_N", "depth_m", "Fsy_N")
        return {n: r[:, i].copy() for i, n in enumerate(names)}

    @property
    def record_fs_hz(self) -> float:
        return 1.0 / (self.dt * self.every)
