"""Shagniev 2019 time-domain model: detection, agreement with the lobes, adaptive depth; schema."""

import copy

import numpy as np
import pytest
import yaml

from robomill.chatter.detection import (
    SlidingDetector,
    chatter_indicator,
    growth_rate_1_s,
    run_adaptive,
)
from robomill.chatter.lobes_sdm import critical_depth, sdm_spectral_radius
from robomill.chatter.seed import classify_run
from robomill.chatter.timedomain import SeedParams, SeedSimulation, horizontal_tool

DET = {"window_s": 0.5, "band_hz": [20.0, 1000.0], "harmonic_halfwidth_hz": 10.0,
       "growth_ratio": 3.0, "rising_windows": 3, "min_fraction_of_mean": 0.05}


@pytest.fixture(scope="module")
def boundary_1260():
    p = SeedParams()
    a, _ = critical_depth(horizontal_tool(p), p.cutting_model(), p.spindle_rpm,
                          depth_max_m=2e-3, m=60, rtol=1e-3)
    return p, a


def test_horizontal_model_is_stable_with_the_suspension_mode():
    tool = horizontal_tool(SeedParams())
    assert tool.is_stable()
    fn = tool.natural_frequencies_hz()
    assert np.any(np.abs(fn - 173.0) < 10.0)  # 167 Hz suspension mode, stiffened by the arm


def test_indicator_finds_planted_line_between_harmonics():
    fs, tooth = 4000.0, 84.0
    t = np.arange(0, 1.0, 1 / fs)
    x = 12 + sum(5 / k * np.sin(2 * np.pi * k * tooth * t) for k in range(1, 6))
    x = x + 0.8 * np.sin(2 * np.pi * 205.0 * t)
    amp, f = chatter_indicator(x, fs, tooth, (20.0, 1000.0), 10.0)
    assert f == pytest.approx(205.0, abs=1.0)
    assert amp == pytest.approx(0.8, rel=0.1)


def test_growth_rate_of_a_planted_exponential():
    t = np.linspace(0.0, 3.0, 121)
    chatter = np.minimum(0.01 * np.exp(2.7 * t), 5.0)  # e^{2.7 t} until "saturation"
    amp = np.hypot(0.05, chatter)  # over an uncorrelated floor of 0.05
    assert growth_rate_1_s(t, amp) == pytest.approx(2.7, rel=0.01)
    assert np.isnan(growth_rate_1_s(t, np.full_like(t, 0.3)))


def test_stable_noise_free_cut_becomes_exactly_periodic(boundary_1260):
    """Below the boundary, with no K_t scatter, the regenerative Δ = x(t) − x(t − τ) must decay
    to rounding level: no tooth may switch in or out at different sub-steps from one pass to the
    next (the quarter-step spindle-angle offset)."""
    p, a_b = boundary_1260
    sim = SeedSimulation(p, 0.97 * a_b, steps_per_tooth=128, duration_s=4.0)
    sim.run(4.0)
    hx = sim.hist_x[sim.m: sim.m + sim.k]
    delta = hx[sim.m:] - hx[:-sim.m]
    assert np.abs(delta[: sim.m * 10]).max() > 1e-6  # the entry transient is there ...
    assert np.abs(delta[-sim.m * 10:]).max() < 1e-10  # ... and gone


@pytest.mark.parametrize("rpm", [1260.0, 2000.0])
def test_simulated_growth_matches_sdm_floquet_exponent(rpm):
    """10 % above the boundary, chatter grows at the rate the SDM monodromy matrix predicts,
    σ = ln ρ/τ (near the boundary the growth is slow and the K_t scatter blurs it)."""
    p = SeedParams(spindle_rpm=rpm, Kt_noise_fraction=0.005, noise_seed=1)
    tool, cut = horizontal_tool(p), p.cutting_model()
    a_b, _ = critical_depth(tool, cut, rpm, depth_max_m=2e-3, m=60, rtol=1e-3)
    unstable, _, sigma_sim = classify_run(p, 1.1 * a_b, duration_s=2.0, steps_per_tooth=128,
                                          det=DET)
    rho, _ = sdm_spectral_radius(tool, cut, rpm, np.array([1.1 * a_b]), m=60)
    sigma_sdm = np.log(rho[0]) / p.tooth_period_s
    assert unstable and sigma_sdm > 5
    assert sigma_sim == pytest.approx(sigma_sdm, rel=0.15)


def test_unknown_seed_parameter_is_refused():
    from robomill.io import ConfigError

    with pytest.raises(ConfigError, match="Kt_nosie_fraction"):
        SeedParams.from_config({"Kt_nosie_fraction": 0.01})


def test_time_domain_agrees_with_lobes(boundary_1260):
    p, a_b = boundary_1260
    assert 0.05e-3 < a_b < 0.5e-3
    below, amp_b, _ = classify_run(p, 0.85 * a_b, duration_s=2.0, steps_per_tooth=128, det=DET)
    above, amp_a, _ = classify_run(p, 1.15 * a_b, duration_s=2.0, steps_per_tooth=128, det=DET)
    assert not below and above
    assert amp_a > 5 * amp_b


def test_unstable_point_is_detected_and_depth_lowered_by_at_most_two_percent(boundary_1260):
    p, a_b = boundary_1260
    p = SeedParams(**{**p.as_dict(), "Kt_noise_fraction": 0.005, "noise_seed": 1})
    sim = SeedSimulation(p, 1.03 * a_b, steps_per_tooth=128, duration_s=4.0)
    det = SlidingDetector(sim.record_fs_hz, p.teeth * p.spindle_rpm / 60, window_s=0.5)
    out = run_adaptive(sim, det, duration_s=4.0, hop_s=0.1, step_fraction=0.01,
                       max_total_fraction=0.02, hold_s=0.5)
    assert out["detections"], "chatter at 3 % above the boundary must be detected"
    assert 0 < out["lowered_fraction"] <= 0.02 + 1e-12
    rec = sim.record()
    assert rec["depth_m"][-1] == pytest.approx(1.03 * a_b * (1 - out["lowered_fraction"]),
                                               rel=2e-3)
    # spectral peak of the chatter near the predicted (~200 Hz) frequency
    f = out["indicator"][:, 2]
    assert np.any((f > 150) & (f < 260))


def test_adaptive_run_settles_after_the_depth_cut(boundary_1260):
    """Shagniev 2019: 1 % above the boundary chatter is detected, the logic block lowers the depth
    by at most 2 %, and the chatter line then dies away while the uncontrolled cut keeps
    chattering (indicator means over the last 1.5 s)."""
    p, a_b = boundary_1260
    p = SeedParams(**{**p.as_dict(), "Kt_noise_fraction": 0.005, "noise_seed": 1})
    final = {}
    for adapt in (False, True):
        sim = SeedSimulation(p, 1.01 * a_b, steps_per_tooth=128, duration_s=6.0)
        det = SlidingDetector(sim.record_fs_hz, p.teeth * p.spindle_rpm / 60, window_s=1.0,
                              harmonic_halfwidth_hz=10.0)
        out = run_adaptive(sim, det, duration_s=6.0, hop_s=0.1, step_fraction=0.01,
                           max_total_fraction=0.02, hold_s=0.5, adapt=adapt)
        assert 1.0 < out["detections"][0] < 3.0  # seed: about 2 s
        t, amp = out["indicator"][:, 0], out["indicator"][:, 1]
        final[adapt] = amp[t > 4.5].mean()
    assert out["lowered_fraction"] <= 0.02 + 1e-12
    assert final[True] < 0.25 * final[False]


def test_stable_point_is_not_detected(boundary_1260):
    p, a_b = boundary_1260
    p = SeedParams(**{**p.as_dict(), "Kt_noise_fraction": 0.005, "noise_seed": 1})
    sim = SeedSimulation(p, 0.9 * a_b, steps_per_tooth=128, duration_s=3.0)
    det = SlidingDetector(sim.record_fs_hz, p.teeth * p.spindle_rpm / 60, window_s=0.5)
    out = run_adaptive(sim, det, duration_s=3.0, hop_s=0.1, step_fraction=0.01,
                       max_total_fraction=0.02, hold_s=0.5)
    assert out["detections"] == []


def test_bad_case_fails_with_key_named(repo):
    from robomill.io import ConfigError
    from robomill.pipeline.config import validate_config

    raw = yaml.safe_load(open(repo / "config.yaml"))
    for key, bad in (("milling", "sideways"), ("radial_immersion", 1.5), ("teeth", 0)):
        cfg = copy.deepcopy(raw)
        cfg["chatter"]["cases"][0][key] = bad
        with pytest.raises(ConfigError, match=rf"chatter\.cases\[0\]\.{key}"):
            validate_config(cfg, repo / "src/robomill/data/schemas/config.schema.yaml")
    cfg = copy.deepcopy(raw)
    del cfg["chatter"]["cases"][0]["Kt_N_m2"]
    with pytest.raises(ConfigError, match="Kt_N_m2"):
        validate_config(cfg, repo / "src/robomill/data/schemas/config.schema.yaml")
