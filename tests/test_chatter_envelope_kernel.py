"""The compiled lower envelope of the zero-order lobes' branches
(robomill.chatter.envelope_kernel), against the envelope written independently: each branch
n_k(f) = 60 f / (N (ε(f) + 2πk)) monotone in f (ε falling), so its depth at a speed is
numpy's linear interpolation of a(f) over n_k(f), and the envelope the minimum over every
branch."""

import numpy as np
import pytest

from robomill.chatter.envelope_kernel import lower_envelope

TEETH = 2


def _branches(seed):
    """Depths and phases of 2 tool models × 2 eigenvalues on 400 frequencies: ε falling
    smoothly in (0, 2π) (so each lobe's speed rises with f), the depth a smooth positive curve;
    one branch has a stretch with no chatter (+inf), as the zero-order depths have where
    Re(1/λ) ≤ 0."""
    rng = np.random.default_rng(seed)
    f = np.linspace(50.0, 1500.0, 400)
    x = (f - f[0]) / (f[-1] - f[0])
    eps = np.empty((2, f.size, 2))
    a = np.empty_like(eps)
    for b in range(2):
        for e in range(2):
            lo, hi = rng.uniform(0.2, 1.0), rng.uniform(4.0, 6.0)
            eps[b, :, e] = hi - (hi - lo) * x**rng.uniform(0.7, 1.5)
            a[b, :, e] = 1e-3 * (1.0 + rng.uniform(0.2, 1.0) * np.cos(rng.uniform(3, 9) * x
                                                                     + rng.uniform(0, 6)) ** 2)
    a[1, 150:180, 0] = np.inf
    return f, eps, a


def _reference(f, eps, a, n_t, n_lobes):
    """The envelope and its chatter frequency by np.interp per branch (independent of the
    kernel's segment loop)."""
    env = np.full((a.shape[0], n_t.size), np.inf)
    hz = np.full(env.shape, np.nan)
    for b in range(a.shape[0]):
        for e in range(a.shape[2]):
            for k in range(n_lobes):
                n = 60.0 * 2 * np.pi * f / (TEETH * (eps[b, :, e] + 2 * np.pi * k))
                assert np.all(np.diff(n) > 0)  # monotone: rising with f
                order = np.argsort(n)
                ns, As, fs = n[order], a[b, order, e], f[order]
                inside = (n_t >= ns[0]) & (n_t <= ns[-1])
                depth = np.interp(n_t, ns, As)
                # a speed between two frequencies either side of a no-chatter stretch is
                # reached by no segment
                j = np.clip(np.searchsorted(ns, n_t), 1, ns.size - 1)
                finite = np.isfinite(As[j - 1]) & np.isfinite(As[j]) | (n_t == ns[j - 1])
                depth = np.where(inside & finite, depth, np.inf)
                lower = depth < env[b]
                env[b, lower] = depth[lower]
                hz[b, lower] = np.interp(n_t, ns, fs)[lower]
    return env, hz


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_envelope_is_the_lowest_branch_interpolated_at_each_speed(seed):
    f, eps, a = _branches(seed)
    n_t = np.linspace(2000.0, 40000.0, 137)
    n_lobes = int(np.ceil(f.max() * 60.0 / (TEETH * n_t.min()))) + 2
    env = np.full((2, n_t.size), np.inf)
    hz = np.full(env.shape, np.nan)
    lower_envelope(env, hz, a, eps, f, n_t, TEETH, n_lobes)
    env_ref, hz_ref = _reference(f, eps, a, n_t, n_lobes)
    assert np.isfinite(env).mean() > 0.9  # the branches reach most of the speeds
    np.testing.assert_array_equal(np.isfinite(env), np.isfinite(env_ref))
    np.testing.assert_allclose(env, env_ref, rtol=1e-12)
    np.testing.assert_allclose(hz, hz_ref, rtol=1e-12)
    # without the chatter frequency the same depths
    env2 = np.full(env.shape, np.inf)
    lower_envelope(env2, None, a, eps, f, n_t, TEETH, n_lobes)
    np.testing.assert_array_equal(env2, env)


def test_speeds_no_branch_reaches_stay_infinite_and_an_existing_lower_value_stays():
    f, eps, a = _branches(4)
    n_t = np.array([10.0, 20.0, 5.0e6])  # far below and far above every lobe's speeds
    env = np.full((2, 3), np.inf)
    env[0, 0] = 1e-9  # lower than any branch: kept
    lower_envelope(env, None, a, eps, f, n_t[np.argsort(n_t)], TEETH, 3)
    assert env[0, 0] == 1e-9 and np.isinf(env[0, 1:]).all() and np.isinf(env[1]).all()
