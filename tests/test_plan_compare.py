"""Chapter 7's comparison findings: how much the rotation about the tool axis changes a pose
prediction (planted pose maps, spreads computed by hand), and the sentences that follow the
comparison table's values."""

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from robomill.pipeline.prose import Prose, load_templates
from robomill.plan.compare import comparison_table, comparison_values, rotation_effect_pct


def _pose_map(k_normal, reachable=None):
    k = np.asarray(k_normal, float)[..., None]  # placement × rotation × direction
    dims = ("placement", "rotation", "direction")
    ones = np.ones_like(k)
    return xr.Dataset({"k_normal_N_m": (dims, k), "k_axial_N_m": (dims, 5e6 * ones),
                       "a_crit_best_low_mm": (dims, 0.3 * ones),
                       "reachable": (dims, np.ones(k.shape, bool) if reachable is None
                                     else np.asarray(reachable)[..., None])},
                      coords={"rotation": [0.0, 30.0, 60.0]})


def test_the_rotation_effect_is_the_largest_spread_over_rotations():
    # placement 0: 100, 110, 120 → (120 − 100)/120 = 16.67 %; placement 1 unchanged
    pmap = _pose_map([[100.0, 110.0, 120.0], [200.0, 200.0, 200.0]])
    assert rotation_effect_pct(pmap) == pytest.approx(100 * 20 / 120)
    assert rotation_effect_pct(_pose_map([[1.0, 1.0, 1.0]])) == 0.0
    # an unreachable pose does not count, however far off its (meaningless) value is
    far = _pose_map([[100.0, 100.0, 1.0]], reachable=[[True, True, False]])
    assert rotation_effect_pct(far) == 0.0
    assert np.isnan(rotation_effect_pct(_pose_map([[1.0, 2.0, 3.0]],
                                                 reachable=[[False] * 3])))


def _comparison(study_feasible, rotation_effect, rotations=12.0, verdicts=("", "", "")):
    plan = pd.DataFrame({"cut": ["plan_01", "plan_02"], "mrr_mm3_s": [30.0, 20.0]})
    study = pd.DataFrame({"cut": ["s1", "s2", "s3"], "mrr_mm3_s": [15.0, 12.0, 40.0],
                          "feasible": study_feasible, "verdict": list(verdicts)})
    return comparison_table(plan, study, rotation_effect, rotations).set_index("quantity")


def test_chapter_7_states_the_ratio_and_the_rotation_effect_from_the_comparison():
    say = Prose(load_templates("ch7"), comparison_values(_comparison([True, True, False], 0.0)))
    text = " ".join(say("comparison", "rotation_effect").split())
    assert "plan's best cut (plan_01) removes 30 mm³/s" in text
    assert "3 cuts that meet the same constraints (2 do, s1) removes 15 mm³/s" in text
    assert "a ratio of **2**" in text
    assert "changes no predicted stiffness" in text  # 0 %: the rotation is a tie-break
    say = Prose(load_templates("ch7"),
                comparison_values(_comparison([False, False, False], 16.7)))
    text = " ".join(say("comparison", "rotation_effect").split())
    # never NaN: without a verdict or a feasible study cut, the best of them all
    assert "none of the study's 3 cuts has a verdict or meets them" in text
    assert "(s3) removes 40 mm³/s: a ratio of **0.75**" in text
    assert "by at most 16.7 %" in text and "{" not in text
    # with verdicts: the best cut judged stable, whatever the constraints say of it
    table = _comparison([True, False, False], 0.0, verdicts=("stable", "stable", "chatter"))
    assert table.loc["mrr_ratio", "value"] == 2.0 and table.loc["mrr_ratio", "cut"] == \
        "judged_stable"
    text = " ".join(Prose(load_templates("ch7"), comparison_values(table))("comparison")
                    .split())
    assert "judged stable from their own recordings (2 are, s1) removes 15 mm³/s" in text


def test_one_allowed_rotation_is_not_an_effect_of_zero():
    """A request with one redundancy angle (the default when it lists none) compares nothing:
    the effect is not computed, and the chapter says why instead of "changes no stiffness"."""
    pmap = _pose_map([[100.0, 110.0, 120.0]]).isel(rotation=[0])
    assert np.isnan(rotation_effect_pct(pmap))
    table = _comparison([True, True, False], rotation_effect_pct(pmap), pmap.sizes["rotation"])
    assert table.loc["rotations", "value"] == 1.0
    assert np.isnan(table.loc["rotation_effect_pct", "value"])


@pytest.mark.parametrize("rotations, says", [
    (1.0, "No rotation about the tool axis was allowed"),
    (12.0, "was not computed (no reachable pose"),
    (float("nan"), "was not computed (no reachable pose")])  # a table without the count
def test_chapter_7_says_what_a_nan_rotation_effect_means(rotations, says):
    table = _comparison([True, True, False], np.nan, rotations)
    if rotations != rotations:
        table = table.drop(index="rotations")
    values = comparison_values(table)
    assert values["rotation_effect_pct"] is None
    text = " ".join(Prose(load_templates("ch7"), values)("rotation_effect").split())
    assert says in text
    assert "changes no predicted" not in text and "at most" not in text and "{" not in text
    assert "a ratio of **2**" in Prose(load_templates("ch7"), values)("comparison")
