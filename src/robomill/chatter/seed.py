"""The Shagniev 2019 study: its lobe diagram, points 1 and 2 simulated in the time domain (point 2
also with detection and depth lowering), the chatter indicator histories and the onset check
of the lobes against the time domain at a few speeds."""

from __future__ import annotations

import numpy as np
import xarray as xr

from robomill.chatter.detection import (
    SlidingDetector,
    chatter_indicator,
    growth_rate_1_s,
    run_adaptive,
)
from robomill.chatter.lobe_maps import sdm_lobes_dataset, speed_grid
from robomill.chatter.lobes_sdm import sdm_lobes, sdm_spectral_radius
from robomill.chatter.lobes_sem import ACCURACY, sem_lobes
from robomill.chatter.timedomain import SeedParams, SeedSimulation, horizontal_tool

GROWTH_WINDOW_TEETH = 20
"""Window of the indicator used for the growth rate, in tooth periods: short against the
e-folding time of chatter near the boundary (0.3 s at 1 % above it in the seed), long enough
to resolve the chatter line between two tooth-passing harmonics (bins of f_tooth/20)."""

#: the simulated runs: name, which depth (point 1 or 2), with the adaptive logic
RUNS = (("point1", "a1", False), ("point2", "a2", False), ("point2_adaptive", "a2", True))


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


def _simulate_runs(p: SeedParams, cfg: dict, depths_m: dict[str, float]):
    """The three runs of :data:`RUNS`: their records, indicator histories (end times,
    amplitudes, frequencies), the detector's events, and the records' sampling rate [Hz]."""
    det, ad, dur = cfg["detector"], cfg["adaptation"], cfg["duration_s"]
    tooth_hz = p.teeth * p.spindle_rpm / 60.0
    runs, indic, events = {}, {}, {}
    for name, point, adapt in RUNS:
        sim = SeedSimulation(p, depths_m[point], steps_per_tooth=cfg["steps_per_tooth"],
                             duration_s=dur)
        out = run_adaptive(sim, _detector(sim, p, det), duration_s=dur, hop_s=det["hop_s"],
                           step_fraction=ad["step_fraction"],
                           max_total_fraction=ad["max_total_fraction"], hold_s=ad["hold_s"],
                           adapt=adapt)
        runs[name] = sim.record()
        indic[name] = _indicator_series(runs[name], sim.record_fs_hz, tooth_hz, det,
                                        det["hop_s"])
        events[name] = out
    return runs, indic, events, sim.record_fs_hz


def _last_window_spectra(runs: dict, nt: int, n_w: int, fs_hz: float):
    """Amplitude spectra [N] of the resultant horizontal force over the last ``n_w`` samples
    of each run (Hann window), and their frequencies [Hz]."""
    spectra = []
    for rec in runs.values():
        R = np.hypot(rec["Rx_N"], rec["Rz_N"])[:nt][-n_w:]
        w = np.hanning(n_w)
        spectra.append(2 * np.abs(np.fft.rfft((R - R.mean()) * w)) / w.sum())
    return np.array(spectra), np.fft.rfftfreq(n_w, 1 / fs_hz)


def _onset_checks(p: SeedParams, cfg: dict) -> np.ndarray:
    """Lobes against the time domain at the ``onset`` speeds, just below and above the SDM
    boundary: rows (rpm, depth fraction, boundary [mm], unstable, indicator [N], SDM Floquet
    exponent [1/s], simulated growth rate [1/s], NaN below the boundary)."""
    det, spt = cfg["detector"], cfg["steps_per_tooth"]
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
    return np.array(onset, float)


def _runs_variables(runs: dict, indic: dict, nt: int, nti: int,
                    spectra: np.ndarray) -> dict:
    """The time histories, spectra and indicator histories of the runs, as data variables."""
    names = list(runs)

    def stack(key, scale=1.0):
        return np.stack([runs[k][key][:nt] * scale for k in names])

    return {
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
        "spectrum_N": (("run", "frequency"), spectra,
                       {"units": "N", "long_name": "amplitude spectrum of R over the last "
                        "window"}),
        "indicator_N": (("run", "window_end"), np.stack([indic[k][1][:nti] for k in names]),
                        {"units": "N", "long_name": "chatter indicator (largest "
                         "non-harmonic line)"}),
        "indicator_hz": (("run", "window_end"),
                         np.stack([indic[k][2][:nti] for k in names]),
                         {"units": "Hz", "long_name": "frequency of the indicator line"}),
    }


def _lobe_variables(lobes: xr.Dataset, sdm_err: np.ndarray, a_sem_m: np.ndarray) -> dict:
    """The seed's lobe diagram (zoa and sdm), the sdm's error and the converged depth."""
    return {
        "seed_a_crit_mm": (("solver", "spindle_rpm"), lobes["a_crit_mm"].values,
                           lobes["a_crit_mm"].attrs),
        "seed_a_crit_error_mm": ("spindle_rpm", sdm_err * 1e3, {
            "units": "mm", "long_name": "discretization error of the sdm critical depth: "
            "|a_sdm - a_sem| + the sem error estimate (sem converged to accuracy)"}),
        "seed_a_crit_sem_mm": ("spindle_rpm", a_sem_m * 1e3, {
            "units": "mm", "long_name": "converged critical depth (spectral element)"}),
        "seed_chatter_hz": (("solver", "spindle_rpm"), lobes["chatter_hz"].values,
                            lobes["chatter_hz"].attrs),
    }


def _onset_variables(onset: np.ndarray) -> dict:
    """The onset checks (:func:`_onset_checks`) as data variables over ``check``."""
    return {
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
    }


def run_seed(cfg: dict, *, accuracy: float = ACCURACY) -> xr.Dataset:
    """Shagniev 2019: its lobe diagram, points 1 and 2, the three time histories (point 1, point 2
    without and with adaptation), the indicator histories and the onset check."""
    p = SeedParams.from_config(cfg["params"])
    tool = horizontal_tool(p)
    cut = p.cutting_model()
    rpm = speed_grid(cfg["spindle_rpm"])
    depth_max_m = cfg["depth_max_mm"] * 1e-3
    lobes = sdm_lobes_dataset(tool, cut, rpm, depth_max_m=depth_max_m,
                              m=cfg["sdm_steps_per_period"], rtol=cfg["rtol"])
    a_sdm = lobes["a_crit_mm"].sel(solver="sdm").values * 1e-3
    # the SDM diagram's own discretization error: its distance to the converged spectral
    # element (plus that one's error estimate); the time-domain points below stay on the SDM
    ref = sem_lobes(tool, cut, rpm, depth_max_m=depth_max_m, accuracy=accuracy)
    sdm_err = np.abs(a_sdm - ref["a_crit_m"]) + ref["error_m"]
    a_star = float(np.nanmin(a_sdm))
    a_at_n, f_at_n, kind_at_n = sdm_lobes(tool, cut, [p.spindle_rpm], depth_max_m=depth_max_m,
                                          m=cfg["sdm_steps_per_period"], rtol=cfg["rtol"] / 5)
    a_n = float(a_at_n[0])
    a1, a2 = cfg["point1_fraction"] * a_n, cfg["point2_fraction"] * a_n
    det, dur = cfg["detector"], cfg["duration_s"]
    tooth_hz = p.teeth * p.spindle_rpm / 60.0
    runs, indic, events, fs = _simulate_runs(p, cfg, {"a1": a1, "a2": a2})
    names = list(runs)
    nt = min(len(r["t_s"]) for r in runs.values())
    nti = min(len(v[0]) for v in indic.values())
    spectra, fspec = _last_window_spectra(runs, nt, int(round(det["window_s"] * fs)), fs)
    onset = _onset_checks(p, cfg)
    ds = xr.Dataset(
        {**_runs_variables(runs, indic, nt, nti, spectra),
         **_lobe_variables(lobes, sdm_err, ref["a_crit_m"]), **_onset_variables(onset)},
        coords={
            "run": ("run", names, {"units": "1", "long_name": "point1: stable point; point2: "
                                   "unstable point; point2_adaptive: point 2 with detection "
                                   "and depth lowering"}),
            "time": ("time", runs["point1"]["t_s"][:nt], {"units": "s", "long_name": "time"}),
            "frequency": ("frequency", fspec, {"units": "Hz", "long_name": "frequency"}),
            "window_end": ("window_end", indic["point1"][0][:nti],
                           {"units": "s", "long_name": "end time of the sliding window"}),
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
        "steps_per_tooth": int(cfg["steps_per_tooth"]),
    })
    return ds
