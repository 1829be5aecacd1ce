"""The linearised edge-force switching of benchmarks/edge_switching.py against an independent
truth: the tooth-period mean of the edge force of Altintas 2012 eq. 2.25, integrated numerically
over the cutter angle for a tool shifted by a constant regenerative difference Δ (the chip
c sin φ + Δx sin φ + Δy cos φ, the force only while the chip is positive and the tooth inside
its engagement), differentiated by central differences."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from edge_switching import EdgeSwitchingCut  # noqa: E402

from robomill.chatter.model import CuttingModel  # noqa: E402

KTE, KRE = 27.7e3, 30.8e3   # N/m
CHIP = 5e-6                 # m


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
    total = np.zeros(2)
    for a, b in zip(cuts[:-1], cuts[1:], strict=True):
        if h(0.5 * (a + b)) > 0:
            total += [quad(lambda p: -KTE * np.cos(p) - KRE * np.sin(p), a, b, epsabs=0)[0],
                      quad(lambda p: KTE * np.sin(p) - KRE * np.cos(p), a, b, epsabs=0)[0]]
    return teeth / (2 * np.pi) * total


@pytest.mark.parametrize("entry, exit_", [(0.0, np.pi), (np.pi / 2, np.pi), (0.0, np.pi / 3)])
def test_the_term_is_the_central_difference_of_the_mean_edge_force(entry, exit_):
    teeth = 3
    model = EdgeSwitchingCut(teeth, 6e8, 0.3, entry, exit_, KTE, KRE, CHIP, 0.5)
    term = model.mean_matrix() - CuttingModel(teeth, 6e8, 0.3, entry, exit_).mean_matrix()
    step = 1e-4 * CHIP
    fd = np.stack([(mean_edge_force(step * u, teeth, entry, exit_)
                    - mean_edge_force(-step * u, teeth, entry, exit_)) / (2 * step)
                   for u in np.eye(2)], axis=1)
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
    up = (mean_edge_force(np.array([0.0, step]), teeth, 0.0, np.pi) - f0) / step
    down = (f0 - mean_edge_force(np.array([0.0, -step]), teeth, 0.0, np.pi)) / step
    two_sided = EdgeSwitchingCut(teeth, 6e8, 0.3, 0.0, np.pi, KTE, KRE, CHIP, 1.0)
    full = two_sided.mean_matrix() - CuttingModel(teeth, 6e8, 0.3, 0.0, np.pi).mean_matrix()
    assert np.allclose(up, 0.5 * full[:, 1], rtol=1e-3)
    assert np.allclose(down, 0.5 * full[:, 1], rtol=1e-3)


@pytest.mark.parametrize("entry, exit_, teeth", [(0.0, np.pi, 2), (np.pi / 2, np.pi, 3),
                                                 (0.0, 1.2, 4)])
def test_the_impulses_of_the_semi_discretization_average_to_the_mean_term(entry, exit_, teeth):
    model = EdgeSwitchingCut(teeth, 6e8, 0.3, entry, exit_, KTE, KRE, CHIP, 0.5)
    for m in (7, 40):
        assert np.allclose(model.interval_means(m).mean(0), model.mean_matrix())
