"""The tracker's noise in the waviness interval (robomill.plan.noise) against truths written
by hand: white noise of known standard deviation s per sample gives a per-bin noise amplitude
σ = s √(6/N) in the Hann-windowed, coherent-gain corrected spectrum of N samples; the floor
estimated from a band beside a line recovers it, scales as 1/√(record duration) through the
tracker's resampling, and the interval built from it covers the read amplitude of planted
lines in at least the nominal fraction of seeded Monte-Carlo draws."""

import numpy as np
import pandas as pd
import pytest
from conftest import default_cell_posture

from robomill.plan.measured import spectrum_amplitude_um, waviness_um
from robomill.plan.noise import (
    READ_POINTS,
    noise_floor_um,
    read_interval_um,
    rice_quantile_um,
    run_duration_s,
)
from robomill.straightness import profile_spectrum
from robomill.straightness.profile import Profile, profile_dataset, spatial_profile
from robomill.straightness.study import gather_profiles

DS_MM, N = 0.01, 4000                      # a 40 mm path on the study's grid
L_MM = DS_MM * N
NOISE_UM = 0.3                             # white noise per sample, standard deviation
SIGMA_UM = NOISE_UM * np.sqrt(6.0 / N)     # by hand: 4 s² Σw²/(Σw)² = 6 s²/N -> 0.01162 µm
LINES = {"strong": (0.1, 0.5123), "weak": (0.01, 1.3071), "absent": (0.0, 2.2049)}
OTHER_UM, F_OTHER = 0.5, 0.5123 + 6.0 / L_MM   # a detected peak inside the strong line's band
COVERAGE = 0.95


def _dataset(prof, run, speed_mm_s):
    spec = profile_spectrum(prof)
    attrs = {"direction": "px", "feed_mm_s": speed_mm_s, "cut": run,
             "fmin_per_mm": 2.5 / prof.length_mm, "floor_um2": 0.0}
    return profile_dataset(prof, spec, fmax_store_per_mm=10.0, attrs=attrs)


def planted_profiles(n_draws, seed=0):
    """``n_draws`` runs along the same 40 mm path at 1 mm/s: the three lateral lines (random
    phases), the other peak and white noise NOISE_UM per sample in both components."""
    rng = np.random.default_rng(seed)
    s = DS_MM * np.arange(N)
    runs, ids = [], []
    for k in range(n_draws):
        lat = NOISE_UM * rng.standard_normal(N)
        for a, f in [*LINES.values(), (OTHER_UM, F_OTHER)]:
            lat += a * np.sin(2 * np.pi * f * s + rng.uniform(0, 2 * np.pi))
        vert = NOISE_UM * rng.standard_normal(N)
        prof = Profile(s_mm=s, deviation_um=np.stack([lat, vert]), start_mm=np.zeros(3),
                       end_mm=np.array([L_MM, 0, 0]), direction=np.array([1.0, 0, 0]),
                       ds_mm=DS_MM, speed_mm_s=1.0)
        runs.append(_dataset(prof, f"r{k}", 1.0))
        ids.append(f"r{k}")
    return gather_profiles(runs, ids)


@pytest.fixture(scope="module")
def draws():
    return planted_profiles(300)


def test_the_floor_beside_a_line_is_the_hand_computed_noise(draws):
    est = np.array([[noise_floor_um(draws, f"r{k}", f, exclude_per_mm=[F_OTHER])
                     for _, f in LINES.values()] for k in range(draws.sizes["run"])])
    # the median over ±20 resolution bins of Rayleigh amplitudes (neighbouring bins correlated
    # by the Hann window): unbiased to a few % (measured +1.7 % over these 900 estimates), one
    # estimate scattered by ~14 % (measured), so within ±50 % (3.5 of its deviations)
    assert np.median(est) == pytest.approx(SIGMA_UM, rel=0.04)
    assert np.mean(est) == pytest.approx(SIGMA_UM, rel=0.04)
    assert np.all(np.abs(est / SIGMA_UM - 1) < 0.5)
    # the other peak (0.5 µm, 43 σ) left in the band would not move a median much, but its
    # main lobe is excluded: leaving it in gives a larger floor
    kept = noise_floor_um(draws, "r0", LINES["strong"][1])
    assert kept >= noise_floor_um(draws, "r0", LINES["strong"][1], exclude_per_mm=[F_OTHER])


def test_the_floor_falls_as_one_over_root_duration_through_the_resampling():
    """A tracker at 1 kHz, s = 5 µm across the path, along the same 40 mm at 1 and 4 mm/s:
    40 000 samples (ten per grid cell) and 10 000 (2.5 per cell), averaged per cell by the
    resampling; σ = s √(6/(f_s T)) either way, so σ √T = s √(6/f_s) = 0.387 µm √s. (Noise
    along the path too makes the cells' sample counts vary, and the unweighted cell means
    then lose some of the samples' information: +12 % at 4 mm/s here, measured; the
    identifying runs' floors carry it, the scaling to another feed does not.)"""
    rng = np.random.default_rng(7)
    fs, s_um = 1000.0, 5.0
    rho_hand = s_um * np.sqrt(6.0 / fs)
    rho = []
    for v in (1.0, 4.0):
        t = np.arange(0.0, L_MM / v, 1.0 / fs)
        x = v * t
        est = []
        for _ in range(4):                      # 4 records × 8 separate ±20-bin bands
            pts = np.stack([x, np.zeros_like(x), np.zeros_like(x)], 1)
            pts[:, 1:] += 1e-3 * s_um * rng.standard_normal((len(x), 2))
            ds = gather_profiles([_dataset(spatial_profile(t, pts, ds_mm=DS_MM), "r", v)],
                                 ["r"])
            est += [noise_floor_um(ds, "r", f) for f in np.arange(1.0, 9.0)]
        # 32 estimates of ~14 % scatter each: their mean within ±10 % (4 of its deviations)
        assert np.mean(est) == pytest.approx(s_um * np.sqrt(6.0 / (fs * L_MM / v)), rel=0.1)
        rho.append(np.mean(est) * np.sqrt(run_duration_s(ds, "r")))
    assert rho == pytest.approx([rho_hand, rho_hand], rel=0.1)


def test_rice_quantiles_by_hand():
    sig = 0.2
    # no line: Rayleigh, P(|N| > x) = exp(-x²/σ²)
    assert rice_quantile_um(0.5, 0.0, sig) == pytest.approx(sig * np.sqrt(np.log(2)), rel=1e-6)
    assert rice_quantile_um(0.01, 0.0, sig) == pytest.approx(
        sig * np.sqrt(-np.log(0.99)), rel=1e-6)
    # a strong line: Gaussian about ν with σ/√2 (the quadrature in phase with it)
    assert rice_quantile_um(0.025, 50 * sig, sig) == pytest.approx(
        50 * sig - 1.959964 * sig / np.sqrt(2), rel=2e-3)
    # no noise level: the identification end itself
    lo, hi = read_interval_um(0.3, 0.4, np.nan, 0.01)
    assert (lo, hi) == (0.3, 0.4)
    lo, hi = read_interval_um(0.3, 0.4, sig, 0.01)
    assert lo < 0.3 and hi == pytest.approx(0.4 + sig * np.sqrt(np.log(READ_POINTS / 0.01)))


def test_the_interval_covers_the_read_in_the_nominal_fraction(draws):
    """The outcome's read (largest amplitude within ±0.5 bins, summed over the three lines)
    against the interval of the exact amplitudes widened by the noise: with the hand σ and
    with the floor estimated on another run (the identifying one)."""
    n = draws.sizes["run"]
    reads = np.array([[spectrum_amplitude_um(draws, f"r{k}", "lateral", f)
                       for _, f in LINES.values()] for k in range(n)])
    total = reads.sum(1)
    beta = (1 - COVERAGE) / (2 * len(LINES))
    a = np.array([v[0] for v in LINES.values()])
    for sigma in (SIGMA_UM, noise_floor_um(draws, "r0", 2.2049 + 9 / L_MM)):
        lo, hi = read_interval_um(a, a, sigma, beta)
        inside = (total >= lo.sum()) & (total <= hi.sum())
        assert inside.mean() >= COVERAGE
        # each line alone within its own ends in ≥ 1 − 2β of the draws
        per_line = (reads >= lo) & (reads <= hi)
        assert np.all(per_line.mean(0) >= 1 - 2 * beta - 3 * np.sqrt(2 * beta / n))
    # the noise bias: the absent line reads more than a single bin's median σ √(ln 2) (the
    # largest over the ±0.5-bin window), less than the union bound's median σ √(ln 2K)
    med = np.median(reads[:, 2])
    assert SIGMA_UM * np.sqrt(np.log(2)) < med < SIGMA_UM * np.sqrt(np.log(2 * READ_POINTS))
    assert np.median(reads[:, 1]) > a[1]                # the weak line (0.86 σ) too
    # the identification interval alone (no noise) misses most draws
    assert ((total >= a.sum()) & (total <= a.sum())).mean() < 0.05


def test_waviness_read_interval_scales_with_the_feed():
    """The prediction at a pose: nominal and identification ends unchanged by the feeds;
    the noise per bin ρ √(v/L) exactly, and the read interval contains the identification
    interval and widens with the feed."""
    rb, q = default_cell_posture([700.0, 0.0, 200.0])
    gears = pd.DataFrame({"joint": [2, 3], "stage": ["motor", "motor"], "order": ["mesh"] * 2,
                          "dq_urad": [10.0, 8.0], "dq_low_urad": [9.0, 7.0],
                          "dq_high_urad": [11.0, 9.0], "n_runs": [3, 3],
                          "noise_um_sqrt_s": [0.4, 0.5]})
    n = np.array([0.0, 1.0, 0.0])
    feeds = np.array([1.0, 4.0, 16.0])
    plain = waviness_um(rb, q[0], n, gears)
    w = waviness_um(rb, q[0], n, gears, length_mm=40.0, feed_mm_s=feeds, coverage=0.9)
    for k in ("nominal", "low", "high"):
        assert w[k] == plain[k]
    assert w["noise"] == pytest.approx(0.5 * np.sqrt(feeds / 40.0), rel=1e-12)
    assert np.all(w["read_low"] <= plain["low"]) and np.all(w["read_high"] >= plain["high"])
    assert np.all(np.diff(w["read_high"]) > 0) and np.all(np.diff(w["read_low"]) <= 0)
    # the high end by hand: Σ a_high + σ_e √(ln(K/β)), β = 0.1/(2·2)
    J = np.asarray(rb.jacobian(q[0]))[:3] * 1e3                  # µm/rad
    a_hi = np.array([11.0, 9.0]) * 1e-6 * np.abs(n @ J[:, [1, 2]])
    sig = np.array([0.4, 0.5])[:, None] * np.sqrt(feeds / 40.0)
    hand = a_hi.sum() + (sig * np.sqrt(np.log(READ_POINTS / 0.025))).sum(0)
    assert w["read_high"] == pytest.approx(hand, rel=1e-9)


def test_the_chapter_states_the_waviness_check_from_the_summary():
    """Chapter 7's waviness sentence follows check_summary.csv's numbers (templates/ch7.yaml)."""
    from robomill.pipeline.prose import Prose, load_templates

    s = {"n_waviness": 24.0, "n_waviness_in_interval": 21.0, "n_waviness_in_tolerance": 13.0,
         "tolerance_percent": 25.0}
    text = Prose(load_templates("ch7"), s)("check_waviness")
    assert "21 of 24 cuts" in text and "25 % of the outcome for 13" in text
    other = Prose(load_templates("ch7"), {**s, "n_waviness_in_interval": 5.0,
                                          "tolerance_percent": 10.0})("check_waviness")
    assert "5 of 24 cuts" in other and "10 % of the outcome" in other
    assert Prose(load_templates("ch7"), {})("check_waviness").startswith(
        "No cut has a waviness outcome")
