"""The linearised edge-force switching of the one stability model
(:class:`robomill.chatter.model.EdgeSwitching`) against an independent truth: the tooth-period
mean of the edge force of Altintas 2012 eq. 2.25, integrated numerically over the cutter angle
for a tool shifted by a constant regenerative difference Δ (the chip c sin φ + Δx sin φ +
Δy cos φ, the force only while the chip is positive and the tooth inside its engagement),
differentiated by central differences."""

import numpy as np
import pytest

from robomill.chatter.lobes_sem import sem_spectral_radius
from robomill.chatter.model import CuttingModel, EdgeSwitching, ModeXY, tool_from_modes

KTE, KRE, KAE = 27.7e3, 30.8e3, 9.5e3   # N/m
CHIP = 5e-6                             # m


def edge_cut(teeth, kt, kr, entry, exit_, kte, kre, chip, gain, **kw):
    """The cutting model with the edge term (``Ka``/``Kae_N_m`` for the axial row)."""
    kae = kw.pop("Kae_N_m", 0.0)
    return CuttingModel(teeth, kt, kr, entry, exit_,
                        edge=EdgeSwitching(kte, kre, chip, gain, kae), **kw)


def mean_edge_force(delta, teeth, entry, exit_):
    """N/(2π) ∫ e(φ) [h(φ) > 0] dφ over the engagement, per unit depth [N/m]: the chip's sign
    changes located on a grid and refined by root finding, e integrated by quadrature on each
    interval where the tooth cuts."""
    from scipy.integrate import quad
    from scipy.optimize import brentq

    def h(p):
        return CHIP * np.sin(p) + delta[0] * np.sin(p) + delta[1] * np.cos(p)

    grid = np.linspace(entry, exit_, 20_001)
    hv = h(grid)
    cuts = [entry] + [brentq(h, a, b, xtol=1e-15) for a, b, ha, hb in
                      zip(grid[:-1], grid[1:], hv[:-1], hv[1:], strict=True)
                      if ha * hb < 0] + [exit_]
    total = np.zeros(3)
    for a, b in zip(cuts[:-1], cuts[1:], strict=True):
        if h(0.5 * (a + b)) > 0:
            total += [quad(lambda p: -KTE * np.cos(p) - KRE * np.sin(p), a, b, epsabs=0)[0],
                      quad(lambda p: KTE * np.sin(p) - KRE * np.cos(p), a, b, epsabs=0)[0],
                      KAE * (b - a)]
    return teeth / (2 * np.pi) * total


@pytest.mark.parametrize("entry, exit_", [(0.0, np.pi), (np.pi / 2, np.pi), (0.0, np.pi / 3)])
def test_the_term_is_the_central_difference_of_the_mean_edge_force(entry, exit_):
    teeth = 3
    model = edge_cut(teeth, 6e8, 0.3, entry, exit_, KTE, KRE, CHIP, 0.5)
    term = model.mean_matrix() - CuttingModel(teeth, 6e8, 0.3, entry, exit_).mean_matrix()
    step = 1e-4 * CHIP
    fd = np.stack([(mean_edge_force(step * u, teeth, entry, exit_)
                    - mean_edge_force(-step * u, teeth, entry, exit_)) / (2 * step)
                   for u in np.eye(2)], axis=1)[:2]
    scale = teeth / (2 * np.pi) * KRE / CHIP
    assert np.allclose(term, fd, atol=1e-3 * scale)
    if entry == 0.0 and exit_ == np.pi:  # slot: -γ N/(π c) [[0, K_te], [0, K_re]], γ = 1/2
        slot = -0.5 * teeth / (np.pi * CHIP) * np.array([[0, KTE], [0, KRE]])
        assert np.allclose(term, slot, rtol=1e-12, atol=1e-9 * scale)
    assert np.abs(term).max() > 0.1 * scale   # the term is there wherever a chip vanishes


def test_the_one_sided_switch_has_half_the_two_sided_slope_on_either_side():
    """In a slot a shift Δy moves the chip's zero outward at one edge and inward at the other;
    the tooth cannot cut outside its engagement, so on either side of Δy = 0 only the edge
    whose contact shortens answers: each one-sided slope is half the two-sided term."""
    teeth = 2
    step = 1e-4 * CHIP
    f0 = mean_edge_force(np.zeros(2), teeth, 0.0, np.pi)
    up = (mean_edge_force(np.array([0.0, step]), teeth, 0.0, np.pi) - f0)[:2] / step
    down = (f0 - mean_edge_force(np.array([0.0, -step]), teeth, 0.0, np.pi))[:2] / step
    two_sided = edge_cut(teeth, 6e8, 0.3, 0.0, np.pi, KTE, KRE, CHIP, 1.0)
    full = two_sided.mean_matrix() - CuttingModel(teeth, 6e8, 0.3, 0.0, np.pi).mean_matrix()
    assert np.allclose(up, 0.5 * full[:, 1], rtol=1e-3)
    assert np.allclose(down, 0.5 * full[:, 1], rtol=1e-3)


@pytest.mark.parametrize("entry, exit_, teeth", [(0.0, np.pi, 2), (np.pi / 2, np.pi, 3),
                                                 (0.0, 1.2, 4)])
def test_the_impulses_of_the_semi_discretization_average_to_the_mean_term(entry, exit_, teeth):
    model = edge_cut(teeth, 6e8, 0.3, entry, exit_, KTE, KRE, CHIP, 0.5)
    for m in (7, 40):
        assert np.allclose(model.interval_means(m).mean(0), model.mean_matrix())


@pytest.mark.parametrize("entry, exit_", [(0.0, np.pi), (np.pi / 2, np.pi)])
def test_the_axial_edge_force_switches_with_the_same_chip(entry, exit_):
    """With the axial row (K_a set) the term gains the axial edge force's row: the central
    difference of the mean axial edge force K_ae over the engaged angles (the window's edge
    makes it one-sided, γ = ½, as for the in-plane rows); the in-plane rows are those of the
    planar term."""
    teeth = 2
    axial = edge_cut(teeth, 6e8, 0.3, entry, exit_, KTE, KRE, CHIP, 0.5, Ka=0.3,
                             Kae_N_m=KAE)
    term = axial.mean_matrix() - CuttingModel(teeth, 6e8, 0.3, entry, exit_,
                                              Ka=0.3).mean_matrix()
    step = 1e-4 * CHIP
    fd = np.stack([(mean_edge_force(step * u, teeth, entry, exit_)
                    - mean_edge_force(-step * u, teeth, entry, exit_)) / (2 * step)
                   for u in np.eye(2)], axis=1)
    scale = teeth / (2 * np.pi) * KRE / CHIP
    assert term.shape == (3, 2)
    assert np.allclose(term[2], fd[2], atol=1e-3 * scale)
    if entry == 0.0:  # a slot: the axial edge force's entry and exit switches cancel
        assert np.abs(term[2]).max() < 1e-6 * teeth / (2 * np.pi) * KAE / CHIP
    else:             # down milling: one switch, at the exit
        assert abs(term[2, 1]) > 0.1 * teeth / (2 * np.pi) * KAE / CHIP
    planar = edge_cut(teeth, 6e8, 0.3, entry, exit_, KTE, KRE, CHIP, 0.5)
    plain = CuttingModel(teeth, 6e8, 0.3, entry, exit_)
    assert np.allclose(term[:2], planar.mean_matrix() - plain.mean_matrix(), rtol=1e-12)


def test_the_term_is_refused_where_it_cannot_be_held():
    """The spectral elements read the instantaneous matrix, which has no impulse: asked with
    the term they say so (one line), as a non-positive feed per tooth is refused."""
    cut = edge_cut(2, 6e8, 0.3, 0.0, np.pi, KTE, KRE, CHIP, 0.5)
    tool = tool_from_modes([ModeXY(800.0, 0.03, 2e7, (0.0, 1.0))])
    with pytest.raises(ValueError, match="impulse"):
        sem_spectral_radius(tool, cut, 28_000.0, np.array([1e-4]))
    with pytest.raises(ValueError, match="feed per tooth"):
        EdgeSwitching(KTE, KRE, 0.0)


def test_the_zero_order_lobes_of_a_normal_mode_scale_by_the_closed_form():
    """One mode along the slot's normal: its zero-order limit is −1/(2 W̄_yy min Re G) at
    every speed, and in a slot W̄_yy = −N K_t K_r/4 without the term and −N K_t K_r/4 −
    γ N K_re/(π c) with it, so the limits' ratio is K_t K_r/4 ÷ (K_t K_r/4 + γ K_re/(π c)),
    written here from those two expressions alone."""
    from robomill.chatter.lobes_zoa import zoa_lobes

    kt, kr, teeth = 6e8, 0.3, 2
    tool = tool_from_modes([ModeXY(800.0, 0.03, 2e7, (0.0, 1.0))])
    rpm = np.array([9_000.0, 17_000.0, 28_000.0])
    plain, _ = zoa_lobes(tool, CuttingModel(teeth, kt, kr, 0.0, np.pi), rpm)
    edge, _ = zoa_lobes(tool, edge_cut(teeth, kt, kr, 0.0, np.pi, KTE, KRE, CHIP, 0.5),
                        rpm)
    ratio = (kt * kr / 4) / (kt * kr / 4 + 0.5 * KRE / (np.pi * CHIP))
    assert np.all(np.isfinite(plain)) and ratio < 0.5
    assert np.allclose(edge / plain, ratio, rtol=1e-6)
