"""The experiment plan and its derived quantities (SPEC §0)."""

import pytest

from robomill.experiment import feed_per_tooth_mm, plan_cuts, tooth_passing_hz
from robomill.io.synthetic_layout import synthetic_cuts


def test_thesis_plan_has_45_cuts(config):
    cuts = synthetic_cuts(config)
    assert len(cuts) == 45
    assert len({c.id for c in cuts}) == 45
    assert [c.direction for c in cuts[:3]] == ["py", "px", "my"]
    s3 = [c for c in cuts if c.set == 3 and c.direction == "px"]
    assert [c.feed_mm_s for c in s3] == [2, 4, 6, 8, 10]


def test_feed_per_tooth_matches_thesis():
    assert tooth_passing_hz(28000, 2) == pytest.approx(933.33, abs=0.01)
    assert 1e3 * feed_per_tooth_mm(1.0, 28000, 2) == pytest.approx(1.07, abs=0.005)
    assert 1e3 * feed_per_tooth_mm(10.0, 28000, 2) == pytest.approx(10.7, abs=0.05)


def test_more_sets_cycle_the_thesis_sets(config):
    cuts = plan_cuts(config["experiment"]["sets"], 9)
    assert len(cuts) == 9 * 15
    s7 = [c for c in cuts if c.set == 7]
    assert {c.depth_mm for c in s7} == {0.25} and s7[0].feed_mm_s == 1.0


def test_missing_data_names_what_a_chapter_lacks():
    from robomill.experiment import Cut, cuts_table, missing_data

    files = [{"kind": "force"}, {"kind": "cell"}]
    cut = [Cut("s1_g1_px", 1, 1, "px", 1.0, 0.25)]
    assert missing_data(files, cut, ("force",)) is None
    assert missing_data(files, cut, ()) is None
    assert missing_data(files, cut, ("impact",)) == "no impact files in manifest.yaml"
    assert missing_data(files, [], ("cuts", "force")) == "no cuts in manifest.yaml"
    assert (missing_data(files, cut, ("robot", "stiffness"))
            == "no robot files and no stiffness files in manifest.yaml")
    empty = cuts_table([], 28000, 2)  # a folder without cuts: no rows, the same columns
    assert len(empty) == 0 and list(empty.columns) == list(cuts_table(cut, 28000, 2).columns)
