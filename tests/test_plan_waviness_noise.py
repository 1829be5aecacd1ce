"""The tracker's noise in the waviness interval (robomill.plan.noise) against truths written
by hand: white noise of known standard deviation s per sample gives a per-bin noise amplitude
σ = s √(6/N) in the Hann-windowed, coherent-gain corrected spectrum of N samples; the floor
estimated from a band beside a line recovers it, scales as 1/√(record duration) through the
tracker's resampling, and the interval built from it covers the read amplitude of planted
lines in the nominal fraction of seeded Monte-Carlo draws (the distribution's own range,
sharper than the bounds, which held every draw)."""

import numpy as np
import pandas as pd
import pytest
from conftest import default_cell_posture

from robomill.plan.measured import spectrum_amplitude_um, waviness_um
from robomill.plan.noise import (
    READ_POINTS,
    hann_response,
    noise_floor_um,
    read_interval_um,
    read_sum_interval_um,
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


def test_the_read_sum_interval_is_calibrated_and_sharper_than_the_bounds(draws):
    """The Monte Carlo interval of the sum of the reads (the lines' exact amplitudes, the hand
    σ and the one estimated on another run) against the same 300 planted draws read by the
    outcome's own code: the count inside lies in the central 99 % binomial range of the
    nominal 0.95 (275–294 of 300: mean 285, sd 3.8), and the interval is narrower than the bounds
    (Rice/union/Bonferroni), which hold every draw."""
    from scipy.stats import binom

    n = draws.sizes["run"]
    total = np.array([sum(spectrum_amplitude_um(draws, f"r{k}", "lateral", f)
                          for _, f in LINES.values()) for k in range(n)])
    a = np.array([v[0] for v in LINES.values()])
    k_lo, k_hi = binom.ppf([0.005, 0.995], n, COVERAGE)
    assert (k_lo, k_hi) == (275, 294)
    beta = (1 - COVERAGE) / (2 * len(LINES))
    for sigma in (SIGMA_UM, noise_floor_um(draws, "r0", 2.2049 + 9 / L_MM)):
        lo, hi = read_sum_interval_um(a, a, a, np.full(3, sigma), coverage=COVERAGE,
                                      level=COVERAGE)
        inside = int(((total >= lo) & (total <= hi)).sum())
        assert k_lo <= inside <= k_hi
        b_lo, b_hi = read_interval_um(a, a, sigma, beta)
        assert ((total >= b_lo.sum()) & (total <= b_hi.sum())).all()
        assert hi - lo < 0.8 * (b_hi.sum() - b_lo.sum())


def test_the_read_sum_interval_by_hand_limits():
    """Without noise the sum of split normals: one line of 1 µm with the interval 0.8-1.4 at
    the 95 % level is its own interval; with a strong line (ν = 50 σ) and an exact amplitude
    the read is Gaussian about ν with σ/√2 (in phase), its largest over the window adding a
    little: the range lies within [ν ± 1.96 σ/√2] widened by 10 %; the Hann window's response
    by hand: 1 at the line, 0.5 one bin off, 0 two bins off."""
    lo, hi = read_sum_interval_um([1.0], [0.8], [1.4], [np.nan], coverage=0.95, level=0.95)
    assert (lo, hi) == (pytest.approx(0.8, abs=0.01), pytest.approx(1.4, abs=0.02))
    sig = 0.02
    lo, hi = read_sum_interval_um([1.0], [1.0], [1.0], [sig], coverage=0.95, level=0.95)
    half = 1.959964 * sig / np.sqrt(2)
    assert 1.0 - 1.1 * half < lo < 1.0 and 1.0 < hi < 1.0 + 1.1 * half + 0.1 * sig
    assert np.abs(hann_response([0.0, 1.0, 2.0])) == pytest.approx([1.0, 0.5, 0.0], abs=1e-9)


def test_waviness_read_interval_scales_with_the_feed():
    """The prediction at a pose: nominal and identification ends unchanged by the feeds;
    the noise per bin ρ √(v/L) exactly, and the read interval is the Monte Carlo range of the
    two lines' reads by hand (their amplitudes through the Jacobian), widening with the feed."""
    rb, q = default_cell_posture([700.0, 0.0, 200.0])
    gears = pd.DataFrame({"joint": [2, 3], "stage": ["motor", "motor"], "order": ["mesh"] * 2,
                          "dq_urad": [10.0, 8.0], "dq_low_urad": [9.0, 7.0],
                          "dq_high_urad": [11.0, 9.0], "n_runs": [3, 3],
                          "noise_um_sqrt_s": [0.4, 0.5]})
    n = np.array([0.0, 1.0, 0.0])
    feeds = np.array([1.0, 4.0, 16.0])
    plain = waviness_um(rb, q[0], n, gears)
    w = waviness_um(rb, q[0], n, gears, length_mm=40.0, feed_mm_s=feeds, coverage=0.9,
                    level=0.95)
    for k in ("nominal", "low", "high"):
        assert w[k] == plain[k]
    assert w["noise"] == pytest.approx(0.5 * np.sqrt(feeds / 40.0), rel=1e-12)
    # wider with the feed (these lines are near the noise: the read's low end rises too)
    assert np.all(np.diff(w["read_high"]) > 0)
    assert np.all(np.diff(w["read_high"] - w["read_low"]) > 0)
    J = np.asarray(rb.jacobian(q[0]))[:3] * 1e3                  # µm/rad
    s = np.abs(n @ J[:, [1, 2]])
    sig = np.array([0.4, 0.5])[None, :] * np.sqrt(feeds / 40.0)[:, None]
    hand = read_sum_interval_um(np.array([10.0, 8.0]) * 1e-6 * s,
                                np.array([9.0, 7.0]) * 1e-6 * s,
                                np.array([11.0, 9.0]) * 1e-6 * s, sig, coverage=0.9, level=0.95)
    assert w["read_low"] == pytest.approx(hand[0], rel=1e-9)
    assert w["read_high"] == pytest.approx(hand[1], rel=1e-9)


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
