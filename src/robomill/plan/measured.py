"""What the lab measured, as the planner uses it: cutting coefficients with their confidence
intervals, joint stiffness with its interval, the impact test's modes, and the gear errors of
the tracker runs expressed as joint-angle amplitudes (so they can be carried to a new pose).

Each quantity may be absent (no dynamometer cuts, no load tests, no impact test, no tracker
runs); :func:`missing_predictions` says which predictions that removes.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import stats

from robomill.forces import CuttingCoefficients
from robomill.forces.coefficients import identification_status, not_identified_sentence
from robomill.kinematics import SerialRobot
from robomill.plan.noise import (
    noise_floor_um,
    read_sum_interval_um,
    record_duration_s,
    run_duration_s,
)
from robomill.settings import schema_default
from robomill.stiffness import jacobian_m
from robomill.straightness import perpendicular_axes

PREDICTIONS = {
    "stability_margin": ("modes", "coefficients"),
    "deflection": ("joints", "coefficients"),
    "force": ("coefficients",),
    "waviness": ("gears",),
    "pose_dependent_modes": ("joints", "modes"),
}
"""Each prediction and the measured quantities it needs."""

SOURCES = {
    "modes": "no impact test (results/modal/modes.csv)",
    "coefficients": "no cutting coefficients (results/forces/cutting_coefficients.csv)",
    "joints": "no load tests of the cell's robot (results/stiffness/<robot>/joint_stiffness.csv)",
    "gears": "no tracker runs with gear lines (results/straightness/peaks.csv)",
}


@dataclass(frozen=True)
class Measured:
    """The lab's identified quantities (each None when not measured)."""

    modes: pd.DataFrame | None = None
    coefficients: pd.DataFrame | None = None
    joints: pd.DataFrame | None = None
    gears: pd.DataFrame | None = None
    waviness_coverage: float = 0.95
    """Two-sided coverage of the interval of the waviness the next tracker run reads
    (:mod:`robomill.plan.noise`; config ``plan.waviness_noise.coverage``)."""
    waviness_min_cycles: float = 4.5
    """Periods along the path from which a gear line counts as waviness
    (:func:`robomill.plan.check.waviness_min_cycles`)."""
    force_regression: object | None = None
    """The coefficient regression of the identifying cuts
    (:class:`robomill.forces.prediction.ForceRegression`), for the force's prediction
    interval; None: the coefficients' confidence corners."""
    level: float = schema_default("plan", "interval_level")
    """Nominal two-sided level of the plan's intervals (config ``plan.interval_level``)."""
    stability_evidence: object | None = None
    """The study's chatter verdicts as the weights of the stability model's members
    (:class:`robomill.plan.stability.VerdictEvidence`); None: equal weights."""

    def has(self, name: str) -> bool:
        """Whether ``name`` was measured: a table with rows; cutting coefficients must also
        be identified (a design with one feed per tooth writes them as NaN with the reason,
        :func:`robomill.forces.coefficients.not_identified_table`)."""
        v = getattr(self, name)
        if v is None or len(v) == 0:
            return False
        return name != "coefficients" or identification_status(v) is None

    def why_missing(self, name: str) -> str:
        """Why ``name`` is not there (:data:`SOURCES`; the coefficients' reason when the
        table is there but not identified)."""
        v = getattr(self, name)
        if name == "coefficients" and v is not None and len(v) > 0:
            why = identification_status(v)
            if why is not None:
                return ("no cutting coefficients (results/forces/cutting_coefficients.csv: "
                        f"{not_identified_sentence(why)})")
        return SOURCES[name]


def missing_predictions(m: Measured) -> dict[str, str]:
    """Predictions that cannot be made, each with the reason (the first missing source)."""
    out = {}
    for pred, needs in PREDICTIONS.items():
        for n in needs:
            if not m.has(n):
                out[pred] = m.why_missing(n)
                break
    return out


def coefficient_bounds(coeffs: pd.DataFrame) -> dict[str, CuttingCoefficients]:
    """Nominal coefficients and the two ends of their confidence intervals (``ci_low`` and
    ``ci_high`` of ``cutting_coefficients.csv``; the value where an interval is missing)."""
    t = coeffs.set_index("name")
    out = {}
    for key, col in (("nominal", "value"), ("low", "ci_low"), ("high", "ci_high")):
        vals = {}
        for k in ("Ktc", "Krc", "Kac", "Kte", "Kre", "Kae"):
            v = t.loc[k, col] if col in t and k in t.index else np.nan
            vals[k] = float(v) if np.isfinite(v) else float(t.loc[k, "value"])
        out[key] = CuttingCoefficients(**vals)
    return out


def compliance_bounds(joints: pd.DataFrame) -> dict[str, np.ndarray]:
    """Joint compliances c = 1/k [rad/(N·m)] at the nominal stiffness and at the ends of its
    95 % interval (``low``: 1/k_high, ``high``: 1/k_low; an unbounded upper stiffness gives
    compliance 0, a non-positive lower bound twice the nominal compliance). Unobservable joints
    are rigid (as :func:`robomill.stiffness.compliance_from_table`)."""
    k = joints["k_Nm_rad"].to_numpy(float)
    obs = joints["observable"].astype(str).str.lower().isin(["true", "1"]).to_numpy()
    ok = obs & np.isfinite(k) & (k > 0)
    lo = joints.get("ci95_low_Nm_rad", pd.Series(k)).to_numpy(float)
    hi = joints.get("ci95_high_Nm_rad", pd.Series(k)).to_numpy(float)
    c = np.where(ok, 1.0 / np.where(ok, k, 1.0), 0.0)
    with np.errstate(divide="ignore"):
        c_lo = np.where(ok & np.isfinite(hi) & (hi > 0), 1.0 / np.where(hi > 0, hi, 1.0), 0.0)
        c_hi = np.where(ok & (lo > 0), 1.0 / np.where(lo > 0, lo, 1.0), 2.0 * c)
    return {"nominal": c, "low": np.minimum(c_lo, c), "high": np.maximum(c_hi, c)}


def spectrum_amplitude_um(profiles, run: str, component: str, f_lo_per_mm: float,
                          f_hi_per_mm: float | None = None, *,
                          halfwidth_bins: float = 0.5) -> float:
    """The largest sinusoid amplitude of one component of a tracker run's spectrum
    (``amplitude_um`` of ``results/straightness/profiles.nc``: Hann-windowed, coherent-gain
    corrected, thesis eqs. 2.1–2.3) from ``f_lo`` to ``f_hi`` (default ``f_lo``)
    ± ``halfwidth_bins`` resolution bins 1/L of the run [µm]; NaN where the run is absent."""
    runs = [str(r) for r in profiles["run"].values]
    if run not in runs:
        return float("nan")
    k = runs.index(run)
    half = halfwidth_bins * float(profiles["resolution_per_mm"].values[k])
    f = profiles["f"].values.astype(float)
    amp = profiles["amplitude_um"].isel(run=k).sel(component=component).values
    hi = f_lo_per_mm if f_hi_per_mm is None else f_hi_per_mm
    near = (f >= f_lo_per_mm - half) & (f <= hi + half) & np.isfinite(amp)
    return float(amp[near].max()) if near.any() else float("nan")


def gear_joint_amplitudes(peaks: pd.DataFrame, robot: SerialRobot,
                          poses: Mapping[str, tuple[np.ndarray, np.ndarray]], *,
                          min_sensitivity: float = 0.02, profiles=None,
                          noise_band_bins: float = schema_default(
                              "plan.waviness_noise", "band_bins"),
                          noise_exclude_bins: float = schema_default(
                              "plan.waviness_noise", "exclude_bins"),
                          level: float = schema_default("plan", "interval_level")
                          ) -> pd.DataFrame:
    """Joint-angle amplitude of every gear element seen on the tracker paths.

    A gear error δq_j of joint j moves the TCP by J_v[:, j] δq_j; a peak of amplitude A along
    the path's component axis l (lateral ẑ × u or vertical, :func:`perpendicular_axes`) at the
    run's posture q gives δq_j = A / |lᵀ J_v[:, j](q)|. Peaks whose axis sees less than
    ``min_sensitivity`` of the joint's TCP motion are left out (ill-conditioned). Each element's
    estimates over the runs give its nominal (median) and interval: the lowest and highest
    run, each widened by its own read's noise, ± z σ/√2 (σ the per-bin noise near the line,
    below; z the normal quantile of the two-sided ``level``), so that one run alone still
    gives an interval.

    A is the component's own sinusoid amplitude at the peak's frequency in the run's spectrum
    (``profiles``, :func:`spectrum_amplitude_um`), the quantity :func:`waviness_um` carries and
    :func:`robomill.plan.check.waviness_outcomes` measures. Without ``profiles`` (or the run in
    it) A is the peak's ``amplitude_um``, √(2P) of the lateral + vertical power at the peak bin
    (:func:`robomill.straightness.spectrum_peaks`), which exceeds the component's amplitude by
    the other component's share there.

    With ``profiles``, each element also gets the tracker's noise level near its line in the
    identifying runs: the lateral spectrum's per-bin noise σ (:func:`robomill.plan.noise.
    noise_floor_um` over ± ``noise_band_bins`` resolution bins, without ± ``noise_exclude_bins``
    around the run's detected peaks) times √T, T the run's record duration, which is the
    tracker's constant s √(6/f_s) (:mod:`robomill.plan.noise`); median over the runs
    (``noise_um_sqrt_s``, NaN without profiles). The lateral component: the one the outcome
    reads (the wall normal).

    Parameters
    ----------
    peaks
        ``results/straightness/peaks.csv`` (gear-attributed rows: ``mechanism`` gear, ``joint``
        given).
    profiles
        ``results/straightness/profiles.nc`` (the runs' spectra, joined on the peaks' ``run``).
    poses
        Per cut id (the peaks' ``cut``): the posture ``q_rad`` at the run's middle and the unit
        path direction ``u``.

    Returns
    -------
    pandas.DataFrame
        ``joint, stage, order, dq_urad, dq_low_urad, dq_high_urad, n_runs,
        noise_um_sqrt_s``.
    """
    cols = ["joint", "stage", "order", "dq_urad", "dq_low_urad", "dq_high_urad", "n_runs",
            "noise_um_sqrt_s"]
    if peaks is None or peaks.empty:
        return pd.DataFrame(columns=cols)
    g = peaks[(peaks.get("mechanism", "gear") == "gear") & peaks["joint"].notna()]
    rows = []
    for _, r in g.iterrows():
        pose = poses.get(str(r.get("cut", "")))
        if pose is None:
            continue
        q, u = pose
        j = int(r["joint"]) - 1
        Jv = jacobian_m(robot, np.asarray(q, float))[:3, j] * 1e6           # µm/rad
        axes = perpendicular_axes(np.asarray(u, float))
        ax = axes[0] if r["component"] == "lateral" else axes[1]
        sens = abs(float(ax @ Jv))
        if sens < min_sensitivity * np.linalg.norm(Jv) or sens == 0:
            continue
        a_um = float(r["amplitude_um"])
        rho = np.nan
        if profiles is not None and "run" in r:
            run = str(r["run"])
            a = spectrum_amplitude_um(profiles, run, str(r["component"]),
                                      float(r["f_spatial_per_mm"]))
            a_um = a if np.isfinite(a) else a_um
            others = peaks.loc[peaks["run"].astype(str) == run, "f_spatial_per_mm"]
            sigma = noise_floor_um(profiles, run, float(r["f_spatial_per_mm"]),
                                   exclude_per_mm=others.to_numpy(float),
                                   band_bins=noise_band_bins, exclude_bins=noise_exclude_bins)
            rho = sigma * np.sqrt(run_duration_s(profiles, run))
            sigma = sigma / np.sqrt(2) * float(stats.norm.ppf(0.5 + level / 2))
        else:
            sigma = 0.0
        rows.append({"joint": j + 1, "stage": r["stage"], "order": r["order"],
                     "dq": a_um / sens * 1e6, "rho": rho,
                     "dq_lo": max(a_um - np.nan_to_num(sigma), 0.0) / sens * 1e6,
                     "dq_hi": (a_um + np.nan_to_num(sigma)) / sens * 1e6})
    if not rows:
        return pd.DataFrame(columns=cols)
    g = pd.DataFrame(rows).groupby(["joint", "stage", "order"])
    t = g["dq"]
    out = pd.DataFrame({"dq_urad": t.median(), "dq_low_urad": g["dq_lo"].min(),
                        "dq_high_urad": g["dq_hi"].max(), "n_runs": t.size(),
                        "noise_um_sqrt_s": g["rho"].median()}).reset_index()
    return out[cols]


def waviness_um(robot: SerialRobot, q_rad: np.ndarray, normal: np.ndarray,
                gears: pd.DataFrame, *, direction: np.ndarray | None = None,
                length_mm: float | None = None, orders: Mapping | None = None,
                min_cycles: float = 4.5, feed_mm_s: np.ndarray | None = None,
                coverage: float = schema_default("plan.waviness_noise", "coverage"),
                level: float = schema_default("plan", "interval_level")
                ) -> dict[str, np.ndarray]:
    """Path waviness normal to the wall at postures ``q_rad`` ``(..., n)``: each gear element's
    joint amplitude carried through the Jacobian, A = δq_j |nᵀ J_v[:, j](q)|, summed over the
    elements (lines adding in phase: a bound on the peak waviness) [µm]; nominal, low, high
    from the elements' amplitude intervals (:func:`gear_joint_amplitudes`): the
    identification interval, the spread between the identifying runs.

    With the path ``direction`` (unit, ``(..., 3)`` or ``(3,)``), its ``length_mm`` and the
    elements' ``orders`` (cycles per joint revolution per ``(joint, stage, order)``,
    :func:`robomill.straightness.gear_orders`), an element counts only where it completes at
    least ``min_cycles`` periods along the cut: spatial frequency
    f = order·|dq_j/ds|/(2π) (dq/ds from J dq = (u, 0) at fixed orientation) times the length.
    A joint that hardly turns along the path prints its gear error as a slow offset, not as
    waviness; ``min_cycles`` is the analysis band's edge plus the Hann main lobe, where a
    read is clear of the slow deviation's lobe (:func:`robomill.plan.check.waviness_min_cycles`,
    the outcome's rule too).

    With the feeds ``feed_mm_s`` ``(V,)`` and the elements' ``noise_um_sqrt_s`` (the tracker's
    noise level, :func:`gear_joint_amplitudes`), also the interval of the amplitude the next
    tracker run along the cut reads, ``read_low``/``read_high`` ``(..., V)``: per counted
    element the noise per bin σ_e = ρ_e / √(L/v) of a record of duration L/v, and the central
    ``coverage`` range of the sum of the lines' reads, each line's amplitude drawn from its
    identification interval (at the two-sided ``level``) and read through the window with that
    noise (:func:`robomill.plan.noise.read_sum_interval_um`);
    ``noise`` the largest σ_e over the counted elements (NaN where none counts or no level
    is known).

    The quantity: the amplitude a of a·sin(2πfs) normal to the wall (n = ẑ × u, the
    tracker's lateral axis), summed over the lines; the outcome it is checked against reads
    the same quantity from the run's lateral amplitude spectrum (thesis eqs. 2.1–2.3:
    :func:`robomill.plan.check.waviness_outcomes`)."""
    J = jacobian_m(robot, q_rad)
    Jv = J[..., :3, :] * 1e6                                                 # µm/rad
    s = np.abs(np.einsum("...i,...ij->...j", np.asarray(normal, float), Jv))  # (..., n)
    rates = None
    if direction is not None and length_mm is not None and orders is not None:
        u = np.broadcast_to(np.asarray(direction, float), J.shape[:-2] + (3,))
        twist = np.concatenate([u * 1e-3, np.zeros_like(u)], -1)            # m per mm
        rates = np.abs(np.linalg.solve(J, twist[..., None])[..., 0])        # rad/mm
    out = {}
    counted = []
    terms = {}
    for key, col in (("nominal", "dq_urad"), ("low", "dq_low_urad"), ("high", "dq_high_urad")):
        tot = np.zeros(s.shape[:-1])
        terms[key] = []
        for _, r in gears.iterrows():
            j = int(r["joint"]) - 1
            term = s[..., j] * float(r[col]) * 1e-6
            count = np.ones(s.shape[:-1], bool)
            if rates is not None:
                order = orders.get((j + 1, str(r["stage"]), str(r["order"])))
                if order is not None:
                    cycles = order * rates[..., j] / (2 * np.pi) * float(length_mm)
                    count = cycles >= min_cycles
                    term = np.where(count, term, 0.0)
            if key == "nominal":
                counted.append(count)
            terms[key].append(term)
            tot = tot + term
        out[key] = tot
    if feed_mm_s is not None and length_mm is not None and "noise_um_sqrt_s" in gears:
        out.update(_read_interval(terms, counted, gears["noise_um_sqrt_s"].to_numpy(float),
                                  record_duration_s(length_mm, np.atleast_1d(feed_mm_s)),
                                  s.shape[:-1], coverage, level))
    return out


def _read_interval(terms, counted, rho, duration_s, shape, coverage, level):
    """``read_low``, ``read_high``, ``noise`` ``(*shape, V)`` of :func:`waviness_um`."""
    V = duration_s.size
    lo, hi = np.zeros(shape + (V,)), np.zeros(shape + (V,))
    noise = np.full(shape + (V,), np.nan)
    if not counted:
        return {"read_low": lo, "read_high": hi, "noise": noise}
    cnt = np.stack(counted, -1)[..., None, :]                               # (..., 1, G)
    sigma = rho[None, :] / np.sqrt(duration_s)[:, None]                     # (V, G)
    sig = np.where(cnt, sigma, np.nan)                                      # (..., V, G)
    line = {k: np.where(cnt, np.stack(terms[k], -1)[..., None, :], 0.0)
            for k in ("nominal", "low", "high")}
    lo, hi = read_sum_interval_um(line["nominal"], line["low"], line["high"], sig,
                                  coverage=coverage, level=level)
    noise = np.fmax.reduce(np.where(np.isfinite(sig), sig, np.nan), axis=-1)
    return {"read_low": lo, "read_high": hi, "noise": noise}


def cut_mid_poses(robot: SerialRobot, cuts, experiment: Mapping, *, tool_rotation: np.ndarray,
                  q0_rad: np.ndarray) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Posture at the middle of each study cut and its unit feed direction (the poses at which
    the tracker runs along those cuts saw their gear lines;
    :func:`robomill.experiment.cut_joint_path_rad`)."""
    from robomill.experiment import cut_joint_path_rad, feed_direction

    L = float(experiment["cut_length_mm"])
    out = {}
    for cut in cuts:
        q = cut_joint_path_rad(robot, cut, experiment, np.array([L / 2]),
                               tool_rotation=tool_rotation, q0_rad=q0_rad)[0]
        out[cut.id] = (q, feed_direction(cut))
    return out
