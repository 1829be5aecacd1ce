"""Issue 28: the stability prediction and the virtual cell's time-domain check agree whatever
the feed direction. Truths written by hand, not by the library: reversing the feed negates
both in-plane components of every mode shape, which leaves φφᵀ (the receptance) unchanged
(a mirror of the part and the modes is no symmetry: the spindle keeps its sense of rotation,
so the mirror image of a cut is the other milling mode, the up/down case below);
the mean directional coefficient along the wall normal of a half-immersion cut,
W̄_yy = N K_t/(2π) ∫ cos φ (sin φ − K_r cos φ) dφ, is N K_t (1/2 − K_r π/4)/(2π) > 0 in
up-milling and −N K_t (1/2 + K_r π/4)/(2π) in down-milling, so Tlusty's limit of a normal mode
a = 1/(2 max Re(W̄_yy G)) is 2kζ(1−ζ)/W̄_yy in up-milling (below the resonance, where
Re G peaks at 1/(4kζ(1−ζ))) and 2kζ(1+ζ)/|W̄_yy| in down-milling (above it, −1/(4kζ(1+ζ))):
up-milling 2.6 times deeper at K_r = 0.3; and the delay-free cut is stable where
the linear system ẋ = (A + a B W̄ C) x, W̄ = N K_t/4 [[−K_r, −1], [1, −K_r]] for a slot, has
no eigenvalue with a positive real part."""

import numpy as np
import pytest

from robomill.chatter.coupling import coupling_depth
from robomill.chatter.modal_timedomain import ModalCut, simulate_modal_cut, stability_verdict
from robomill.chatter.model import CuttingModel
from robomill.plan.lobes import batch_zoa_lobes
from robomill.plan.poses import cut_frames

TEETH = 2


def verdict(f_hz, zeta, k_N_m, shape_xy, rpm, entry, exit_, c_m, depth_m, Kt, Kr, *,
            duration_s=0.6, steps=256, band_hz=(100.0, 5000.0)):
    """The time-domain verdict (a regenerative and a delay-free run)."""
    runs = [simulate_modal_cut(
        ModalCut(np.asarray(f_hz, float), np.asarray(zeta, float), np.asarray(k_N_m, float),
                 np.asarray(shape_xy, float), rpm, TEETH, entry, exit_, c_m, depth_m, Kt,
                 Kr * Kt, 0.0, overlap=mu, linear_chip=mu == 0.0),
        duration_s=duration_s, steps_per_tooth=steps, Kt_noise_fraction=0.005, noise_seed=1)
        for mu in (1.0, 0.0)]
    return stability_verdict(*runs, TEETH * rpm / 60.0, band_hz=band_hz,
                             harmonic_halfwidth_hz=10.0, growth_ratio=3.0)


def critical_depth_m(f_hz, zeta, k_N_m, shape_xy, rpm, entry, exit_, Kt, Kr):
    """The planner's critical depth: the regenerative lobes of the modes (zero-order,
    robomill.plan.stability)."""
    cut = CuttingModel(TEETH, Kt, Kr, entry, exit_)
    args = ([f_hz], zeta, [k_N_m], [shape_xy], cut)
    return batch_zoa_lobes(*args, np.array([rpm]))[0, 0]


def delay_free_depth_m(f_hz, zeta, k_N_m, shape_xy, entry, exit_, Kt, Kr):
    """The delay-free mode-coupling depth, chapter 4's diagnostic (the one routine,
    robomill.chatter.coupling.coupling_depth)."""
    cut = CuttingModel(TEETH, Kt, Kr, entry, exit_)
    return coupling_depth([f_hz], zeta, [k_N_m], [shape_xy], cut, depth_max_m=1.0)[0]


# two modes in the base frame, neither along a cut axis (planted)
BASE_SHAPES = np.array([[0.3, 1.0, 0.2], [1.0, 0.4, 0.1]])
BASE_SHAPES = BASE_SHAPES / np.linalg.norm(BASE_SHAPES, axis=1)[:, None]
F2, Z2, K2 = np.array([1800.0, 2300.0]), np.array([0.03, 0.03]), np.array([2.0e7, 3.0e7])


def test_reversing_the_feed_gives_the_same_stability_in_prediction_and_simulation():
    frames_plan = cut_frames(np.array([90.0, 270.0]))                     # the planner's
    py, my = (BASE_SHAPES @ R[:, :2] for R in frames_plan)
    np.testing.assert_allclose(my, -py, atol=1e-12)                # both components negated
    np.testing.assert_allclose(np.einsum("mi,mj->mij", my, my),
                               np.einsum("mi,mj->mij", py, py), atol=1e-12)
    py, my = (BASE_SHAPES @ R[:, :2] for R in frames_plan)
    Kt, Kr, rpm = 6.0e8, 0.3, 6000.0
    a = [critical_depth_m(F2, Z2, K2, s, rpm, 0.0, np.pi, Kt, Kr) for s in (py, my)]
    assert np.isfinite(a[0]) and a[1] == pytest.approx(a[0], rel=1e-12)
    for depth in (0.5 * a[0], 2.5 * a[0]):
        v = [verdict(F2, Z2, K2, s, rpm, 0.0, np.pi, 5e-5, depth, Kt, Kr) for s in (py, my)]
        assert v[0].stable == v[1].stable == (depth < a[0])
        assert v[1].growth_regenerative == pytest.approx(v[0].growth_regenerative, rel=1e-9)
        assert v[1].growth_coupling == pytest.approx(v[0].growth_coupling, rel=1e-9)


# one mode along the wall normal, half immersion (planted)
F1, Z1, K1 = 2000.0, 0.03, 2.0e7
KT1, KR1, HALF = 6.0e8, 0.3, np.pi / 2
WYY_DOWN = -TEETH * KT1 * (0.5 + KR1 * np.pi / 4) / (2 * np.pi)
WYY_UP = TEETH * KT1 * (0.5 - KR1 * np.pi / 4) / (2 * np.pi)
A_DOWN_M = 2 * K1 * Z1 * (1 + Z1) / abs(WYY_DOWN)     # Tlusty's absolute limits
A_UP_M = 2 * K1 * Z1 * (1 - Z1) / WYY_UP


def test_up_and_down_milling_differ_as_by_hand():
    up, down = CuttingModel(TEETH, KT1, KR1, 0.0, HALF), CuttingModel(TEETH, KT1, KR1, HALF,
                                                                       np.pi)
    assert up.mean_matrix()[1, 1] == pytest.approx(WYY_UP, rel=1e-12)
    assert down.mean_matrix()[1, 1] == pytest.approx(WYY_DOWN, rel=1e-12)
    assert A_UP_M / A_DOWN_M == pytest.approx(2.62, abs=0.01)
    rpm = np.linspace(5000.0, 8000.0, 301)
    args = ([[F1]], [Z1], [[K1]], [[[0.0, 1.0]]])
    a_down = batch_zoa_lobes(*args, down, rpm)[0]
    a_up = batch_zoa_lobes(*args, up, rpm)[0]
    assert a_down.min() == pytest.approx(A_DOWN_M, rel=0.02)      # the envelopes' floors
    assert a_up.min() == pytest.approx(A_UP_M, rel=0.02)
    assert np.all(a_up > A_UP_M * 0.99)
    # the time domain agrees at the speed of the down-milling floor: half of it stable in
    # both, 1.8 times it chatter in down-milling only (below the up-milling floor)
    n = float(rpm[np.argmin(a_down)])
    for depth, down_stable in ((0.5 * A_DOWN_M, True), (1.8 * A_DOWN_M, False)):
        assert (critical_depth_m([F1], [Z1], [K1], [[0.0, 1.0]], n, HALF, np.pi, KT1, KR1)
                > depth) == down_stable
        assert critical_depth_m([F1], [Z1], [K1], [[0.0, 1.0]], n, 0.0, HALF, KT1, KR1) > depth
        assert verdict([F1], [Z1], [K1], [[0.0, 1.0]], n, HALF, np.pi, 5e-5, depth, KT1,
                       KR1).stable == down_stable
        assert verdict([F1], [Z1], [K1], [[0.0, 1.0]], n, 0.0, HALF, 5e-5, depth, KT1,
                       KR1).stable


# the virtual cell's modes at the pose of the default study's s1_g1_my (cut frame, rounded):
# robot modes far below the tooth frequency, a feed per tooth of 1.07 um
F6 = np.array([24.36, 36.18, 72.86, 70.65, 84.65, 87.54])
Z6 = np.array([0.04, 0.035, 0.03, 0.025, 0.025, 0.03])
K6 = np.array([1.187e6, 1.283e6, 2.212e6, 1.223e6, 1.462e6, 2.956e6])
S6 = np.array([[-0.941, 0.282], [-0.188, 0.941], [-0.365, 0.183], [-0.445, 0.891],
               [-0.913, 0.365], [-0.286, 0.095]])
KT6, KR6, RPM6, C6 = 796e6, 168.0 / 796.0, 28000.0, 1e-3 / (2 * 28000.0 / 60.0)


def delay_free_rate(depth_m):
    """Largest real part [1/s] of the linear delay-free system, built here by hand."""
    w = 2 * np.pi * F6
    n = 2 * len(F6)
    A, B, C = np.zeros((n, n)), np.zeros((n, 2)), np.zeros((2, n))
    for r in range(len(F6)):
        A[2 * r, 2 * r + 1] = 1.0
        A[2 * r + 1, 2 * r] = -w[r] ** 2
        A[2 * r + 1, 2 * r + 1] = -2 * Z6[r] * w[r]
        B[2 * r + 1] = S6[r] * w[r] ** 2 / K6[r]
        C[:, 2 * r] = S6[r]
    W = TEETH * KT6 / 4 * np.array([[-KR6, -1.0], [1.0, -KR6]])
    return float(np.linalg.eigvals(A + depth_m * B @ W @ C).real.max())


@pytest.mark.parametrize("depth_m", [0.25e-3, 1.0e-3])
def test_delay_free_check_follows_its_linear_model_at_a_micrometre_feed(depth_m):
    """s1_g1_my of the default study: stable by a wide margin in the linear delay-free model at
    0.25 mm, called chatter when the seed's h >= 0 clipping drove the delay-free run's teeth
    out of the cut; unstable at 1 mm, and the check must say so."""
    stable = delay_free_rate(depth_m) < 0
    assert stable == (depth_m == 0.25e-3)
    assert (delay_free_depth_m(F6, Z6, K6, S6, 0.0, np.pi, KT6, KR6) > depth_m) == stable
    # the regenerative limit of the same modes lies far deeper (the chip's overlap factor 1)
    assert critical_depth_m(F6, Z6, K6, S6, RPM6, 0.0, np.pi, KT6, KR6) > 4 * depth_m
    v = verdict(F6, Z6, K6, S6, RPM6, 0.0, np.pi, C6, depth_m, KT6, KR6, duration_s=3.0,
                steps=32, band_hz=(5.0, 500.0))
    assert v.stable == stable
    assert v.out_of_cut_fraction <= 0.05                 # the regenerative run stays in the cut


def _record(rng, rms, out_share, n=3000):
    """A run's record with a stationary vibration of ``rms`` and ``out_share`` of the deep
    teeth out of the cut."""
    deep = np.ones(n)
    return {"delta_m": rms * rng.standard_normal((n, 2)), "force_N": rng.standard_normal((n, 3)),
            "teeth_deep": deep, "teeth_out": (rng.random(n) < out_share) * deep,
            "fs_hz": 3000.0}


def test_the_verdict_counts_the_teeth_of_the_regenerative_run_only():
    """Which run grew a little more must not decide (s1_g1_py and s1_g1_my: growth 0.990
    against 0.988, and 0.969 against 0.983)."""
    rng = np.random.default_rng(0)
    kw = {"band_hz": (5.0, 500.0), "harmonic_halfwidth_hz": 5.0, "growth_ratio": 3.0}
    steady, teeth_out = _record(rng, 1e-7, 0.0), _record(rng, 1e-6, 0.2)
    for regen, coupling in ((steady, teeth_out), (teeth_out, steady)):
        v = stability_verdict(regen, coupling, 933.0, **kw)
        assert max(v.growth_regenerative, v.growth_coupling) < 1.2
        assert v.stable == (regen is steady)
        assert v.out_of_cut_fraction == pytest.approx(0.0 if regen is steady else 0.2, abs=0.03)
