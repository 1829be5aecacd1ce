"""Whether the feed directions share the cutting coefficients
(:func:`robomill.forces.coefficients.direction_heterogeneity`): mean forces written here from the
slot's mean-force lines (Altintas 2012, §2.4: F̄_y/(Na) = K_tc c/4 + K_te/π,
F̄_x/(Na) = −(K_rc c/4 + K_re/π), F̄_z/(Na) = K_ac c/π + K_ae/2), and Cochran's Q worked out by
hand from the least-squares slope's standard error."""

import numpy as np
import pandas as pd
import pytest

from robomill.findings import Findings
from robomill.forces.coefficients import direction_heterogeneity
from robomill.forces.findings import _directions
from robomill.pipeline.prose import load_templates, render

FEEDS_MM = np.array([0.001, 0.002, 0.003, 0.004, 0.005, 0.006])
DEPTH_MM = 0.5
N = 2
# the same small departure from the line in every direction (N/mm per unit N a), so that two
# directions with the same coefficients give the same estimates exactly
WIGGLE = np.array([0.02, -0.03, 0.01, 0.03, -0.02, -0.01])
BASE = {"Ktc": 800.0, "Krc": 200.0, "Kac": 250.0, "Kte": 25.0, "Kre": 30.0, "Kae": 6.0}


def _cuts(direction: str, k: dict) -> pd.DataFrame:
    c, na = FEEDS_MM, N * DEPTH_MM
    return pd.DataFrame({
        "cut": [f"{direction}_{i}" for i in range(c.size)], "direction": direction,
        "feed_per_tooth_mm": c, "depth_mm": DEPTH_MM, "in_fit": True,
        "F_feed_N": -na * (k["Krc"] * c / 4 + k["Kre"] / np.pi + WIGGLE),
        "F_cross_feed_N": na * (k["Ktc"] * c / 4 + k["Kte"] / np.pi + WIGGLE),
        "F_axial_N": na * (k["Kac"] * c / np.pi + k["Kae"] / 2 + WIGGLE)})


def _ktc_standard_error() -> float:
    """4 × the standard error of the slope of F̄_y/(Na) against c, by the textbook formula."""
    c = FEEDS_MM
    X = np.column_stack([np.ones_like(c), c])
    resid = WIGGLE - X @ np.linalg.lstsq(X, WIGGLE, rcond=None)[0]
    s2 = resid @ resid / (c.size - 2)
    return 4 * np.sqrt(s2 / np.sum((c - c.mean()) ** 2))


def test_directions_with_the_same_coefficients_agree_exactly():
    means = pd.concat([_cuts("px", BASE), _cuts("py", BASE)], ignore_index=True)
    het = direction_heterogeneity(means, flutes=N).set_index("name")
    assert het.loc["Ktc", "directions"] == "px, py"
    assert het["q"].to_numpy() == pytest.approx(0.0, abs=1e-9)
    assert not het["disagree"].any()
    assert het.loc["Ktc", "value_px"] == pytest.approx(het.loc["Ktc", "value_py"], rel=1e-12)


def test_a_direction_with_another_ktc_is_found_and_q_is_as_by_hand():
    other = dict(BASE, Ktc=1200.0)
    means = pd.concat([_cuts("px", BASE), _cuts("py", other)], ignore_index=True)
    het = direction_heterogeneity(means, flutes=N).set_index("name")
    s = _ktc_standard_error()
    # two estimates 400 N/mm² apart with the same standard error: Q = 2 (200/s)²
    assert het.loc["Ktc", "value_py"] - het.loc["Ktc", "value_px"] == pytest.approx(400.0)
    assert het.loc["Ktc", "q"] == pytest.approx(2 * (200.0 / s) ** 2, rel=1e-9)
    assert het.loc["Ktc", "disagree"]
    assert het.loc["Ktc", "i2_pct"] == pytest.approx(100 * (1 - 1 / het.loc["Ktc", "q"]))
    assert not het.drop(index="Ktc")["disagree"].any()   # the others are the same


def test_too_few_identifying_directions_say_nothing():
    one_feed = _cuts("my", BASE).assign(feed_per_tooth_mm=0.003)
    assert direction_heterogeneity(pd.concat([_cuts("px", BASE), one_feed]), flutes=N) is None
    assert direction_heterogeneity(_cuts("px", BASE).drop(columns="direction")) is None
    # cuts left out of the fit (chatter) are left out here too
    out = _cuts("py", dict(BASE, Ktc=1200.0)).assign(in_fit=False)
    assert direction_heterogeneity(pd.concat([_cuts("px", BASE), out]), flutes=N) is None


def test_the_chapter_says_which_coefficients_the_directions_do_not_share():
    means = pd.concat([_cuts("px", BASE), _cuts("py", dict(BASE, Ktc=1200.0))],
                      ignore_index=True)
    found = Findings("forces")
    _directions(found, means, {"flutes": N}, 0.95)
    assert found.values()["verdict_coefficient_directions_agree"] == "fail"
    [line] = found.values()["coefficient_directions_disagree"]
    assert line.startswith("Ktc ") and "(px)" in line and "(py)" in line and "Q = " in line
    templates = load_templates("ch3_forces")
    assert "do not share" in render(templates["directions"], found)
    assert render(templates["directions_agree"], found) == ""
    same = Findings("forces")
    _directions(same, pd.concat([_cuts("px", BASE), _cuts("py", BASE)]), {"flutes": N}, 0.95)
    assert render(templates["directions"], same) == ""
    assert "agree within their scatter" in render(templates["directions_agree"], same)


def test_half_immersion_cuts_take_the_general_fit_per_direction():
    """Down-milling cuts at half immersion (entry 90°, exit 180°): each direction is identified
    by the general least squares; the same forces in both directions give the same estimates,
    and a direction whose forces are twice as large (every coefficient doubled) is found."""
    from robomill.forces.model import CuttingCoefficients, mean_milling_forces

    def cuts(direction, scale):
        k = CuttingCoefficients(*(scale * BASE[n] for n in
                                  ("Ktc", "Krc", "Kac", "Kte", "Kre", "Kae")))
        F = mean_milling_forces(FEEDS_MM, DEPTH_MM, k, flutes=N, entry_rad=np.pi / 2,
                                exit_rad=np.pi)
        F = F + np.outer(WIGGLE, [1.0, -1.0, 1.0])
        return pd.DataFrame({"direction": direction, "feed_per_tooth_mm": FEEDS_MM,
                             "depth_mm": DEPTH_MM, "in_fit": True, "flutes": N,
                             "entry_deg": 90.0, "exit_deg": 180.0, "F_feed_N": F[:, 0],
                             "F_cross_feed_N": F[:, 1], "F_axial_N": F[:, 2]})

    same = direction_heterogeneity(pd.concat([cuts("px", 1.0), cuts("py", 1.0)]))
    assert same["q"].to_numpy() == pytest.approx(0.0, abs=1e-9)
    assert not same["disagree"].any()
    het = direction_heterogeneity(pd.concat([cuts("px", 1.0), cuts("py", 2.0)])).set_index("name")
    assert het.loc["Ktc", "value_py"] == pytest.approx(2 * het.loc["Ktc", "value_px"], rel=0.05)
    assert het["disagree"].all()


def test_holm_by_hand():
    from robomill.forces.coefficients import holm_rejects

    # m = 4 finite: 0.001 ≤ 0.05/4, 0.012 ≤ 0.05/3, 0.03 > 0.05/2 stops; 0.04 not reached
    p = np.array([0.03, 0.001, np.nan, 0.012, 0.04])
    assert holm_rejects(p, 0.05).tolist() == [False, True, False, True, False]
    assert not holm_rejects(np.array([0.02, 0.03]), 0.01).any()


def test_directions_that_agree_are_rarely_flagged_as_a_family():
    """Three directions with the same coefficients and independent scatter (10 cuts each,
    5 feeds × 2 depths), 200 studies: the family of six tests flags at most about its level
    (5 %), where testing each coefficient alone at 5 % would flag far more often."""
    from robomill.forces.coefficients import direction_heterogeneity

    rng = np.random.default_rng(7)
    feeds = np.repeat([0.001, 0.002, 0.003, 0.004, 0.005], 2)
    depths = np.tile([0.25, 0.5], 5)
    flagged, any_alone = 0, 0
    for _ in range(200):
        parts = []
        for d in ("px", "py", "my"):
            c, a = feeds, depths
            na = N * a
            parts.append(pd.DataFrame({
                "direction": d, "feed_per_tooth_mm": c, "depth_mm": a, "in_fit": True,
                "F_feed_N": -na * (BASE["Krc"] * c / 4 + BASE["Kre"] / np.pi)
                + rng.normal(0, 0.05, c.size),
                "F_cross_feed_N": na * (BASE["Ktc"] * c / 4 + BASE["Kte"] / np.pi)
                + rng.normal(0, 0.05, c.size),
                "F_axial_N": na * (BASE["Kac"] * c / np.pi + BASE["Kae"] / 2)
                + rng.normal(0, 0.05, c.size)}))
        het = direction_heterogeneity(pd.concat(parts, ignore_index=True), flutes=N)
        flagged += bool(het["disagree"].any())
        any_alone += bool((het["p_value"] < 0.05).any())
    assert flagged / 200 <= 0.10
    assert any_alone / 200 >= 0.15
