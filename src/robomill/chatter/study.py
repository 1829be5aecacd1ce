"""The chapter-4 computations as datasets (called by the rule scripts and the benchmark)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import xarray as xr

from robomill.chatter.detection import (
    SlidingDetector,
    chatter_indicator,
    growth_rate_1_s,
    run_adaptive,
)
from robomill.chatter.lobes_sdm import sdm_lobes, sdm_spectral_radius
from robomill.chatter.lobes_sem import ACCURACY, sem_lobes
from robomill.chatter.lobes_zoa import zoa_lobes
from robomill.chatter.model import CuttingModel, modes_from_xy_lists, tool_from_modes
from robomill.chatter.thesis import (
    DIRECTIONS,
    cutting_from_coefficients,
    mode_coupling,
    modes_in_slot_frame,
    recommend,
)
from robomill.chatter.timedomain import SeedParams, SeedSimulation, horizontal_tool
from robomill.xrvars import coord

SOLVERS = ("zoa", "sem")
MODE_COUPLING_RTOL = 0.005
"""Bisection bracket of the mode-coupling depth (its error is half of it)."""
GROWTH_WINDOW_TEETH = 20
"""Window of the indicator used for the growth rate, in tooth periods: short against the
e-folding time of chatter near the boundary (0.3 s at 1 % above it in the seed), long enough
to resolve the chatter line between two tooth-passing harmonics (bins of f_tooth/20)."""


def speed_grid(spec: dict) -> np.ndarray:
    return np.linspace(float(spec["start"]), float(spec["stop"]), int(spec["num"]))


def sdm_lobes_dataset(tool, cut: CuttingModel, rpm: np.ndarray, *, depth_max_m: float, m: int,
                      rtol: float, progress=None) -> xr.Dataset:
    """ZOA and first-order SDM lobes on one speed grid (the seed-002 diagram): a_crit_mm,
    chatter_hz over (solver = zoa, sdm; spindle_rpm), and the SDM bifurcation kind."""
    a_z, f_z = zoa_lobes(tool, cut, rpm)
    a_s, f_s, kind = sdm_lobes(tool, cut, rpm, depth_max_m=depth_max_m, m=m, rtol=rtol,
                               f_ref_hz=f_z, progress=progress)
    return xr.Dataset(
        {
            "a_crit_mm": (("solver", "spindle_rpm"), np.stack([a_z, a_s]) * 1e3,
                          {"units": "mm", "long_name": "critical axial depth of cut"}),
            "chatter_hz": (("solver", "spindle_rpm"), np.stack([f_z, f_s]),
                           {"units": "Hz", "long_name": "chatter frequency at the boundary"}),
            "sdm_bifurcation": ("spindle_rpm", kind.astype(str),
                                {"units": "1", "long_name": "SDM critical multiplier: hopf, "
                                 "flip (period doubling), fold; empty if stable to depth_max"}),
        },
        coords={"solver": ("solver", ["zoa", "sdm"], {"units": "1", "long_name":
                                                      "zoa: zero-order analytical; sdm: "
                                                      "semi-discretization"}),
                "spindle_rpm": coord("spindle_rpm", rpm, "rpm", "spindle speed")},
        attrs={"sdm_steps_per_period": int(m), "sdm_rtol": float(rtol),
               "depth_max_mm": depth_max_m * 1e3})


def lobes_dataset(tool, cut: CuttingModel, rpm: np.ndarray, *, depth_max_m: float,
                  accuracy: float, progress=None) -> xr.Dataset:
    """ZOA and converged spectral-element lobes on one speed grid: ``a_crit_mm``,
    ``chatter_hz`` over (solver = zoa, sem; spindle_rpm); beside them the SEM's estimated
    discretization error ``a_crit_error_mm`` (refined per speed to ``accuracy``), its
    ``bifurcation`` kind and the ``collocation_order`` used
    (:func:`robomill.chatter.lobes_sem.sem_lobes`)."""
    a_z, f_z = zoa_lobes(tool, cut, rpm)
    r = sem_lobes(tool, cut, rpm, depth_max_m=depth_max_m, accuracy=accuracy, f_ref_hz=f_z,
                  progress=progress)
    return xr.Dataset(
        {
            "a_crit_mm": (("solver", "spindle_rpm"), np.stack([a_z, r["a_crit_m"]]) * 1e3,
                          {"units": "mm", "long_name": "critical axial depth of cut"}),
            "a_crit_error_mm": ("spindle_rpm", r["error_m"] * 1e3,
                                {"units": "mm", "long_name": "estimated discretization error "
                                 "of the sem critical depth: |a(p) - a(p-2)| + root tolerance"}),
            "chatter_hz": (("solver", "spindle_rpm"), np.stack([f_z, r["chatter_hz"]]),
                           {"units": "Hz", "long_name": "chatter frequency at the boundary"}),
            "bifurcation": ("spindle_rpm", r["kind"].astype(str),
                            {"units": "1", "long_name": "sem critical multiplier: hopf, "
                             "flip (period doubling), fold; empty if stable to depth_max"}),
            "collocation_order": ("spindle_rpm", r["p"].astype(np.int64),
                                  {"units": "1", "long_name": "sem polynomial order p per "
                                   "element at which the accuracy was met"}),
        },
        coords={"solver": ("solver", list(SOLVERS), {"units": "1", "long_name":
                                                     "zoa: zero-order analytical; sem: "
                                                     "spectral element (Chebyshev "
                                                     "collocation)"}),
                "spindle_rpm": coord("spindle_rpm", rpm, "rpm", "spindle speed")},
        attrs={"accuracy": float(accuracy), "depth_max_mm": depth_max_m * 1e3,
               "worst_relative_error": float(np.nanmax(r["error_m"] / r["a_crit_m"]))
               if np.isfinite(r["a_crit_m"]).any() else float("nan")})


def run_case(case: dict, *, accuracy: float, depth_max_m: float,
             progress=None) -> xr.Dataset:
    """One configured lobe case (schema ``chatter.cases[]``); ``progress(fraction)`` is called
    as the semi-discretization works through the speed grid."""
    modes = modes_from_xy_lists(case["modes"].get("x", []), case["modes"].get("y", []))
    tool = tool_from_modes(modes)
    cut = CuttingModel.from_immersion(case["teeth"], case["Kt_N_m2"], case["Kr"],
                                      case["radial_immersion"], case["milling"])
    ds = lobes_dataset(tool, cut, speed_grid(case["spindle_rpm"]), depth_max_m=depth_max_m,
                       accuracy=accuracy, progress=progress)
    ds.attrs.update({"case_" + k: v for k, v in case.items() if k != "modes"})
    ds.attrs["case_modes"] = case["modes"]
    ds.attrs["phi_st_rad"], ds.attrs["phi_ex_rad"] = cut.phi_st, cut.phi_ex
    return ds


def _indicator_series(rec: dict, fs: float, tooth_hz: float, det: dict, hop_s: float):
    R = np.hypot(rec["Rx_N"], rec["Rz_N"])
    n = int(round(det["window_s"] * fs))
    ends = np.arange(n, R.size + 1, max(1, int(round(hop_s * fs))))
    out = [chatter_indicator(R[e - n:e], fs, tooth_hz, tuple(det["band_hz"]),
                             det["harmonic_halfwidth_hz"]) for e in ends]
    return rec["t_s"][ends - 1], np.array([o[0] for o in out]), np.array([o[1] for o in out])


def _detector(sim, p: SeedParams, det: dict) -> SlidingDetector:
    return SlidingDetector(sim.record_fs_hz, p.teeth * p.spindle_rpm / 60.0,
                           window_s=det["window_s"], band_hz=tuple(det["band_hz"]),
                           harmonic_halfwidth_hz=det["harmonic_halfwidth_hz"],
                           growth_ratio=det["growth_ratio"],
                           rising_windows=det["rising_windows"],
                           min_fraction_of_mean=det["min_fraction_of_mean"])


def growth_rate_of_run(rec: dict, fs_hz: float, tooth_hz: float, det: dict) -> float:
    """Simulated chatter growth rate [1/s] of a run: :func:`growth_rate_1_s` on the indicator
    over ``GROWTH_WINDOW_TEETH``-tooth windows advanced one tooth period at a time."""
    t, amp, _ = _indicator_series(rec, fs_hz, tooth_hz,
                                  dict(det, window_s=GROWTH_WINDOW_TEETH / tooth_hz),
                                  1.0 / tooth_hz)
    return growth_rate_1_s(t, amp)


def classify_run(p: SeedParams, depth_m: float, *, duration_s: float, steps_per_tooth: int,
                 det: dict) -> tuple[bool, float, float]:
    """Time-domain verdict at fixed setpoint: unstable when the chatter indicator of the last
    window exceeds the detector floor (a fraction of the mean force). Returns (unstable,
    indicator of the last window [N], simulated growth rate [1/s], NaN if it does not grow)."""
    sim = SeedSimulation(p, depth_m, steps_per_tooth=steps_per_tooth, duration_s=duration_s)
    sim.run(duration_s)
    rec = sim.record()
    fs = sim.record_fs_hz
    tooth_hz = p.teeth * p.spindle_rpm / 60.0
    n = int(round(det["window_s"] * fs))
    R = np.hypot(rec["Rx_N"], rec["Rz_N"])[-n:]
    amp, _ = chatter_indicator(R, fs, tooth_hz, tuple(det["band_hz"]),
                               det["harmonic_halfwidth_hz"])
    unstable = bool(amp >= det["min_fraction_of_mean"] * np.mean(R))
    return unstable, float(amp), growth_rate_of_run(rec, fs, tooth_hz, det)


def run_seed(cfg: dict, *, accuracy: float = ACCURACY) -> xr.Dataset:
    """Seed 002: its lobe diagram, points 1 and 2, the three time histories (point 1, point 2
    without and with adaptation), the indicator histories and the onset check."""
    p = SeedParams.from_config(cfg["params"])
    tool = horizontal_tool(p)
    cut = p.cutting_model()
    rpm = speed_grid(cfg["spindle_rpm"])
    lobes = sdm_lobes_dataset(tool, cut, rpm, depth_max_m=cfg["depth_max_mm"] * 1e-3,
                              m=cfg["sdm_steps_per_period"], rtol=cfg["rtol"])
    a_sdm = lobes["a_crit_mm"].sel(solver="sdm").values * 1e-3
    # the SDM diagram's own discretization error: its distance to the converged spectral
    # element (plus that one's error estimate); the time-domain points below stay on the SDM
    ref = sem_lobes(tool, cut, rpm, depth_max_m=cfg["depth_max_mm"] * 1e-3, accuracy=accuracy)
    sdm_err = np.abs(a_sdm - ref["a_crit_m"]) + ref["error_m"]
    a_star = float(np.nanmin(a_sdm))
    a_at_n, f_at_n, kind_at_n = sdm_lobes(tool, cut, [p.spindle_rpm],
                                          depth_max_m=cfg["depth_max_mm"] * 1e-3,
                                          m=cfg["sdm_steps_per_period"], rtol=cfg["rtol"] / 5)
    a_n = float(a_at_n[0])
    a1, a2 = cfg["point1_fraction"] * a_n, cfg["point2_fraction"] * a_n
    det, ad, dur = cfg["detector"], cfg["adaptation"], cfg["duration_s"]
    spt = cfg["steps_per_tooth"]
    tooth_hz = p.teeth * p.spindle_rpm / 60.0
    runs, indic, events = {}, {}, {}
    for name, depth, adapt in (("point1", a1, False), ("point2", a2, False),
                               ("point2_adaptive", a2, True)):
        sim = SeedSimulation(p, depth, steps_per_tooth=spt, duration_s=dur)
        out = run_adaptive(sim, _detector(sim, p, det), duration_s=dur, hop_s=det["hop_s"],
                           step_fraction=ad["step_fraction"],
                           max_total_fraction=ad["max_total_fraction"], hold_s=ad["hold_s"],
                           adapt=adapt)
        runs[name] = sim.record()
        indic[name] = _indicator_series(runs[name], sim.record_fs_hz, tooth_hz, det,
                                        det["hop_s"])
        events[name] = out
    fs = sim.record_fs_hz
    t = runs["point1"]["t_s"]
    nt = min(len(r["t_s"]) for r in runs.values())
    names = list(runs)

    def stack(key, scale=1.0):
        return np.stack([runs[k][key][:nt] * scale for k in names])

    # amplitude spectra of the resultant horizontal force over the last window of each run
    n_w = int(round(det["window_s"] * fs))
    spectra = []
    for k in names:
        R = np.hypot(runs[k]["Rx_N"], runs[k]["Rz_N"])[:nt][-n_w:]
        w = np.hanning(n_w)
        spectra.append(2 * np.abs(np.fft.rfft((R - R.mean()) * w)) / w.sum())
    fspec = np.fft.rfftfreq(n_w, 1 / fs)
    ti = indic["point1"][0]
    nti = min(len(v[0]) for v in indic.values())
    # onset check: lobes vs time domain at a few speeds, just below and above the boundary
    onset = []
    for n_rpm in cfg["onset"]["spindle_rpm"]:
        pn = SeedParams(**{**p.as_dict(), "spindle_rpm": float(n_rpm)})
        a_b = float(sdm_lobes(horizontal_tool(pn), pn.cutting_model(), [n_rpm],
                              depth_max_m=cfg["depth_max_mm"] * 1e-3,
                              m=cfg["sdm_steps_per_period"], rtol=cfg["rtol"] / 5)[0][0])
        fracs = np.asarray(cfg["onset"]["depth_fractions"], float)
        rho, _ = sdm_spectral_radius(horizontal_tool(pn), pn.cutting_model(), n_rpm,
                                     fracs * a_b, m=cfg["sdm_steps_per_period"])
        for frac, sigma in zip(fracs, np.log(rho) / pn.tooth_period_s, strict=True):
            unstable, amp, grow = classify_run(pn, frac * a_b, steps_per_tooth=spt, det=det,
                                               duration_s=cfg["onset"]["duration_s"])
            onset.append((n_rpm, frac, a_b * 1e3, unstable, amp, sigma,
                          grow if frac > 1 else np.nan))
    onset = np.array(onset, float)
    runs_attrs = {"units": "1", "long_name": "point1: stable point; point2: unstable point; "
                  "point2_adaptive: point 2 with detection and depth lowering"}
    ds = xr.Dataset(
        {
            "xs_vib_um": (("run", "time"), stack("xs_vib_m", 1e6),
                          {"units": "um", "long_name": "tool vibration x_s (feed direction)"}),
            "zs_um": (("run", "time"), stack("zs_m", 1e6),
                      {"units": "um", "long_name": "tool displacement z_s (normal)"}),
            "Rx_N": (("run", "time"), stack("Rx_N"), {"units": "N", "long_name":
                                                      "cutting force R_x"}),
            "Rz_N": (("run", "time"), stack("Rz_N"), {"units": "N", "long_name":
                                                      "cutting force R_z"}),
            "R_N": (("run", "time"), np.hypot(stack("Rx_N"), stack("Rz_N")),
                    {"units": "N", "long_name": "resultant horizontal cutting force"}),
            "depth_mm": (("run", "time"), stack("depth_m", 1e3),
                         {"units": "mm", "long_name": "axial depth of cut"}),
            "Fsy_N": (("run", "time"), stack("Fsy_N"),
                      {"units": "N", "long_name": "vertical suspension force F_sy"}),
            "spectrum_N": (("run", "frequency"), np.array(spectra),
                           {"units": "N", "long_name": "amplitude spectrum of R over the last "
                            "window"}),
            "indicator_N": (("run", "window_end"), np.stack([indic[k][1][:nti] for k in names]),
                            {"units": "N", "long_name": "chatter indicator (largest "
                             "non-harmonic line)"}),
            "indicator_hz": (("run", "window_end"),
                             np.stack([indic[k][2][:nti] for k in names]),
                             {"units": "Hz", "long_name": "frequency of the indicator line"}),
            "seed_a_crit_mm": (("solver", "spindle_rpm"), lobes["a_crit_mm"].values,
                               lobes["a_crit_mm"].attrs),
            "seed_a_crit_error_mm": ("spindle_rpm", sdm_err * 1e3, {
                "units": "mm", "long_name": "discretization error of the sdm critical depth: "
                "|a_sdm - a_sem| + the sem error estimate (sem converged to accuracy)"}),
            "seed_a_crit_sem_mm": ("spindle_rpm", ref["a_crit_m"] * 1e3, {
                "units": "mm", "long_name": "converged critical depth (spectral element)"}),
            "seed_chatter_hz": (("solver", "spindle_rpm"), lobes["chatter_hz"].values,
                                lobes["chatter_hz"].attrs),
            "onset_a_boundary_mm": ("check", onset[:, 2], {"units": "mm", "long_name":
                                                           "SDM boundary at the check speed"}),
            "onset_depth_fraction": ("check", onset[:, 1], {"units": "1", "long_name":
                                                            "simulated depth / boundary"}),
            "onset_check_rpm": ("check", onset[:, 0], {"units": "rpm", "long_name":
                                                       "spindle speed of the check"}),
            "onset_unstable": ("check", onset[:, 3].astype(bool),
                               {"units": "1", "long_name": "time domain finds chatter"}),
            "onset_indicator_N": ("check", onset[:, 4], {"units": "N", "long_name":
                                                         "indicator in the last window"}),
            "onset_growth_rate_sdm_1_s": ("check", onset[:, 5], {
                "units": "1/s", "long_name": "SDM Floquet exponent ln(rho)/tau at the depth"}),
            "onset_growth_rate_simulated_1_s": ("check", onset[:, 6], {
                "units": "1/s", "long_name": "simulated chatter growth rate (unstable checks)"}),
        },
        coords={
            "run": ("run", names, runs_attrs),
            "time": ("time", t[:nt], {"units": "s", "long_name": "time"}),
            "frequency": ("frequency", fspec, {"units": "Hz", "long_name": "frequency"}),
            "window_end": ("window_end", ti[:nti], {"units": "s", "long_name":
                                                    "end time of the sliding window"}),
            "solver": lobes["solver"],
            "spindle_rpm": lobes["spindle_rpm"],
            "check": ("check", np.arange(len(onset)), {"units": "1", "long_name":
                                                       "onset check number"}),
        },
    )
    ev = events["point2_adaptive"]
    # linear theory beside the simulation: Floquet exponents σ = ln ρ / τ of the SDM at the
    # point-2 depth and at the depth the logic block left, against the simulated growth
    a_adapted = a2 * (1.0 - ev["lowered_fraction"])
    rho, _ = sdm_spectral_radius(tool, cut, p.spindle_rpm, np.array([a2, a_adapted]),
                                 m=cfg["sdm_steps_per_period"])
    sigma_sdm = np.log(rho) / p.tooth_period_s
    sigma_sim = growth_rate_of_run(runs["point2"], fs, tooth_hz, det)
    # settling: mean chatter indicator over the last quarter of each run
    final = {k: float(np.mean(indic[k][1][indic[k][0] >= 0.75 * dur])) for k in names}
    ds.attrs.update({
        "sdm_bifurcation_at_n": str(kind_at_n[0]),
        "detector_window_s": float(det["window_s"]),
        "growth_window_teeth": GROWTH_WINDOW_TEETH,
        "Kt_noise_fraction": float(p.Kt_noise_fraction),
        "sdm_chatter_hz_at_n": float(f_at_n[0]),
        "growth_rate_sdm_point2_1_s": float(sigma_sdm[0]),
        "growth_rate_sdm_adapted_1_s": float(sigma_sdm[1]),
        "growth_rate_simulated_point2_1_s": sigma_sim,
        "adapted_depth_mm": a_adapted * 1e3,
        **{f"indicator_final_{k}_N": v for k, v in final.items()},
        "seed_params": p.as_dict(), "a_star_mm": a_star * 1e3,
        "a_boundary_at_n_mm": a_n * 1e3, "point1_depth_mm": a1 * 1e3,
        "point2_depth_mm": a2 * 1e3, "spindle_rpm_seed": p.spindle_rpm,
        "tooth_hz": tooth_hz, "record_fs_hz": fs,
        "detections_point2_s": list(map(float, events["point2"]["detections"])),
        "detections_adaptive_s": list(map(float, ev["detections"])),
        "adaptation_times_s": [float(e[0]) for e in ev["events"]],
        "adaptation_setpoint_fraction": [float(e[1]) for e in ev["events"]],
        "adaptation_lowered_fraction": float(ev["lowered_fraction"]),
        "detections_point1_s": list(map(float, events["point1"]["detections"])),
        "chatter_hz_zoa_at_n": float(np.interp(p.spindle_rpm, rpm, lobes["chatter_hz"]
                                               .sel(solver="zoa").values)),
        "sdm_steps_per_period": int(cfg["sdm_steps_per_period"]),
        "accuracy": float(accuracy),
        "steps_per_tooth": int(spt),
    })
    return ds


def run_thesis(modes: pd.DataFrame, coeffs: pd.DataFrame, peaks: pd.DataFrame, cfg: dict,
               *, teeth: int, spindle_rpm: float, depths_mm: list[float],
               accuracy: float) -> tuple[xr.Dataset, pd.DataFrame]:
    """Lobes for the +X, +Y, −Y slots (converged to ``accuracy``, with their error), the
    mode-coupling check, the force-peak comparison and the recommendations table.

    The recommended depth applies the safety fraction on top of the error: a_rec =
    (1 − safety_fraction)(a_limit − a_limit_error), with a_limit the smaller of the
    regenerative and mode-coupling depths and a_limit_error the discretization error of the
    regenerative depth (sem; none for zoa) or the bisection half-bracket of the mode-coupling
    depth; ``stability_margin_min`` = (a_limit − a_limit_error)/a − 1 is the margin at the
    pessimistic end of the error and decides ``chatter_free``. The study's ``spindle_rpm`` is
    added to the speed grid (``chatter.thesis.spindle_rpm``) where the grid misses it, so that
    its recommendation rows are at the speed the study cut with."""
    cut = cutting_from_coefficients(coeffs, teeth)
    rpm = speed_grid(cfg["spindle_rpm"])
    if spindle_rpm is not None and not np.isclose(rpm, spindle_rpm, rtol=1e-9, atol=0).any():
        rpm = np.sort(np.append(rpm, float(spindle_rpm)))  # the study's own speed, exactly
    dmax = cfg["depth_max_mm"] * 1e-3
    per_dir, mc, rows = [], [], []
    for d in DIRECTIONS:
        modes_d = modes_in_slot_frame(modes, d)
        tool = tool_from_modes(modes_d)
        ds = lobes_dataset(tool, cut, rpm, depth_max_m=dmax, accuracy=accuracy)
        per_dir.append(ds)
        mc.append(mode_coupling(modes_d, cut, depth_max_m=dmax, rtol=MODE_COUPLING_RTOL))
        for s in SOLVERS:
            err = ds["a_crit_error_mm"].values * 1e-3 if s == "sem" else None
            rows += recommend(ds["a_crit_mm"].sel(solver=s).values * 1e-3, rpm,
                              ds["chatter_hz"].sel(solver=s).values, d,
                              thesis_rpm=spindle_rpm,
                              thesis_depths_m=[x * 1e-3 for x in depths_mm],
                              safety_fraction=cfg["safety_fraction"], solver=s,
                              a_error_m=err)
    lobes = xr.concat(per_dir, dim=xr.DataArray(list(DIRECTIONS), dims="direction"))
    lobes["direction"].attrs = {"units": "1", "long_name": "slot feed direction (px: +X, "
                                "py: +Y, my: -Y)"}
    rel = lobes["a_crit_error_mm"] / lobes["a_crit_mm"].sel(solver="sem")
    lobes.attrs["worst_relative_error"] = float(rel.max()) if rel.notnull().any() else np.nan
    # force peaks (60–120 Hz in the thesis) by direction
    pk = peaks.copy()
    pk["direction"] = pk["cut"].astype(str).str.rsplit("_", n=1).str[-1]
    fmin = [pk.loc[pk.direction == d, "dominant_hz"].min() for d in DIRECTIONS]
    fmed = [pk.loc[pk.direction == d, "dominant_hz"].median() for d in DIRECTIONS]
    fmax = [pk.loc[pk.direction == d, "dominant_hz"].max() for d in DIRECTIONS]
    lobes["mode_coupling_a_mm"] = ("direction", [x["a_mc_m"] * 1e3 for x in mc],
                                   {"units": "mm", "long_name": "mode-coupling critical depth "
                                    "(2-D model without delay)"})
    lobes["mode_coupling_hz"] = ("direction", [x["frequency_hz"] for x in mc],
                                 {"units": "Hz", "long_name": "mode-coupling frequency"})
    lobes["coupled_mode_hz"] = (("direction", "pair"), [x["pair_hz"] for x in mc],
                                {"units": "Hz", "long_name": "natural frequencies of the "
                                 "coupled pair"})
    lobes["coupled_mode"] = (("direction", "pair"), [x["pair"] for x in mc],
                             {"units": "1", "long_name": "row index in modes.csv of the "
                              "coupled pair"})
    lobes["pair"] = ("pair", [0, 1], {"units": "1", "long_name": "member of the pair"})
    for name, vals, ln in (("force_peak_min_hz", fmin, "smallest"),
                           ("force_peak_median_hz", fmed, "median"),
                           ("force_peak_max_hz", fmax, "largest")):
        lobes[name] = ("direction", np.asarray(vals, float),
                       {"units": "Hz", "long_name": f"{ln} dominant force peak over the cuts"})
    lobes["frequency"] = ("frequency", np.linspace(1.0, 200.0, 400),
                          {"units": "Hz", "long_name": "frequency"})
    frf = np.stack([np.abs(tool_from_modes(modes_in_slot_frame(modes, d))
                           .frf(lobes["frequency"].values)) for d in DIRECTIONS])
    lobes["frf_abs_m_N"] = (("direction", "out", "in", "frequency"), frf,
                            {"units": "m/N", "long_name": "|G| in the slot frame"})
    lobes["out"] = ("out", ["feed", "normal"], {"units": "1", "long_name": "response axis"})
    lobes["in"] = ("in", ["feed", "normal"], {"units": "1", "long_name": "force axis"})
    lobes.attrs.update({"Kt_N_m2": cut.Kt_N_m2, "Kr": cut.Kr, "teeth": cut.teeth,
                        "thesis_spindle_rpm": spindle_rpm, "thesis_depths_mm": list(depths_mm)})
    rec = pd.DataFrame(rows)
    # mode coupling does not depend on speed: it caps the depth at every speed
    amc = {d: x["a_mc_m"] * 1e3 for d, x in zip(DIRECTIONS, mc, strict=True)}
    rec["a_mode_coupling_mm"] = rec["direction"].map(amc)
    limit = np.fmin(rec["a_crit_mm"], rec["a_mode_coupling_mm"])
    by_mc = rec["a_mode_coupling_mm"] < rec["a_crit_mm"]
    limit_err = np.where(by_mc, 0.5 * MODE_COUPLING_RTOL * rec["a_mode_coupling_mm"],
                         rec["a_crit_error_mm"].fillna(0.0))
    is_rec = rec["kind"] == "recommended"
    rec.loc[is_rec, "axial_depth_mm"] = ((1 - cfg["safety_fraction"])
                                         * (limit - limit_err)[is_rec])
    rec["a_limit_mm"] = limit
    rec["a_limit_error_mm"] = limit_err
    rec["limited_by"] = np.where(by_mc, "mode_coupling", "regenerative")
    rec["stability_margin"] = rec["a_limit_mm"] / rec["axial_depth_mm"] - 1
    rec["stability_margin_min"] = ((rec["a_limit_mm"] - rec["a_limit_error_mm"])
                                   / rec["axial_depth_mm"] - 1)
    rec["chatter_free"] = rec["stability_margin_min"] > 0
    fpk = dict(zip(DIRECTIONS, fmed, strict=True))
    rec["force_peak_median_hz"] = rec["direction"].map(fpk)
    return lobes, rec
