"""Spectral-element lobes: the collocation pieces, the published benchmark's converged values
at the default settings, the convergence order against the first-order semi-discretization,
agreement with the zero-order method in slotting, the flip lobe, refinement to an accuracy and
the warm-started map."""

import numpy as np
import pytest

from robomill.chatter.lobes_sdm import critical_depth as sdm_critical_depth
from robomill.chatter.lobes_sdm import sdm_spectral_radius
from robomill.chatter.lobes_sem import (
    ACCURACY,
    _scan_root,
    cheb,
    critical_depth,
    segments,
    sem_lobes,
    sem_spectral_radius,
    speed_operator,
)
from robomill.chatter.lobes_zoa import zoa_lobes
from robomill.chatter.model import CuttingModel, ModeXY, tool_from_modes

MODE = dict(f_hz=922.0, zeta=0.011, k_N_m=1.34e6)
TOOL = tool_from_modes([ModeXY(**MODE, shape=(1.0, 0.0))])
CUT = CuttingModel.from_immersion(2, 6e8, 0.3333, 0.05, "down")  # insperger2004_down005
SDM_LIMIT_MM = {6400.0: 1.63915}
"""First-order SDM extrapolated to m → ∞ here: m = 320 gives 1.639884 mm, m = 640 1.639335 mm
(errors falling 4× per doubling, order 2), Richardson 1.639152 mm."""


def test_cheb_differentiates_polynomials_exactly():
    x, D = cheb(7)
    assert x[0] == -1 and x[-1] == 1 and np.all(np.diff(x) > 0)
    for k in range(8):
        np.testing.assert_allclose(D @ x**k, k * x ** max(k - 1, 0) * (k > 0), atol=1e-10)
    with pytest.raises(ValueError):
        cheb(0)


def test_segments_of_low_immersion_down_milling():
    """a_e/D = 0.05 down-milling, 2 teeth: the tooth cuts from acos(−0.9) to π, then flies
    free for the rest of the tooth period."""
    seg = segments(CUT, 6000.0)
    omega = 2 * np.pi * 6000.0 / 60
    tau = 60.0 / (2 * 6000.0)
    engaged = [s for s in seg if s[2]]
    assert len(engaged) == 1
    t0, t1, _ = engaged[0]
    assert t1 - t0 == pytest.approx((np.pi - np.arccos(-0.9)) / omega, rel=1e-12)
    assert sum(b - a for a, b, _ in seg) == pytest.approx(tau, rel=1e-12)
    # slotting with 4 teeth: always two teeth in the cut, one smooth segment
    slot = segments(CuttingModel.from_immersion(4, 6e8, 0.3, 1.0, "down"), 6000.0)
    assert len(slot) == 1 and len(slot[0][2]) == 2


def test_free_system_period_map_converges_to_the_exact_one():
    """Without cutting the period map is e^{Aτ}: ρ = max |e^{λτ}| (free flight is exact; the
    collocated cutting segment converges spectrally)."""
    tau = 60 / (2 * 10000.0)
    exact = np.abs(np.exp(np.linalg.eigvals(TOOL.A) * tau)).max()
    err = [abs(sem_spectral_radius(TOOL, CUT, 10000.0, [0.0], p=p)[0][0] / exact - 1)
           for p in (4, 8, 16)]
    assert err[0] > err[1] > err[2] and err[2] < 1e-10


def test_same_spectral_radius_as_fine_sdm():
    """Away from the boundary the spectral radius equals the first-order SDM's at large m."""
    depths = np.array([0.5e-3, 1.0e-3, 2.5e-3])
    rho_sem, _ = sem_spectral_radius(TOOL, CUT, 6400.0, depths, p=12)
    rho_sdm, _ = sdm_spectral_radius(TOOL, CUT, 6400.0, depths, m=320)
    np.testing.assert_allclose(rho_sem, rho_sdm, rtol=2e-4)


@pytest.mark.parametrize(("rpm", "issue_mm"), [(6400.0, 1.636), (8400.0, 1.630)])
def test_benchmark_converged_values_at_default_settings(rpm, issue_mm):
    """Issue 23: the converged first-order values (Richardson-extrapolated) 1.636 mm at
    6400 rpm and 1.630 mm at 8400 rpm, met within 0.5 % by the default accuracy; the error
    estimate meets the accuracy and bounds the true error (against order 24)."""
    r = critical_depth(TOOL, CUT, rpm, depth_max_m=10e-3)
    assert r.a_crit_m * 1e3 == pytest.approx(issue_mm, rel=0.005)
    assert r.error_m <= ACCURACY * r.a_crit_m
    ref = _scan_root(speed_operator(TOOL, CUT, rpm, 24), 10e-3, 16, 1e-10)
    assert abs(r.a_crit_m - ref) <= r.error_m
    if rpm in SDM_LIMIT_MM:
        assert ref * 1e3 == pytest.approx(SDM_LIMIT_MM[rpm], rel=2e-5)


def test_convergence_order_spectral_against_first_order_sdm():
    """On the benchmark at 6400 rpm the SEM error falls by more than 10× per two added nodes
    (faster than any power: spectral), while the first-order SDM error falls 4× per doubling
    of m (second order), towards the same limit."""
    rpm = 6400.0
    ref = _scan_root(speed_operator(TOOL, CUT, rpm, 24), 10e-3, 16, 1e-11)
    err = [abs(_scan_root(speed_operator(TOOL, CUT, rpm, p), 10e-3, 16, 1e-11) / ref - 1)
           for p in (2, 4, 6, 8, 10)]
    assert all(e1 < e0 / 10 for e0, e1 in zip(err[:-1], err[1:], strict=True)), err
    assert err[-1] < 1e-5
    a = {m: sdm_critical_depth(TOOL, CUT, rpm, depth_max_m=10e-3, m=m, rtol=1e-6,
                               n_scan=24)[0] for m in (20, 40, 80)}
    order = np.log2((a[20] - a[40]) / (a[40] - a[80]))
    assert order == pytest.approx(2.0, abs=0.25)
    richardson = a[80] + (a[80] - a[40]) / 3
    assert richardson == pytest.approx(ref, rel=1e-3)
    assert a[40] / ref - 1 == pytest.approx(0.031, abs=0.003)  # the old default: +3.1 %


def test_zoa_and_sem_agree_for_symmetric_slotting():
    """insperger2004_slot: 4 teeth, slotting, symmetric x/y modes: W(t) is nearly constant
    and the zero-order method must agree."""
    tool = tool_from_modes([ModeXY(**MODE, shape=(1.0, 0.0)), ModeXY(**MODE, shape=(0.0, 1.0))])
    cut = CuttingModel.from_immersion(4, 6e8, 0.3333, 1.0, "down")
    rpm = np.linspace(8000, 14000, 7)
    a_z, _ = zoa_lobes(tool, cut, rpm)
    r = sem_lobes(tool, cut, rpm, depth_max_m=10e-3)
    np.testing.assert_allclose(r["a_crit_m"], a_z, rtol=0.003)  # measured: <= 0.10 %
    assert (r["error_m"] <= ACCURACY * r["a_crit_m"]).all()
    assert set(r["kind"]) == {"hopf"}


def test_flip_lobe_and_hopf_lobes_of_the_benchmark():
    rpm = np.array([12000.0, 18000.0, 22000.0])
    r = sem_lobes(TOOL, CUT, rpm, depth_max_m=10e-3)
    a_z, _ = zoa_lobes(TOOL, CUT, rpm)
    assert list(r["kind"]) == ["hopf", "flip", "hopf"]
    assert r["a_crit_m"][1] < 0.4 * a_z[1]
    assert r["chatter_hz"][1] == pytest.approx(1.5 * 2 * 18000.0 / 60, rel=1e-6)
    np.testing.assert_allclose(r["a_crit_m"][[0, 2]], a_z[[0, 2]], rtol=0.08)


def test_refinement_meets_a_tight_accuracy():
    loose = critical_depth(TOOL, CUT, 8400.0, depth_max_m=10e-3, accuracy=0.02, p0=4)
    tight = critical_depth(TOOL, CUT, 8400.0, depth_max_m=10e-3, accuracy=1e-4, p0=4)
    assert tight.p > loose.p
    assert tight.error_m <= 1e-4 * tight.a_crit_m
    assert loose.error_m <= 0.02 * loose.a_crit_m
    assert abs(loose.a_crit_m - tight.a_crit_m) <= loose.error_m + tight.error_m


def test_warm_started_map_equals_cold_map():
    rpm = np.linspace(5000, 25000, 41)
    warm = sem_lobes(TOOL, CUT, rpm, depth_max_m=10e-3)
    cold = sem_lobes(TOOL, CUT, rpm, depth_max_m=10e-3, warm_start=False)
    fin = np.isfinite(cold["a_crit_m"])  # nan: stable up to depth_max (lobe tops)
    np.testing.assert_array_equal(np.isfinite(warm["a_crit_m"]), fin)
    tol = (warm["error_m"] + cold["error_m"])[fin]
    assert (np.abs(warm["a_crit_m"] - cold["a_crit_m"])[fin] <= tol).all()
    assert list(warm["kind"]) == list(cold["kind"])


def test_three_mode_two_dof_against_fine_sdm():
    """Three modes (two in x, one oblique) at half immersion, up-milling: the SEM depth
    equals the first-order SDM extrapolated from m = 80, 160 (Richardson, order 2)."""
    tool = tool_from_modes([ModeXY(700.0, 0.02, 2e7, (1.0, 0.0)),
                            ModeXY(1100.0, 0.015, 3e7, (1.0, 0.0)),
                            ModeXY(850.0, 0.02, 2.5e7, (0.6, 0.8))])
    cut = CuttingModel.from_immersion(3, 7e8, 0.3, 0.5, "up")
    for rpm in (9000.0, 15000.0):
        r = critical_depth(tool, cut, rpm, depth_max_m=20e-3)
        a80, _ = sdm_critical_depth(tool, cut, rpm, depth_max_m=20e-3, m=80, rtol=1e-5)
        a160, _ = sdm_critical_depth(tool, cut, rpm, depth_max_m=20e-3, m=160, rtol=1e-5)
        assert r.a_crit_m == pytest.approx(a160 + (a160 - a80) / 3, rel=2e-3)


def test_stable_to_depth_max_gives_nan():
    r = critical_depth(TOOL, CUT, 6400.0, depth_max_m=1e-3)
    assert np.isnan(r.a_crit_m) and np.isnan(r.error_m)


def test_bad_accuracy_is_refused():
    with pytest.raises(ValueError, match="accuracy"):
        critical_depth(TOOL, CUT, 6400.0, depth_max_m=10e-3, accuracy=0.0)


def test_accuracy_config_key(repo):
    """chatter.accuracy defaults to 0.005; 0, above 0.1 and the removed first-order keys are
    refused with the key named."""
    import copy

    import yaml

    from robomill.io import ConfigError
    from robomill.pipeline.config import validate_config

    schema = repo / "src/robomill/data/schemas/config.schema.yaml"
    raw = yaml.safe_load(open(repo / "config.yaml"))
    cfg = copy.deepcopy(raw)
    del cfg["chatter"]["accuracy"]
    assert validate_config(cfg, schema)["chatter"]["accuracy"] == ACCURACY
    for bad in (0.0, 0.5):
        cfg = copy.deepcopy(raw)
        cfg["chatter"]["accuracy"] = bad
        with pytest.raises(ConfigError, match=r"chatter\.accuracy"):
            validate_config(cfg, schema)
    cfg = copy.deepcopy(raw)
    cfg["chatter"]["sdm_steps_per_period"] = 40
    with pytest.raises(ConfigError, match="sdm_steps_per_period"):
        validate_config(cfg, schema)
