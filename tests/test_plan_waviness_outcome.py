"""The waviness outcome of a cut is read from its tracker run's spectrum at the gear lines the
prediction used, detected as peaks or not, in the prediction's component (lateral = wall
normal ẑ × u) and amplitude definition (sinusoid amplitude a of a·sin(2πfs))."""

import numpy as np
import pandas as pd
import pytest
from conftest import default_cell_posture

from robomill.plan.check import RunOutcomes, check_table, waviness_elements, waviness_outcomes
from robomill.plan.measured import gear_joint_amplitudes
from robomill.straightness import profile_spectrum, spectrum_peaks
from robomill.straightness.profile import Profile, profile_dataset
from robomill.straightness.study import gather_profiles

DS_MM, N = 0.01, 4000                       # a 40 mm path on the study's grid
L_MM = DS_MM * N
STRONG_UM, F_STRONG = 1.0, 0.5123           # lateral line of element (2, motor, mesh)
WEAK_UM, F_WEAK = 0.05, 1.3071              # lateral line of element (3, motor, mesh)
VERTICAL_UM = 2.0                           # vertical line at F_STRONG: not the wall normal
OTHER_UM, F_OTHER = 0.7, 3.011              # a line of an element the prediction did not use
NOISE_UM = 0.3                              # white noise per component, RMS


def planted_run(run, cut, seed=0):
    rng = np.random.default_rng(seed)
    s = DS_MM * np.arange(N)
    lat = (STRONG_UM * np.sin(2 * np.pi * F_STRONG * s + 0.3)
           + WEAK_UM * np.sin(2 * np.pi * F_WEAK * s + 1.1)
           + OTHER_UM * np.sin(2 * np.pi * F_OTHER * s) + NOISE_UM * rng.standard_normal(N))
    vert = VERTICAL_UM * np.sin(2 * np.pi * F_STRONG * s - 0.7) + NOISE_UM * rng.standard_normal(N)
    prof = Profile(s_mm=s, deviation_um=np.stack([lat, vert]), start_mm=np.zeros(3),
                   end_mm=np.array([L_MM, 0, 0]), direction=np.array([1.0, 0, 0]),
                   ds_mm=DS_MM, speed_mm_s=1.0)
    spec = profile_spectrum(prof, nfft=32768)
    attrs = {"direction": "px", "feed_mm_s": 1.0, "cut": cut, "fmin_per_mm": 2.5 / L_MM,
             "floor_um2": 0.0}
    return prof, spec, profile_dataset(prof, spec, fmax_store_per_mm=20.0, attrs=attrs)


ELEMENTS_PEAKS = pd.DataFrame({      # the study's attributed gear lines (peaks.csv rows)
    "mechanism": ["gear", "gear", "gear", "gear", "temporal"],
    "joint": [2, 3, 5, 6, np.nan], "stage": ["motor", "motor", "motor", "motor", ""],
    "order": ["mesh", "mesh", "runout", "mesh", ""],
    "component": ["vertical", "vertical", "lateral", "lateral", "vertical"]})


def run_gears(run, cut):
    return pd.DataFrame({"run": run, "cut": cut, "joint": [2, 3, 4, 5, 6],
                         "stage": "motor", "order": ["mesh", "mesh", "mesh", "runout", "mesh"],
                         # joint 5's runout: 2 cycles over 40 mm, fewer than 2.5; joint 6's
                         # mesh 0.7 bins from joint 2's: one unresolved line, read once
                         "f_spatial_per_mm": [F_STRONG, F_WEAK, F_OTHER, 2.0 / L_MM,
                                              F_STRONG + 0.7 / L_MM]})


def test_the_weak_line_is_below_the_peak_threshold_and_still_an_outcome():
    _, spec, ds = planted_run("px_f1", "plan_01")
    # the study's peak detection (config: threshold 25, local ratio 1.5 over ±25 bins)
    pk = spectrum_peaks(spec, fmin_per_mm=2.5 / L_MM, fmax_per_mm=20.0, threshold=25.0,
                        n_peaks=20, local_ratio=1.5, floor_halfwidth_bins=25.0)
    f = pk["f_spatial_per_mm"].to_numpy()
    assert np.any(np.abs(f - F_STRONG) < 1 / L_MM)               # detected
    assert not np.any(np.abs(f - F_WEAK) < 2 / L_MM)             # not detected
    # the detected peak's amplitude mixes the vertical line: √(1² + 2²), not the wall normal
    strong = pk.iloc[int(np.argmin(np.abs(f - F_STRONG)))]
    assert strong["amplitude_um"] == pytest.approx(np.hypot(STRONG_UM, VERTICAL_UM), rel=0.02)

    profiles = gather_profiles([ds], ["px_f1"])
    elements = waviness_elements(ELEMENTS_PEAKS)
    assert len(elements) == 4
    out = waviness_outcomes(elements, run_gears("px_f1", "plan_01"), profiles)
    # by hand: 1.0 + 0.05 µm (lateral only; the 0.7 µm line of an unused element and joint
    # 5's sub-2.5-cycle runout left out, joint 6's line the same as joint 2's); noise per
    # bin ≈ 0.3·√(6/4000) ≈ 0.012 µm
    assert out["plan_01"] == pytest.approx(STRONG_UM + WEAK_UM, abs=0.03)
    only_weak = waviness_outcomes(elements[elements["joint"] == 3],
                                  run_gears("px_f1", "plan_01"), profiles)
    assert only_weak["plan_01"] == pytest.approx(WEAK_UM, abs=0.025)


def test_check_table_compares_the_spectrum_outcome_with_the_prediction():
    _, _, ds = planted_run("px_f1", "plan_01")
    _, _, ds2 = planted_run("mx_f1", "s2_g1", seed=1)
    profiles = gather_profiles([ds, ds2], ["px_f1", "mx_f1"])
    gears = pd.concat([run_gears("px_f1", "plan_01"), run_gears("mx_f1", "s2_g1")])
    pred = pd.DataFrame({"cut": ["plan_01", "s2_g1", "s9"], "waviness_um": [1.0, 3.0, 1.0],
                         "waviness_low_um": [0.9, 2.5, 0.9],
                         "waviness_high_um": [1.1, 3.5, 1.1]})
    t = check_table(pred, peaks=ELEMENTS_PEAKS,
                    study=RunOutcomes(run_gears=gears, profiles=profiles)
                    ).set_index(["cut", "quantity"])
    a = t.loc[("plan_01", "waviness")]
    assert a["outcome"] == pytest.approx(1.05, abs=0.03)
    assert a["within_interval"] and a["within_tolerance"]
    assert a["source"] == "results/straightness/profiles.nc"
    b = t.loc[("s2_g1", "waviness")]
    assert not b["within_interval"] and not b["within_tolerance"]    # 3.0 vs ~1.05
    assert ("s9", "waviness") not in t.index                         # no tracker run


def test_no_tracker_spectra_no_waviness_outcome():
    pred = pd.DataFrame({"cut": ["c"], "waviness_um": [1.0], "waviness_low_um": [0.9],
                         "waviness_high_um": [1.1]})
    assert check_table(pred, peaks=ELEMENTS_PEAKS).empty
    assert waviness_outcomes(waviness_elements(None), None, None).empty


def test_the_identification_reads_the_same_component_amplitude():
    """A joint's gear amplitude is identified from the peak's component amplitude in the run's
    spectrum (1.0 µm lateral), not from the peak's √(2P) of both components (√5 µm): the
    quantity the prediction carries is the one the outcome measures."""
    rb, q = default_cell_posture([700.0, 0.0, 200.0])
    u = np.array([1.0, 0.0, 0.0])
    sens = abs(np.cross([0, 0, 1.0], u) @ np.asarray(rb.jacobian(q[0]))[:3, 0]) * 1e3  # µm/rad
    _, _, ds = planted_run("px_f1", "c1")
    profiles = gather_profiles([ds], ["px_f1"])
    peaks = pd.DataFrame({"mechanism": ["gear"], "joint": [1], "stage": ["motor"],
                          "order": ["mesh"], "component": ["lateral"], "cut": ["c1"],
                          "run": ["px_f1"], "f_spatial_per_mm": [F_STRONG],
                          "amplitude_um": [np.hypot(STRONG_UM, VERTICAL_UM)]})
    poses = {"c1": (q[0], u)}
    with_spectrum = gear_joint_amplitudes(peaks, rb, poses, profiles=profiles)
    assert with_spectrum.loc[0, "dq_urad"] == pytest.approx(STRONG_UM / sens * 1e6, rel=0.02)
    from_peak = gear_joint_amplitudes(peaks, rb, poses)
    assert from_peak.loc[0, "dq_urad"] == pytest.approx(np.sqrt(5.0) / sens * 1e6, rel=1e-9)


def test_a_point_interval_admits_its_outcome_within_the_tables_rounding():
    """A prediction identified from one run has a point interval, written to 6 significant
    digits: the unrounded outcome it came from is inside; one a unit further is not."""
    pred = pd.DataFrame({"cut": ["a", "b"], "force_N": 0.473841, "force_low_N": 0.473841,
                         "force_high_N": 0.473841})
    mean = pd.DataFrame({"cut": ["a", "b"], "Fx_N": [0.47384114, 0.4738425], "Fy_N": 0.0,
                         "Fz_N": 0.0})
    t = check_table(pred, study=RunOutcomes(mean_forces=mean)).set_index("cut")
    assert t.loc["a", "within_interval"] and not t.loc["b", "within_interval"]


def test_a_line_inside_the_slow_deviations_lobe_is_not_read_as_waviness():
    """A gear line 3.1 periods along the path, next to a 3 µm slow deviation at 2 periods
    (what the cubic detrend leaves of a path's slow error), reads that deviation's Hann lobe,
    not its own 0.1 µm: the line counts only from fmin_cycles + the main lobe's half width
    (waviness_min_cycles), in the outcome as in the prediction (plan_05)."""
    from robomill.plan.check import WAVINESS_MIN_CYCLES, waviness_min_cycles
    from robomill.plan.measured import Measured

    assert waviness_min_cycles(2.5, 2.0) == 4.5 == WAVINESS_MIN_CYCLES
    assert Measured().waviness_min_cycles == WAVINESS_MIN_CYCLES  # prediction = outcome
    rng = np.random.default_rng(3)
    s = DS_MM * np.arange(N)
    lat = (3.0 * np.sin(2 * np.pi * 2.0 / L_MM * s + 0.4)            # the slow deviation
           + 0.1 * np.sin(2 * np.pi * 3.1 / L_MM * s + 0.9)          # the low gear line
           + STRONG_UM * np.sin(2 * np.pi * F_STRONG * s + 0.3)
           + NOISE_UM * rng.standard_normal(N))
    prof = Profile(s_mm=s, deviation_um=np.stack([lat, NOISE_UM * rng.standard_normal(N)]),
                   start_mm=np.zeros(3), end_mm=np.array([L_MM, 0, 0]),
                   direction=np.array([1.0, 0, 0]), ds_mm=DS_MM, speed_mm_s=1.0)
    spec = profile_spectrum(prof, nfft=32768)
    ds = profile_dataset(prof, spec, fmax_store_per_mm=20.0,
                         attrs={"direction": "px", "feed_mm_s": 1.0, "cut": "plan_05",
                                "fmin_per_mm": 2.5 / L_MM, "floor_um2": 0.0})
    profiles = gather_profiles([ds], ["px_f10"])
    gears = pd.DataFrame({"run": "px_f10", "cut": "plan_05", "joint": [2, 3],
                          "stage": ["motor", "reducer_input"], "order": "mesh",
                          "f_spatial_per_mm": [F_STRONG, 3.1 / L_MM]})
    elements = pd.DataFrame({"joint": [2, 3], "stage": ["motor", "reducer_input"],
                             "order": "mesh"})
    # by hand: the strong line alone, 1.0 µm (noise per bin ≈ 0.3·√(6/4000) ≈ 0.012 µm)
    assert waviness_outcomes(elements, gears, profiles)["plan_05"] == pytest.approx(
        STRONG_UM, abs=0.03)
    # read from 2.5 periods, the low line reads the slow deviation's lobe: far above 0.1 µm
    leaky = waviness_outcomes(elements, gears, profiles, min_cycles=2.5)["plan_05"]
    assert leaky - STRONG_UM > 0.5


def test_one_run_gives_an_identification_interval_of_its_noise():
    """One tracker run alone: the joint amplitude's interval is the read ± z σ/√2, σ the
    per-bin noise near the line (white noise of 0.3 µm RMS over N samples, Hann window: the
    amplitude spectrum's per-bin σ = 2·0.3·√(1.5/N)), not a point."""
    rb, q = default_cell_posture([700.0, 0.0, 200.0])
    u = np.array([1.0, 0.0, 0.0])
    sens = abs(np.cross([0, 0, 1.0], u) @ np.asarray(rb.jacobian(q[0]))[:3, 0]) * 1e3
    _, _, ds = planted_run("px_f1", "c1", seed=3)
    profiles = gather_profiles([ds], ["px_f1"])
    peaks = pd.DataFrame({"mechanism": ["gear"], "joint": [1], "stage": ["motor"],
                          "order": ["mesh"], "component": ["lateral"], "cut": ["c1"],
                          "run": ["px_f1"], "f_spatial_per_mm": [F_STRONG],
                          "amplitude_um": [STRONG_UM]})
    g = gear_joint_amplitudes(peaks, rb, {"c1": (q[0], u)}, profiles=profiles, level=0.95)
    half_um = (g.loc[0, "dq_high_urad"] - g.loc[0, "dq_low_urad"]) / 2 * sens * 1e-6
    sigma_um = 2 * NOISE_UM * np.sqrt(1.5 / N)
    assert g.loc[0, "n_runs"] == 1
    assert half_um == pytest.approx(1.96 * sigma_um / np.sqrt(2), rel=0.35)
    assert g.loc[0, "dq_low_urad"] < STRONG_UM / sens * 1e6 < g.loc[0, "dq_high_urad"]
