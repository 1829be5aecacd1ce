"""The force prediction interval of a new cut covers held-out cuts at about its nominal rate.

The cuts come from an independent generator: the instantaneous chip force of every tooth,
summed and averaged numerically over a revolution (not the closed form the predictor uses),
with the scatter a dynamometer mean shows from cut to cut added."""

import numpy as np
import pytest

from robomill.forces.prediction import fit_force_regression, predict_mean_force

K = {"Ktc": 800.0, "Krc": 170.0, "Kac": 220.0, "Kte": 28.0, "Kre": 31.0, "Kae": 6.7}


def simulated_mean_force(c_mm, a_mm, flutes, entry, exit_, n_phi=3600):
    """Mean force (feed, cross-feed, axial) [N] by summing each tooth's force over a
    revolution on a fine grid: h = c sin φ in the window, F_t = a(K_tc h + K_te), F_r =
    a(K_rc h + K_re), F_a = a(K_ac h + K_ae), F_x = −F_t cos φ − F_r sin φ, F_y = F_t sin φ −
    F_r cos φ."""
    phi = np.linspace(0, 2 * np.pi, n_phi, endpoint=False)
    F = np.zeros(3)
    for j in range(flutes):
        p = np.mod(phi + 2 * np.pi * j / flutes, 2 * np.pi)
        on = (p >= entry) & (p < exit_)
        h = c_mm * np.sin(p)
        ft = a_mm * (K["Ktc"] * h + K["Kte"]) * on
        fr = a_mm * (K["Krc"] * h + K["Kre"]) * on
        fa = a_mm * (K["Kac"] * h + K["Kae"]) * on
        F += [np.mean(-ft * np.cos(p) - fr * np.sin(p)), np.mean(ft * np.sin(p)
                                                               - fr * np.cos(p)),
              np.mean(fa)]
    return F


def test_prediction_interval_covers_held_out_cuts_at_nominal_rate():
    rng = np.random.default_rng(7)
    feeds = np.array([0.002, 0.004, 0.006, 0.008, 0.010])
    depths = np.array([0.25, 0.5])
    train = [(c, a, 0.0, np.pi) for c in feeds for a in depths]
    train += [(c, 0.5, np.pi / 2, np.pi) for c in feeds[::2]]            # down-milling half
    clean_train = np.array([simulated_mean_force(c, a, 2, s, e) for c, a, s, e in train])
    held = [(c, a, s, e) for c in (0.003, 0.007, 0.009) for a in (0.3, 0.45)
            for s, e in ((0.0, np.pi), (np.pi / 2, np.pi))]
    clean_held = np.array([simulated_mean_force(c, a, 2, s, e) for c, a, s, e in held])
    sigma_N = 0.4
    hits = total = 0
    narrow_ci_hits = 0
    for _ in range(300):
        F = clean_train + rng.normal(0, sigma_N, clean_train.shape)
        tr = np.array(train)
        reg = fit_force_regression(tr[:, 0], tr[:, 1], F, flutes=2, entry_rad=tr[:, 2],
                                   exit_rad=tr[:, 3])
        h = np.array(held)
        p = predict_mean_force(reg, h[:, 0], h[:, 1], flutes=2, entry_rad=h[:, 2],
                               exit_rad=h[:, 3], level=0.95)
        new = np.linalg.norm(clean_held + rng.normal(0, sigma_N, clean_held.shape), axis=1)
        hits += int(np.sum((new >= p["low_N"]) & (new <= p["high_N"])))
        total += len(held)
        # the mean regression's band alone (no new-cut scatter) is far too narrow
        band = 1.96 * np.sqrt(np.maximum(p["magnitude_sd_N"] ** 2 - sigma_N ** 2, 0))
        narrow_ci_hits += int(np.sum(np.abs(new - p["magnitude_N"]) <= band))
    assert 0.92 <= hits / total <= 0.98
    assert narrow_ci_hits / total < 0.85


def test_interval_widens_away_from_the_identified_chip_loads():
    feeds = np.array([0.004, 0.005, 0.006])
    tr = [(c, a) for c in feeds for a in (0.25, 0.5)]
    F = np.array([simulated_mean_force(c, a, 2, 0.0, np.pi) for c, a in tr])
    F += np.random.default_rng(1).normal(0, 0.3, F.shape)
    tr = np.array(tr)
    reg = fit_force_regression(tr[:, 0], tr[:, 1], F, flutes=2)
    p = predict_mean_force(reg, np.array([0.005, 0.02]), 0.4, flutes=2)
    w = p["high_N"] - p["low_N"]
    assert w[1] > 1.5 * w[0]
    assert p["magnitude_N"][0] == pytest.approx(np.linalg.norm(
        simulated_mean_force(0.005, 0.4, 2, 0.0, np.pi)), rel=0.02)


def test_regression_from_the_mean_forces_table_of_any_design():
    import pandas as pd

    from robomill.forces.prediction import regression_from_means

    rows = []
    rng = np.random.default_rng(2)
    for c in (0.002, 0.005, 0.008):
        for ent, z in ((np.pi / 2, 3), (0.0, 3)):
            F = simulated_mean_force(c, 0.4, z, ent, np.pi) + rng.normal(0, 0.01, 3)
            rows.append({"feed_per_tooth_mm": c, "depth_mm": 0.4, "flutes": z,
                         "entry_deg": np.degrees(ent), "exit_deg": 180.0, "F_feed_N": F[0],
                         "F_cross_feed_N": F[1], "F_axial_N": F[2]})
    reg = regression_from_means(pd.DataFrame(rows), flutes=2)
    assert reg is not None and reg.n_cuts == 6
    assert reg.theta_xy[0] == pytest.approx(K["Ktc"], rel=0.05)
    assert reg.theta_z[1] == pytest.approx(K["Kae"], rel=0.1)
    one_feed = pd.DataFrame(rows).assign(feed_per_tooth_mm=0.005)
    assert regression_from_means(one_feed, flutes=2) is None
