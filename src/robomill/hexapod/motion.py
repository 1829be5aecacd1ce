"""Motion of the force-controlled hexapod: the forward dynamics integrated in time and the
seed's acceleration programmes [Rybak n.d., eq. 6].

The state integrates the twist itself, so the seed's ``S`` is the identity and ``Ṡ = 0``;
orientation is carried as a unit quaternion. A :class:`Programme` is a motion with
piecewise-constant acceleration; :func:`run_programme` replays it open loop under its
inverse-dynamics forces (:func:`programme_forces`); :func:`force_error_drift` is the final pose
error when one actuator's force is off, :func:`instability_rates` why it grows.

Units: SI throughout (m, kg, s, N, rad).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from robomill.hexapod.dynamics import forward_acceleration, inverse_dynamics
from robomill.hexapod.geometry import Hexapod, euler_to_matrix, vcross
from robomill.settings import schema_defaults

#: the ODE solver's defaults, as the schema states them (config ``hexapod.solver``)
SOLVER = schema_defaults("hexapod.solver")


def _quat_dot(q: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Derivative of the scalar-last unit quaternion for the angular velocity ``w`` in base
    axes: ``q̇ = ½ [w, 0] ⊗ q``."""
    qv, qw = q[:3], q[3]
    return 0.5 * np.concatenate([qw * w + vcross(w, qv), [-(w @ qv)]])


def state_vector(p: np.ndarray, R: np.ndarray, twist: np.ndarray) -> np.ndarray:
    """ODE state ``[p (3), quaternion xyzw (4), v (3), ω (3)]``."""
    return np.concatenate([p, Rotation.from_matrix(R).as_quat(), twist])


def unpack_state(y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(p, R, twist)`` from an ODE state (quaternion renormalised)."""
    q = y[3:7] / np.linalg.norm(y[3:7])
    return y[:3], Rotation.from_quat(q).as_matrix(), y[7:13]


ForceLaw = Callable[[float, np.ndarray, int], np.ndarray]
"""``forces(t, state, segment) -> Γ`` (N, shape (6,)); ``segment`` is the index of the
integration interval between breakpoints (a law may ignore it)."""


@dataclass(frozen=True)
class Simulation:
    """Forward-dynamics result: time (s), position (m), Euler angles ``(ψ, θ, φ)`` (rad),
    twist and the applied forces at the output times; ``nfev`` right-hand-side calls."""

    t: np.ndarray
    position: np.ndarray
    euler: np.ndarray
    rotation: np.ndarray
    twist: np.ndarray
    forces: np.ndarray
    nfev: int
    t_stop: float | None = None


def simulate(hx: Hexapod, y0: np.ndarray, forces: ForceLaw, t_eval: np.ndarray,
             breakpoints: Sequence[float] = (), rtol: float = SOLVER["rtol"],
             atol: float = SOLVER["atol"], method: str = SOLVER["method"],
             stop: Callable[[float, np.ndarray], float] | None = None) -> Simulation:
    """Integrate the forward dynamics (seed eq. 6) with ``scipy.integrate.solve_ivp``.

    The integration restarts at every ``breakpoint`` (a jump of the commanded acceleration),
    so the adaptive steps never straddle a discontinuity. Tolerances ``rtol``/``atol`` apply to
    the state in SI units (m, m/s, rad/s and the quaternion). ``stop(t, y)`` is a terminal
    event: the integration ends where it crosses zero (the result then stops early).
    """
    t_eval = np.asarray(t_eval, float)
    edges = [t_eval[0], *[b for b in breakpoints if t_eval[0] < b < t_eval[-1]], t_eval[-1]]

    events = None
    if stop is not None:
        def event(t, y, seg):
            return stop(t, y)
        event.terminal = True
        events = [event]

    def rhs(t, y, seg):
        p, R, twist = unpack_state(y)
        acc = forward_acceleration(hx, p, R, twist, forces(t, y, seg))
        q = y[3:7] / np.linalg.norm(y[3:7])
        return np.concatenate([twist[:3], _quat_dot(q, twist[3:]), acc])

    ys, ts, segs, nfev, y, t_stop = [], [], [], 0, np.asarray(y0, float), None
    for k, (t0, t1) in enumerate(zip(edges[:-1], edges[1:], strict=True)):
        last = k == len(edges) - 2
        sel = (t_eval >= t0) & ((t_eval <= t1) if last else (t_eval < t1))
        sol = solve_ivp(rhs, (t0, t1), y, method=method, t_eval=t_eval[sel], rtol=rtol,
                        atol=atol, dense_output=True, args=(k,), events=events)
        if not sol.success:
            raise RuntimeError(f"forward dynamics failed on [{t0}, {t1}] s: {sol.message}")
        nfev += sol.nfev
        ys.append(sol.y.T)
        ts.append(sol.t)
        segs.append(np.full(sol.t.size, k))
        y = sol.sol(t1)
        if sol.status == 1:                                   # stopped by the event
            t_stop = float(sol.t_events[0][0])
            break
    t = np.concatenate(ts)
    y_all = np.vstack(ys)
    pos, rot, tw, fs = [], [], [], []
    for ti, yi, si in zip(t, y_all, np.concatenate(segs), strict=True):
        p, R, twist = unpack_state(yi)
        pos.append(p)
        rot.append(R)
        tw.append(twist)
        fs.append(forces(ti, yi, int(si)))
    rot = np.array(rot)
    return Simulation(t=t, position=np.array(pos), euler=Rotation.from_matrix(rot).as_euler(
        "xyz"), rotation=rot, twist=np.array(tw), forces=np.array(fs), nfev=nfev,
        t_stop=t_stop)


@dataclass(frozen=True)
class Programme:
    """A platform motion with piecewise-constant linear acceleration and constant
    orientation (seed: γ_x = +1 on [0, 2] s, −1 on [2, 4] s, γ_y = 5 on [0, 4] s, start at
    rest). ``edges_s`` are the segment limits (n + 1), ``accel_m_s2`` one row (3,) per
    segment; ``start_m`` the start position and ``euler_rad`` the fixed orientation."""

    edges_s: np.ndarray
    accel_m_s2: np.ndarray
    start_m: np.ndarray
    euler_rad: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def segment_of(self, t: float) -> int:
        """Index of the segment holding ``t`` (right-continuous; the last one holds its end)."""
        k = int(np.searchsorted(self.edges_s, t, side="right")) - 1
        return int(np.clip(k, 0, len(self.edges_s) - 2))

    def state(self, t: float, segment: int | None = None
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Commanded ``(p, v, a)`` at time ``t`` (exact integration of the segments), on the
        polynomial of ``segment`` (default: the segment holding ``t``), so an integrator can
        reach a segment's end without seeing the next segment's acceleration."""
        k = self.segment_of(t) if segment is None else segment
        p, v = np.array(self.start_m, float), np.zeros(3)
        for j in range(k):
            a = np.asarray(self.accel_m_s2[j], float)
            dt = self.edges_s[j + 1] - self.edges_s[j]
            p, v = p + v * dt + 0.5 * a * dt**2, v + a * dt
        a = np.asarray(self.accel_m_s2[k], float)
        dt = t - self.edges_s[k]
        return p + v * dt + 0.5 * a * dt**2, v + a * dt, a

    @property
    def rotation(self) -> np.ndarray:
        return euler_to_matrix(self.euler_rad)


def programme_forces(hx: Hexapod, prog: Programme) -> ForceLaw:
    """Feed-forward force law: inverse dynamics of the commanded motion at time ``t`` (it does
    not look at the simulated state: open-loop force control, as in the seed)."""
    R = prog.rotation

    def law(t: float, y: np.ndarray | None = None, segment: int | None = None) -> np.ndarray:
        p, v, a = prog.state(t, segment)
        return inverse_dynamics(hx, p, R, np.concatenate([v, np.zeros(3)]),
                                np.concatenate([a, np.zeros(3)]))

    return law


def run_programme(hx: Hexapod, prog: Programme, t_eval: np.ndarray,
                  force_scale: np.ndarray | None = None, rtol: float = SOLVER["rtol"],
                  atol: float = SOLVER["atol"], stop_error_m: float | None = None,
                  method: str = SOLVER["method"]) -> Simulation:
    """Forward dynamics under the programme's inverse-dynamics forces, each actuator's force
    multiplied by ``force_scale`` (6,) (1 = exact; 1.01 = +1 % error).

    With ``stop_error_m`` the integration stops once the position leaves the commanded one by
    that much (open-loop force control is unstable, see :func:`instability_rates`)."""
    law = programme_forces(hx, prog)
    scale = np.ones(6) if force_scale is None else np.asarray(force_scale, float)
    p0, _, _ = prog.state(prog.edges_s[0])
    y0 = state_vector(p0, prog.rotation, np.zeros(6))
    stop = None
    if stop_error_m is not None:
        def stop(t, y):
            return stop_error_m - np.linalg.norm(y[:3] - prog.state(t)[0])
    return simulate(hx, y0, lambda t, y, seg: scale * law(t, y, seg), t_eval,
                    breakpoints=list(prog.edges_s[1:-1]), rtol=rtol, atol=atol, stop=stop,
                    method=method)


def pose_error(sim: Simulation, prog: Programme) -> tuple[np.ndarray, np.ndarray]:
    """Final position error (m, (3,)) and orientation error as a rotation vector (rad, (3,))
    of a simulation against the programme's exact motion at the final time."""
    p_exact, _, _ = prog.state(sim.t[-1])
    dp = sim.position[-1] - p_exact
    drot = Rotation.from_matrix(sim.rotation[-1] @ prog.rotation.T).as_rotvec()
    return dp, drot


def vertical_programme(start_m: Sequence[float], rise_m: float, duration_s: float
                       ) -> Programme:
    """The seed's vertical move: from rest at ``start`` up by ``rise`` in ``duration`` at
    constant acceleration ``2 rise / T²`` (seed: 53.3 → 54.57)."""
    acc = np.array([[0.0, 0.0, 2.0 * rise_m / duration_s**2]])
    return Programme(edges_s=np.array([0.0, duration_s]), accel_m_s2=acc,
                     start_m=np.asarray(start_m, float))


def force_error_drift(hx: Hexapod, prog: Programme, actuator: int, error_pct: float,
                      n_eval: int = 2, rtol: float = SOLVER["rtol"], atol: float = SOLVER["atol"],
                      method: str = SOLVER["method"]) -> tuple[np.ndarray, np.ndarray]:
    """Final position error (m) and rotation vector (rad) when actuator ``actuator`` (1–6)
    delivers ``(1 + error_pct/100)`` times its inverse-dynamics force (seed: actuator 1 at
    +1 %)."""
    scale = np.ones(6)
    scale[actuator - 1] += error_pct / 100.0
    t = np.linspace(prog.edges_s[0], prog.edges_s[-1], max(n_eval, 2))
    sim = run_programme(hx, prog, t, scale, rtol=rtol, atol=atol, method=method)
    return pose_error(sim, prog)


def instability_rates(hx: Hexapod, p: np.ndarray, R: np.ndarray, eps: float = 1e-7
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (1/s) and pose parts of the eigenvectors of the forward dynamics
    linearised about static equilibrium at ``(p, R)`` with the actuator forces held at their
    equilibrium values (central differences on the 12-state ``[δp, δφ, v, ω]``).

    A compressed leg pushing with a constant force is a negative lateral stiffness
    (``Γ/ℓ``), so the force-controlled platform is an inverted pendulum: real eigenvalue
    pairs ``±λ``, and any force error grows like ``e^{λt}``.
    """
    forces = inverse_dynamics(hx, p, R, np.zeros(6), np.zeros(6))

    def f(x):
        Rx = Rotation.from_rotvec(x[3:6]).as_matrix() @ R
        acc = forward_acceleration(hx, p + x[:3], Rx, x[6:], forces)
        return np.concatenate([x[6:], acc])

    jac = np.zeros((12, 12))
    for k in range(12):
        dx = np.zeros(12)
        dx[k] = eps
        jac[:, k] = (f(dx) - f(-dx)) / (2 * eps)
    ev, vec = np.linalg.eig(jac)
    order = np.argsort(-ev.real)
    return ev[order], vec[:6, order]
