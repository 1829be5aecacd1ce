"""Lobes: zero-order closed form, semi-discretization convergence, slotting agreement, the
published 1-DOF benchmark, damped system without cutting."""

import numpy as np
import pytest

from robomill.chatter.lobes_sdm import (
    critical_depth,
    sdm_lobes,
    sdm_spectral_radius,
)
from robomill.chatter.lobes_zoa import zoa_lobes
from robomill.chatter.model import CuttingModel, ModeXY, immersion_angles, tool_from_modes

BENCH = dict(teeth=2, Kt_N_m2=6.0e8, Kr=0.3333)
MODE = dict(f_hz=922.0, zeta=0.011, k_N_m=1.34e6)


def test_immersion_angles():
    assert immersion_angles(1.0, "up") == pytest.approx((0.0, np.pi))
    assert immersion_angles(0.5, "down") == pytest.approx((np.pi / 2, np.pi))
    with pytest.raises(ValueError):
        immersion_angles(0.5, "sideways")


def test_interval_means_average_to_mean_matrix():
    cut = CuttingModel.from_immersion(3, 7e8, 0.4, 0.3, "up")
    np.testing.assert_allclose(cut.interval_means(37).mean(0), cut.mean_matrix(), rtol=1e-12)
    phi = np.linspace(0, 2 * np.pi / 3, 20001)[:-1]
    np.testing.assert_allclose(cut.instantaneous(phi).mean(0), cut.mean_matrix(), atol=2e5)


def test_zoa_equals_closed_form_single_symmetric_mode():
    """One mode in y only: a_lim = 1/(2 W̄_yy Re G) at each chatter frequency; the lobe
    diagram's minimum equals the minimum of the closed form."""
    mode = ModeXY(600.0, 0.03, 2e7, (0.0, 1.0))
    tool = tool_from_modes([mode])
    cut = CuttingModel.from_immersion(4, 8e8, 0.3, 1.0, "down")
    wyy = cut.mean_matrix()[1, 1]
    f = np.linspace(400, 900, 20001)
    r = f / mode.f_hz
    re_g = ((1 - r**2) / ((1 - r**2) ** 2 + (2 * mode.zeta * r) ** 2)) / mode.k_N_m
    a_closed = np.where(wyy * re_g > 0, 1 / (2 * wyy * re_g), np.inf)
    rpm = np.linspace(4000, 12000, 4001)
    a, fc = zoa_lobes(tool, cut, rpm, f_hz=f)
    assert np.nanmin(a) == pytest.approx(a_closed.min(), rel=2e-3)
    # at the best speeds the chatter frequency is where the closed form is smallest
    assert fc[np.nanargmin(a)] == pytest.approx(f[np.argmin(a_closed)], rel=5e-3)


def test_damped_system_without_cutting_is_stable():
    tool = tool_from_modes([ModeXY(**MODE, shape=(1.0, 0.0)), ModeXY(500.0, 0.02, 5e6, (0.3, 1.0))])
    cut = CuttingModel.from_immersion(2, 6e8, 0.3, 0.5, "up")
    rho, _ = sdm_spectral_radius(tool, cut, 10000.0, [0.0, 1e-12])
    assert (rho < 1).all()
    # and the period map of the free system is e^{Aτ}: ρ = max |e^{λτ}|
    tau = 60 / (2 * 10000.0)
    lam = np.linalg.eigvals(tool.A)
    assert rho[0] == pytest.approx(np.abs(np.exp(lam * tau)).max(), rel=1e-9)


def test_sdm_converges_as_step_shrinks():
    tool = tool_from_modes([ModeXY(**MODE, shape=(1.0, 0.0))])
    cut = CuttingModel.from_immersion(**BENCH, radial_immersion=0.05, milling="down")
    kw = dict(depth_max_m=10e-3, rtol=2e-4, n_scan=24)
    vals = {m: critical_depth(tool, cut, 22000.0, m=m, **kw)[0] for m in (10, 20, 40, 80, 160)}
    err = {m: abs(vals[m] / vals[160] - 1) for m in (10, 20, 40, 80)}
    assert err[80] < err[40] < err[20] < err[10] + 1e-3
    assert err[40] < 0.01  # the default m = 40 is within 1 % of the m = 160 result


def test_zoa_and_sdm_agree_for_slotting():
    modes = [ModeXY(**MODE, shape=(1.0, 0.0)), ModeXY(**MODE, shape=(0.0, 1.0))]
    tool = tool_from_modes(modes)
    cut = CuttingModel.from_immersion(4, 6e8, 0.3333, 1.0, "down")
    rpm = np.linspace(8000, 14000, 13)
    a_z, _ = zoa_lobes(tool, cut, rpm)
    a_s, _, kind = sdm_lobes(tool, cut, rpm, depth_max_m=10e-3, rtol=0.002)
    assert np.nanmin(a_s) == pytest.approx(np.nanmin(a_z), rel=0.03)
    np.testing.assert_allclose(a_s, a_z, rtol=0.02)
    assert set(kind) == {"hopf"}


def test_published_benchmark_insperger2004_down005():
    """Insperger & Stépán (2004) / Ding et al. (2010), a/D = 0.05 down-milling: Hopf lobes
    whose minima (~1.7 mm) the zero-order method also finds, and a flip lobe just below
    Ω = 60·2f_n/(3N) ≈ 18 440 rpm that only the semi-discretization finds."""
    tool = tool_from_modes([ModeXY(**MODE, shape=(1.0, 0.0))])
    cut = CuttingModel.from_immersion(**BENCH, radial_immersion=0.05, milling="down")
    rpm = np.array([12000.0, 17000.0, 18000.0, 22000.0])
    a_s, f_s, kind = sdm_lobes(tool, cut, rpm, depth_max_m=10e-3, rtol=0.002)
    a_z, _ = zoa_lobes(tool, cut, rpm)
    assert list(kind) == ["hopf", "flip", "flip", "hopf"]
    # Hopf boundaries: both methods, within a few per cent at low immersion
    np.testing.assert_allclose(a_s[[0, 3]], a_z[[0, 3]], rtol=0.08)
    assert 1.5e-3 < a_s[0] < 2.0e-3 and 1.5e-3 < a_s[3] < 2.0e-3
    # flip lobe: much lower than the zero-order prediction there; chatter at f_tooth(k + 1/2)
    assert a_s[2] < 0.4 * a_z[2]
    f_tooth = 2 * 18000.0 / 60
    assert f_s[2] == pytest.approx(1.5 * f_tooth, rel=1e-6)


def test_lobe_solvers_share_one_parameter_block_expanded_in_their_docstrings():
    """The numpydoc entries the three solvers share are written once (chatter.model) and
    expanded in place: no placeholder left, each entry with its description."""
    from robomill.chatter import sdm_lobes, sem_lobes, zoa_lobes

    for f in (sdm_lobes, sem_lobes, zoa_lobes):
        assert "{lobe:" not in f.__doc__
        assert "    tool, cut\n        Tool model and cutting model.\n" in f.__doc__
        assert "    spindle_rpm\n        Speeds [rpm].\n" in f.__doc__
    for f in (sdm_lobes, sem_lobes):
        assert "    depth_max_m\n        Largest depth searched" in f.__doc__
        assert "        (default: the tool's most flexible natural frequency).\n" in f.__doc__
    assert "depth_max_m" not in zoa_lobes.__doc__


def test_sdm_scan_stops_at_the_first_unstable_depth_and_reuses_nothing_but_exact_bits():
    """The lazy scan (lowest depths first, stopping at the first unstable one) and the kept
    scan eigen-decompositions must give what a full scan gives: every scan depth below the
    bracket stable, the upper end unstable, and the same radii whether or not the batch's
    decomposition was kept from another speed."""
    from robomill.chatter import lobes_sdm

    tool = tool_from_modes([ModeXY(**MODE, shape=(1.0, 0.0)), ModeXY(**MODE, shape=(0.0, 1.0))])
    cut = CuttingModel.from_immersion(**BENCH, radial_immersion=0.05, milling="down")
    dmax, n_scan, rtol = 2e-2, 16, 0.01
    scan = np.geomspace(dmax / 300.0, dmax, n_scan)
    for rpm in (5000.0, 9000.0):
        lobes_sdm._EIGEN_CACHE.clear()
        rho_full, _ = sdm_spectral_radius(tool, cut, rpm, scan, m=20)  # all 16 at once
        a, _ = critical_depth(tool, cut, rpm, depth_max_m=dmax, m=20, n_scan=n_scan, rtol=rtol)
        first = int(np.nonzero(rho_full >= 1.0)[0][0])
        assert first > 0
        assert scan[first - 1] <= a <= scan[first]  # bracketed by the first unstable depth
        assert (rho_full[:first] < 1.0).all()
    pair = scan[:2]
    lobes_sdm._EIGEN_CACHE.clear()
    fresh = sdm_spectral_radius(tool, cut, 7000.0, pair, m=20)
    sdm_spectral_radius(tool, cut, 6000.0, pair, m=20)  # keeps the pair's decomposition
    kept = sdm_spectral_radius(tool, cut, 7000.0, pair, m=20)
    assert len(lobes_sdm._EIGEN_CACHE) >= 1
    np.testing.assert_array_equal(fresh[1], kept[1])


def test_one_zero_order_routine_serves_one_tool_and_the_planners_batches():
    """zoa_lobes is zoa_envelope for one tool: the same depths as the planner's batch
    routine given the same receptance and frequency grid, and the chatter frequency of the
    envelope's branch lies on the grid's span."""
    from robomill.chatter.lobes_zoa import default_frequency_grid, zoa_envelope
    from robomill.plan.lobes import batch_zoa_lobes

    modes = [ModeXY(**MODE, shape=(1.0, 0.0)), ModeXY(500.0, 0.02, 5e6, (0.3, 1.0))]
    tool = tool_from_modes(modes)
    cut = CuttingModel.from_immersion(3, 7e8, 0.4, 0.5, "up")
    rpm = np.linspace(12000.0, 3000.0, 91)  # descending: results come back in this order
    f = default_frequency_grid(tool)
    a, fc = zoa_lobes(tool, cut, rpm, f_hz=f)
    env = zoa_envelope(np.moveaxis(tool.frf(f), -1, 0)[None], f, cut, rpm)
    batch = batch_zoa_lobes([[m.f_hz for m in modes]], [m.zeta for m in modes],
                            [[m.k_N_m for m in modes]], [[m.shape for m in modes]], cut, rpm,
                            f_hz=f)
    ok = np.isfinite(a)
    assert ok.sum() > 80
    np.testing.assert_array_equal(env[0][ok], a[ok])
    np.testing.assert_allclose(batch[0][ok], a[ok], rtol=1e-9)
    assert (fc[ok] >= f.min()).all() and (fc[ok] <= f.max()).all()
    # the same speeds in ascending order give the same depths, reversed
    a_up, _ = zoa_lobes(tool, cut, rpm[::-1], f_hz=f)
    np.testing.assert_array_equal(a_up[::-1][ok], a[ok])


def test_no_negative_real_part_is_no_chatter_not_the_largest_float():
    """W̄G with the eigenvalue Λ = −1e-7 i and 0 (by construction G = W̄⁻¹ diag(Λ, 0)): 1/Λ
    has no real part, so no branch reaches any speed: +inf at every speed, not the largest
    float (1.8e308 m, which a learn round's chapter 4 could not draw)."""
    from robomill.chatter.lobes_zoa import zoa_envelope

    cut = CuttingModel.from_immersion(2, 6e8, 0.3, 1.0, "down")
    G = np.linalg.solve(cut.mean_matrix(), np.diag([-1e-7j, 0.0]))[None, None]  # (1,1,2,2)
    a = zoa_envelope(np.repeat(G, 2, axis=1), np.array([500.0, 501.0]), cut,
                     np.array([3000.0, 6000.0]))
    assert np.isposinf(a).all()
