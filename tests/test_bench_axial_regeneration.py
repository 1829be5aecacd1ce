"""The zero-order depth with the axial force's regeneration (the package's model, through
``benchmarks/axial_regeneration.py``): without an axial coefficient it is the planar model's,
the planar path is the planner's own zero-order routine, and on one mode the depth moves as
the directional factor written by hand says."""

import sys
from collections import namedtuple
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "benchmarks"))
from axial_regeneration import zoa_planar_and_axial_m  # noqa: E402

from robomill.chatter.model import CuttingModel  # noqa: E402
from robomill.plan.lobes import batch_zoa_lobes  # noqa: E402

Mode = namedtuple("Mode", "f_hz zeta k_N_m shape")
SLOT = CuttingModel(2, 6.0e8, 0.3, 0.0, np.pi)
RPM = 20000.0


def test_without_an_axial_coefficient_the_depth_is_the_planar_one():
    modes = [Mode(70.0, 0.05, 2e6, (0.6, 0.0, 0.8)), Mode(35.0, 0.04, 1e6, (0.0, 0.6, 0.8))]
    planar, axial = zoa_planar_and_axial_m(modes, np.eye(3), SLOT, 0.0, RPM)
    assert np.isfinite(planar) and axial == pytest.approx(planar, rel=1e-12)


def test_the_planar_path_is_the_planners_zero_order_routine():
    modes = [Mode(70.0, 0.05, 2e6, (0.6, 0.0, 0.8)), Mode(35.0, 0.04, 1e6, (0.28, 0.96, 0.0))]
    planar, _ = zoa_planar_and_axial_m(modes, np.eye(3), SLOT, 1.7e8, RPM)
    ref = batch_zoa_lobes([[70.0, 35.0]], [0.05, 0.04], [[2e6, 1e6]],
                          [[[0.6, 0.0], [0.28, 0.96]]], SLOT, np.array([RPM]))[0, 0]
    assert planar == pytest.approx(ref, rel=1e-9)


def test_one_mode_scales_with_its_directional_factor_by_hand():
    """One mode φ = (c, 0, s) in a slot: the oriented receptance is h φ_xy (φ_xyᵀ W̄ + s w_z)
    of rank one, so the depth goes as 1/K with K = c² W̄_xx + c s N K_ac/π, W̄_xx = −N K_t K_r/4
    (the slot's averages ∫₀^π −sin φ (cos φ + K_r sin φ) dφ = −K_r π/2 and ∫₀^π sin φ dφ = 2);
    s of the sign that keeps K's sign."""
    c, s = 0.8, -0.6
    Kac = 0.28 * SLOT.Kt_N_m2
    modes = [Mode(70.0, 0.05, 2e6, (c, 0.0, s))]
    # a speed whose lobes reach the mode (tooth passing 100 Hz above its 70 Hz)
    planar, axial = zoa_planar_and_axial_m(modes, np.eye(3), SLOT, Kac, 3000.0)
    N, Kt, Kr = SLOT.teeth, SLOT.Kt_N_m2, SLOT.Kr
    K2 = c**2 * (-N * Kt * Kr / 4)
    K3 = K2 + c * s * N * Kac / np.pi
    assert np.isfinite(planar)
    assert axial / planar == pytest.approx(K2 / K3, rel=1e-3)
    assert axial < planar
