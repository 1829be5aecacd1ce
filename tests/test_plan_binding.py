"""The production plan's binding interval (robomill.plan.binding) and what a learn round does to
it: on a planted cutting law, the cuts a learn round adds narrow the binding force interval
towards the planted scatter of a new cut."""

from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from robomill.forces.model import CuttingCoefficients, mean_milling_forces
from robomill.forces.prediction import fit_force_regression, predict_mean_force
from robomill.plan.binding import binding_interval, binding_table, interval_names


def _candidates():
    """Two placements × two speeds; the chosen cut at placement 1, 20 000 rpm."""
    dims = ("placement", "spindle_rpm")
    coords = {"placement": [0, 1], "spindle_rpm": [10000.0, 20000.0]}

    def v(values):
        return xr.DataArray(np.array(values, float), dims=dims, coords=coords)
    return xr.Dataset({
        "stability_margin_low": v([[0.5, 0.5], [0.5, 0.30]]),
        "stability_margin_high": v([[0.9, 0.9], [0.9, 0.70]]),
        "force_low_N": v([[10, 10], [10, 70.0]]),
        "force_high_N": v([[20, 20], [20, 90.0]]),
    })


ROW = pd.Series({"cut": "P1", "i_placement": 1, "spindle_rpm": 20000.0})


def test_the_binding_interval_is_the_prediction_closest_to_its_limit():
    req = SimpleNamespace(constraints={"min_stability_margin": 0.2, "max_force_N": 100.0,
                                       "max_deflection_normal_um": None})
    b = binding_interval(_candidates(), req, ROW)
    # margin: (0.30 − 0.2)/0.2 = 0.5 of slack; force: (100 − 90)/100 = 0.1: the force binds
    assert b["constraint"] == "max_force_N"
    assert b["slack"] == pytest.approx(0.1)
    assert (b["low"], b["high"], b["width"]) == pytest.approx((70.0, 90.0, 20.0))
    # measured on a given constraint (an earlier plan's): the margin's interval at that cut
    m = binding_interval(_candidates(), req, ROW, "min_stability_margin")
    assert (m["low"], m["high"], m["width"]) == pytest.approx((0.30, 0.70, 0.40))
    assert m["slack"] == pytest.approx(0.5)
    assert interval_names("deflection_normal_high_um") == ("deflection_normal_low_um",
                                                            "deflection_normal_high_um")


def test_the_binding_prediction_is_the_one_a_deeper_cut_breaks():
    """At the chosen depth the force is closer to its limit (slack 0.1 against the margin's
    0.5), but the next depth of the grid breaks the margin (0.15 < 0.2) and not the force
    (95 < 100): the margin binds the removal rate."""
    coords = {"placement": [0, 1], "depth_mm": [0.2, 0.3]}

    def v(values):
        return xr.DataArray(np.array(values, float), dims=("placement", "depth_mm"),
                            coords=coords)
    ds = xr.Dataset({"stability_margin_low": v([[1, 1], [0.30, 0.15]]),
                     "stability_margin_high": v([[2, 2], [0.70, 0.40]]),
                     "force_low_N": v([[1, 1], [70.0, 80.0]]),
                     "force_high_N": v([[2, 2], [90.0, 95.0]])})
    req = SimpleNamespace(constraints={"min_stability_margin": 0.2, "max_force_N": 100.0})
    row = pd.Series({"cut": "P1", "i_placement": 1, "depth_mm": 0.2})
    b = binding_interval(ds, req, row)
    assert b["constraint"] == "min_stability_margin" and b["binds"] == "depth_mm=0.3"
    assert (b["low"], b["high"]) == pytest.approx((0.30, 0.70))
    # at the grid's largest depth nothing larger is cut: the least slack binds (the margin's
    # (0.15 − 0.2)/0.2 = −0.25 against the force's 0.05)
    top = binding_interval(ds, req, pd.Series({"cut": "P1", "i_placement": 1,
                                               "depth_mm": 0.3}))
    assert top["constraint"] == "min_stability_margin" and top["binds"] == "closest to its limit"
    assert top["slack"] == pytest.approx(-0.25)


def test_the_narrowing_is_stated_only_on_the_same_prediction():
    before = binding_table({"constraint": "max_force_N", "width": 40.0, "low": 60.0,
                            "high": 100.0}, "production", 45, 1)
    after = binding_table({"constraint": "max_force_N", "width": 10.0, "low": 75.0,
                           "high": 85.0, "width_same_cut": 16.0}, "production", 51, 2, before)
    assert list(after["when"]) == ["before", "now"]
    # measured at the earlier binding cut (width 16 there now), not at the new binding cut
    assert after["narrowing"].iloc[-1] == pytest.approx(1 - 16.0 / 40.0)
    assert after["raw_folders"].iloc[-1] == 2 and after["study_cuts"].iloc[-1] == 51
    other = binding_table({"constraint": "min_stability_margin", "width": 0.1}, "production",
                          51, 2, before)
    assert np.isnan(other["narrowing"].iloc[-1])


def test_a_learn_round_narrows_the_binding_force_interval_to_the_planted_scatter():
    """Planted law (eq. 2.25 with known coefficients) and planted scatter σ per component.
    The study cut only small chip loads; the production plan's binding cut is at a chip load
    five times the study's largest. The learn round's cuts at and between them (the chip load
    that separates edge and shearing forces) join the identification. Truths from the plant,
    not the estimator: the planted mean lies inside both intervals; after the round the
    interval is no wider than 1.5× the ideal 2·z·σ of a new cut about a known law, and
    narrower than before by at least half."""
    truth = CuttingCoefficients(Ktc=700.0, Krc=250.0, Kac=150.0, Kte=25.0, Kre=20.0, Kae=5.0)
    sigma_N, depth_mm, c0 = 2.0, 1.0, 0.06
    rng = np.random.default_rng(7)

    def measure(c):
        c = np.asarray(c, float)
        F = mean_milling_forces(c, depth_mm, truth, flutes=2)
        return F + rng.normal(0.0, sigma_N, F.shape)

    study_c = np.repeat([0.010, 0.011, 0.012], 3)
    learn_c = np.repeat([0.035, 0.06], 4)

    def width(cs, forces):
        reg = fit_force_regression(cs, depth_mm, forces, flutes=2)
        p = predict_mean_force(reg, c0, depth_mm, flutes=2)
        return float(p["low_N"]), float(p["high_N"])

    F_study = measure(study_c)
    lo_b, hi_b = width(study_c, F_study)
    lo_a, hi_a = width(np.concatenate([study_c, learn_c]),
                       np.vstack([F_study, measure(learn_c)]))
    planted = float(np.linalg.norm(mean_milling_forces(c0, depth_mm, truth, flutes=2)))
    assert lo_b <= planted <= hi_b and lo_a <= planted <= hi_a
    ideal = 2 * 1.96 * sigma_N
    assert hi_a - lo_a <= 1.5 * ideal
    narrowing = binding_table({"constraint": "max_force_N", "width": hi_a - lo_a,
                               "width_same_cut": hi_a - lo_a},
                              "production", 17, 2,
                              binding_table({"constraint": "max_force_N",
                                             "width": hi_b - lo_b}, "production", 9, 1)
                              )["narrowing"].iloc[-1]
    assert narrowing >= 0.5
    # control: as many more cuts at the study's own chip loads do not get there
    lo_c, hi_c = width(np.concatenate([study_c, study_c[:8]]),
                       np.vstack([F_study, measure(study_c[:8])]))
    assert hi_c - lo_c > 1.5 * ideal


def test_the_narrowing_is_measured_at_the_earlier_binding_cut():
    """The earlier plan bound at placement 1, 20 000 rpm (width 0.40 of the margin); the new
    plan's own binding cut is elsewhere. The narrowing reads the new candidates at the earlier
    cut: there the margin's interval is [0.35, 0.55] (width 0.20): 50 %."""
    from robomill.plan.binding import same_cut_width

    req = SimpleNamespace(constraints={"min_stability_margin": 0.2, "max_force_N": 100.0})
    b0 = binding_interval(_candidates(), req, ROW, "min_stability_margin")
    assert (b0["i_placement"], b0["spindle_rpm"]) == (1, 20000.0)
    before = binding_table(b0, "learn", 45, 1)
    after_ds = _candidates()
    after_ds["stability_margin_low"][1, 1] = 0.35
    after_ds["stability_margin_high"][1, 1] = 0.55
    w = same_cut_width(after_ds, req, before)
    assert w == pytest.approx(0.20)
    # as read back from binding.csv (6 significant digits) the point is the grid's
    rounded = before.assign(spindle_rpm=before["spindle_rpm"] * (1 + 3e-7))
    assert same_cut_width(after_ds, req, rounded) == pytest.approx(0.20)
    new_cut = binding_interval(after_ds, req, pd.Series({"cut": "P9", "i_placement": 0,
                                                         "spindle_rpm": 10000.0}),
                               "min_stability_margin")
    table = binding_table({**new_cut, "width_same_cut": w}, "production", 49, 2, before)
    assert table["narrowing"].iloc[-1] == pytest.approx(0.5)
    # the earlier cut's speed is not on another request's grid: no narrowing stated
    other = after_ds.assign_coords(spindle_rpm=[11000.0, 21000.0])
    assert np.isnan(same_cut_width(other, req, before))


def test_chapter_7_states_before_after_and_the_narrowing():
    from pathlib import Path

    from robomill.pipeline.prose import Prose, load_templates
    from robomill.plan.binding import binding_values

    row = {"cut": "P1", "prediction": "mean cutting force [N]", "limit": 100.0}
    before = binding_table({**row, "constraint": "max_force_N", "low": 60.0, "high": 100.0,
                            "width": 40.0}, "production", 45, 1)
    after = binding_table({**row, "constraint": "max_force_N", "low": 75.0, "high": 85.0,
                           "width": 10.0, "width_same_cut": 10.0}, "production", 51, 2, before)
    templates = load_templates("ch7", Path("src/robomill/data/templates/ch7.yaml"))
    text = Prose(templates, binding_values(after))("binding")
    assert "[60, 100] (width 40)" in text and "width 10 at that cut" in text
    assert "cut P1 has it in [75, 85] (width 10)" in text
    assert "**75 %**" in text and "51 cuts from 2 raw folders" in text
    alone = Prose(templates, binding_values(before))("binding")
    assert "[60, 100] (width 40, limit 100)" in alone and "narrowed" not in alone


def test_planned_ids_number_on_after_an_earlier_plans_cuts_in_the_study():
    from robomill.plan.make import after_study_ids

    assert after_study_ids(["plan_01", "plan_02"], ["S1", "S2"]) == ["plan_01", "plan_02"]
    assert after_study_ids(["plan_01", "plan_02"], ["S1", "plan_01", "plan_04"]) == [
        "plan_05", "plan_06"]


def test_the_stability_interval_at_the_binding_cut_is_stated_beside_another_binding():
    """The force binds; the critical depth's interval at the same cut is kept beside it
    (before [4, 20] mm) and measured again at the earlier binding cut after the round
    ([6, 12] mm there: 62.5 % narrower), whatever the new plan's own binding cut."""
    from pathlib import Path

    from robomill.pipeline.prose import Prose, load_templates
    from robomill.plan.binding import binding_values, same_cut_stability_width

    def with_a_crit(lo, hi):
        ds = _candidates()
        dims = ("placement", "spindle_rpm")
        ds["a_crit_low_mm"] = (dims, np.array(lo, float))
        ds["a_crit_high_mm"] = (dims, np.array(hi, float))
        return ds

    req = SimpleNamespace(constraints={"min_stability_margin": 0.2, "max_force_N": 100.0})
    before_ds = with_a_crit([[1, 1], [1, 4.0]], [[2, 2], [2, 20.0]])
    b0 = binding_interval(before_ds, req, ROW)
    assert b0["constraint"] == "max_force_N"
    assert (b0["a_crit_low_mm"], b0["a_crit_high_mm"], b0["a_crit_width_mm"]) == (4, 20, 16)
    before = binding_table(b0, "learn", 45, 1)
    after_ds = with_a_crit([[1, 1], [1, 6.0]], [[3, 2], [2, 12.0]])
    w = same_cut_stability_width(after_ds, req, before)
    assert w == pytest.approx(6.0)
    new_cut = binding_interval(after_ds, req, pd.Series({"cut": "P9", "i_placement": 0,
                                                         "spindle_rpm": 10000.0}),
                               "max_force_N")
    assert new_cut["a_crit_width_mm"] == pytest.approx(2.0)   # the new cut's own: not used
    table = binding_table({**new_cut, "width_same_cut": 10.0, "a_crit_width_same_cut_mm": w},
                          "production", 49, 2, before)
    assert table["a_crit_narrowing"].iloc[-1] == pytest.approx(1 - 6.0 / 16.0)
    assert np.isnan(table["a_crit_narrowing"].iloc[0])
    templates = load_templates("ch7", Path("src/robomill/data/templates/ch7.yaml"))
    text = Prose(templates, binding_values(table))("binding_stability")
    assert "[4, 20] mm (width 16 mm)" in text and "width 6 mm at the same cut" in text
    assert "**62.5 %**" in text and "not at the mean cutting force" in text
    # no earlier plan: nothing said about a narrowing
    assert Prose(templates, binding_values(before))("binding_stability") == ""
