"""The axial force's row in every stability solver: the cutting model's averages against
integrals written by hand, the three solvers (zero-order, semi-discretization, spectral
elements) on one 3-input tool, and the planar model kept exactly where no axial shape or no
axial coefficient is given."""

import numpy as np
import pytest

from robomill.chatter.coupling import coupling_depth, receptance
from robomill.chatter.lobes_sdm import critical_depth, sdm_lobes
from robomill.chatter.lobes_sem import sem_lobes
from robomill.chatter.lobes_zoa import zoa_lobes
from robomill.chatter.model import CuttingModel, ModeXY, conform_rows, tool_from_modes

KT, KR, KA = 8.0e8, 0.21, 0.28
# a robot-like pair: modes mostly along the tool axis with an in-plane part (the thesis' 60 and
# 72 Hz modes are mostly Z), and one in-plane mode
MODES3 = [ModeXY(60.0, 0.05, 2.0e6, (0.30, 0.20, 0.93)),
          ModeXY(72.0, 0.04, 3.0e6, (0.10, -0.50, 0.86)),
          ModeXY(31.0, 0.05, 1.5e6, (0.90, 0.40, -0.17))]
MODES2 = [ModeXY(m.f_hz, m.zeta, m.k_N_m, m.shape[:2]) for m in MODES3]
RPM = np.array([6000.0, 12000.0, 20000.0])


def test_axial_row_averages_by_hand():
    """The slot's axial row: N K_t K_a/(2π) ∫₀^π (sin φ, cos φ) dφ = N K_t K_a/π (1, 0); a
    half-immersion up-milling cut: ∫₀^{π/2} = (1, 1); the planar rows unchanged."""
    slot = CuttingModel(3, KT, KR, 0.0, np.pi, Ka=KA)
    np.testing.assert_allclose(slot.mean_matrix()[2], 3 * KT * KA / np.pi * np.array([1.0, 0.0]),
                               atol=1e-6 * KT)
    np.testing.assert_allclose(slot.mean_matrix()[:2], CuttingModel(3, KT, KR, 0.0, np.pi)
                               .mean_matrix(), rtol=0, atol=0)
    half = CuttingModel.from_immersion(3, KT, KR, 0.5, "up", Ka=KA)
    np.testing.assert_allclose(half.mean_matrix()[2], 3 * KT * KA / (2 * np.pi) * np.ones(2),
                               rtol=1e-12)
    # the per-interval averages and the instantaneous matrix average to the same row
    np.testing.assert_allclose(half.interval_means(41).mean(0), half.mean_matrix(), rtol=1e-12,
                               atol=1e-6)
    phi = np.linspace(0, 2 * np.pi / 3, 60001)[:-1]
    np.testing.assert_allclose(half.instantaneous(phi).mean(0)[2], half.mean_matrix()[2],
                               atol=2e-4 * KT)


def test_conform_rows_pads_and_drops_only_the_axial_row():
    W3 = CuttingModel(2, KT, KR, 0.0, np.pi, Ka=KA).mean_matrix()
    assert conform_rows(W3, 2).shape == (2, 2) and conform_rows(W3, 3) is W3
    padded = conform_rows(W3[:2], 3)
    assert padded.shape == (3, 2) and not padded[2].any()
    with pytest.raises(ValueError, match="4 rows"):
        conform_rows(np.zeros((4, 2)), 2)


def test_receptance_gives_the_inplane_response_to_the_axial_force():
    """G₂₃'s last column is Σ φ_xy φ_z h: one mode by hand."""
    f = np.array([10.0, 60.0, 200.0])
    G = receptance(f, [[60.0]], [0.05], [[2e6]], [[[0.3, 0.2, 0.9]]])[0]
    r = f / 60.0
    h = 1 / (2e6 * (1 - r**2 + 2j * 0.05 * r))
    np.testing.assert_allclose(G[:, :, 2], h[:, None] * np.array([0.27, 0.18])[None], rtol=1e-12)
    np.testing.assert_allclose(G[:, :, :2], receptance(f, [[60.0]], [0.05], [[2e6]],
                                                       [[[0.3, 0.2]]])[0], rtol=0, atol=0)


def test_solvers_agree_with_the_axial_row_and_it_matters():
    """Zero-order, semi-discretization and spectral elements on the 3-input tool of a slot
    (4 teeth: W(t) nearly constant, where the three agree on the planar model too); the
    axial row moves the depth by far more than their differences."""
    tool = tool_from_modes(MODES3)
    assert tool.n_inputs == 3 and tool.frf(np.array([60.0])).shape == (2, 3, 1)
    cut = CuttingModel(4, KT, KR, 0.0, np.pi, Ka=KA)
    a_z, _ = zoa_lobes(tool, cut, RPM)
    a_s = np.asarray(sdm_lobes(tool, cut, RPM, depth_max_m=0.05, rtol=1e-3)[0], float)
    a_e = sem_lobes(tool, cut, RPM, depth_max_m=0.05)["a_crit_m"]
    np.testing.assert_allclose(a_s, a_z, rtol=0.03)
    np.testing.assert_allclose(a_e, a_s, rtol=0.03)
    a_planar, _ = zoa_lobes(tool_from_modes(MODES2), CuttingModel(4, KT, KR, 0.0, np.pi), RPM)
    solvers = max(np.abs(a_s / a_z - 1).max(), np.abs(a_e / a_s - 1).max())
    assert np.all(np.abs(a_z / a_planar - 1) > 2 * solvers)


def test_the_planar_model_is_kept_exactly_without_axial_shape_or_coefficient():
    """A 3-input tool under a cut without K_a, and an in-plane tool under a cut with it: the
    planar lobes to the last digit (the axial row meets no axial shape)."""
    planar = CuttingModel(4, KT, KR, 0.0, np.pi)
    axial = CuttingModel(4, KT, KR, 0.0, np.pi, Ka=KA)
    ref = critical_depth(tool_from_modes(MODES2), planar, 12000.0, depth_max_m=0.05)[0]
    assert critical_depth(tool_from_modes(MODES2), axial, 12000.0, depth_max_m=0.05)[0] == ref
    assert critical_depth(tool_from_modes(MODES3), planar, 12000.0,
                          depth_max_m=0.05)[0] == pytest.approx(ref, rel=1e-9)
    z2, _ = zoa_lobes(tool_from_modes(MODES2), planar, RPM)
    np.testing.assert_array_equal(zoa_lobes(tool_from_modes(MODES2), axial, RPM)[0], z2)


def test_the_delay_free_diagnostic_takes_the_axial_force_too():
    shapes3 = [[m.shape for m in MODES3]]
    args = ([[m.f_hz for m in MODES3]], [m.zeta for m in MODES3], [[m.k_N_m for m in MODES3]])
    a3 = coupling_depth(*args, shapes3, CuttingModel(4, KT, KR, 0.0, np.pi, Ka=KA))
    a0 = coupling_depth(*args, shapes3, CuttingModel(4, KT, KR, 0.0, np.pi, Ka=0.0))
    a2 = coupling_depth(*args, [[m.shape for m in MODES2]], CuttingModel(4, KT, KR, 0.0, np.pi))
    assert a0[0] == pytest.approx(a2[0], rel=1e-3)
    assert a3[0] != pytest.approx(a2[0], rel=1e-2)
