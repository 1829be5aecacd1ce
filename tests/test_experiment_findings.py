"""Chapter 0's findings (robomill.experiment_findings) from hand-made cut tables whose feed
per tooth c = v / (N n), spindle and tooth-passing frequencies are worked out here by hand
(the planted truth), for a single-speed design in the thesis' layout, a spindle-speed series
of another design, and studies that lack cuts or a spindle speed."""

import numpy as np
import pandas as pd
import pytest

from robomill.experiment_findings import experiment_findings, thesis_layout_of
from robomill.findings import findings_from_dict, write_findings
from robomill.pipeline.design_tables import design_summary


def _thesis_like():
    """Two sets in the thesis' layout: set 1 at 1 and 3 mm/s, set 2 at 2 mm/s; 30 000 rpm,
    2 flutes → n = 500 Hz, N n = 1000 Hz, c = v / 1000 Hz: 1, 3 and 2 µm."""
    rows = [(s, g, d, v) for s, g, v in ((1, 1, 1.0), (1, 2, 3.0), (2, 1, 2.0))
            for d in ("py", "px", "my")]
    return pd.DataFrame({"cut": [f"s{s}_g{g}_{d}" for s, g, d, _ in rows],
                         "set": [r[0] for r in rows], "segment": [r[1] for r in rows],
                         "direction": [r[2] for r in rows],
                         "feed_mm_s": [r[3] for r in rows],
                         "depth_mm": [0.25 if r[0] == 1 else 0.5 for r in rows]})


EXPERIMENT = {"spindle_rpm": 30000, "flutes": 2}


def test_a_single_speed_design_in_the_thesis_layout():
    cuts = _thesis_like()
    v = experiment_findings(cuts, EXPERIMENT).values()
    assert v["n_cuts"] == 9 and v["has_cuts"] and v["missing"] == []
    assert v["thesis_layout"] and not v["thesis_study"]  # judged from the table
    assert (v["n_sets"], v["n_segments"], v["n_directions"]) == (2, 2, 3)
    assert v["directions"] == ["+Y", "+X", "−Y"]  # machining order, not the table's
    assert v["single_speed"] and v["spindle_rpm"] == 30000.0
    assert v["spindle_hz"] == pytest.approx(500.0) and v["tooth_passing_hz"] == pytest.approx(
        1000.0)
    assert v["feed_per_tooth_um_range"] == pytest.approx([1.0, 3.0])
    assert v["feed_mm_s_range"] == [1.0, 3.0] and v["depth_mm_values"] == [0.25, 0.5]
    assert v["flutes_values"] == [2]
    assert "design" not in v  # no design given: not stated
    assert v["ref_robot"] == "ABB IRB 1600-6/1.45" and v["ref_spindle_rpm"] == 28000.0


def test_a_spindle_speed_series_of_another_design():
    """Cuts a, b, c at 12 000, 18 000 (the experiment's) and 24 000 rpm with 3 flutes and a
    4-flute cut d: n = 200, 300, 400, 300 Hz; N n = 600, 900, 1200, 1200 Hz;
    c = 2/600, 6/900, 2/1200, 3/1200 mm = 3.333, 6.667, 1.667, 2.5 µm."""
    cuts = pd.DataFrame({"cut": ["a", "b", "c", "d"], "direction": ["mx", "mx", None, "mx"],
                         "direction_deg": [np.nan, np.nan, 45.0, np.nan],
                         "feed_mm_s": [2.0, 6.0, 2.0, 3.0], "depth_mm": [0.5] * 4,
                         "spindle_rpm": [12000.0, np.nan, 24000.0, np.nan],
                         "flutes": [np.nan, np.nan, np.nan, 4.0]})
    design = {"design": "4 cuts", "grouping": ["spindle_rpm", "direction"],
              "dependent": ["feed_mm_s"],
              "groups": [{"label": "12 k", "cuts": ["a"]}, {"label": "18 k", "cuts": ["b", "d"]},
                         {"label": "24 k", "cuts": ["c"]}]}
    v = experiment_findings(cuts, {"spindle_rpm": 18000, "flutes": 3}, design=design).values()
    assert not v["thesis_layout"] and "n_sets" not in v and "directions" not in v
    assert not v["single_speed"] and v["spindle_rpm"] is None and v["spindle_hz"] is None
    assert v["spindle_rpm_range"] == [12000.0, 24000.0]
    assert v["spindle_hz_range"] == pytest.approx([200.0, 400.0])
    assert v["tooth_passing_hz_range"] == pytest.approx([600.0, 1200.0])
    assert v["feed_per_tooth_um_range"] == pytest.approx([1000 / 600, 6000 / 900])
    assert v["flutes_values"] == [3, 4]
    assert v["group_by"] == "spindle_rpm" and v["grouping"] == ["spindle_rpm", "direction"]
    assert [g["label"] for g in v["groups"]] == ["12 k", "18 k", "24 k"]
    assert v["groups"][0]["feed_per_tooth_um"] == pytest.approx([10 / 3, 10 / 3])
    assert v["groups"][1]["feed_per_tooth_um"] == pytest.approx([2.5, 20 / 3])
    assert v["groups"][1]["tooth_passing_hz"] == pytest.approx([900.0, 1200.0])
    assert v["groups"][2]["tooth_passing_hz"] == pytest.approx([1200.0, 1200.0])


def test_the_design_as_the_rule_describes_it():
    """design_summary (the rule's tooling) groups a speed series by its spindle speed."""
    cuts = pd.DataFrame({"cut": ["a", "b", "c"], "direction": ["mx"] * 3,
                         "feed_mm_s": [2.0, 2.0, 2.0], "depth_mm": [0.5] * 3,
                         "spindle_rpm": [12000.0, np.nan, 24000.0]})
    exp = {"spindle_rpm": 18000, "flutes": 3}
    v = experiment_findings(cuts, exp, design=design_summary(cuts, exp)).values()
    assert v["grouping"] == ["spindle_rpm"] and v["design"].startswith("3 cuts: 3 spindle")
    assert [g["label"] for g in v["groups"]] == ["12000 rpm", "18000 rpm", "24000 rpm"]
    assert [g["feed_per_tooth_um"][0] for g in v["groups"]] == pytest.approx(
        [2000 / 600, 2000 / 900, 2000 / 1200])


def test_the_thesis_flags_come_from_the_rule_when_given():
    cuts = _thesis_like()
    v = experiment_findings(cuts, EXPERIMENT, thesis_design=False).values()
    assert not v["thesis_layout"] and "n_sets" not in v
    v = experiment_findings(cuts, EXPERIMENT, thesis_design=True, thesis_study=True).values()
    assert v["thesis_layout"] and v["thesis_study"]
    own = cuts.assign(spindle_rpm=[np.nan] * 8 + [20000.0])  # one cut with its own speed
    assert thesis_layout_of(cuts) and not thesis_layout_of(own)
    assert not thesis_layout_of(cuts.assign(cut=["x"] + list(cuts["cut"][1:])))


def test_a_study_without_cuts_or_spindle_speed_says_what_is_missing(tmp_path):
    v = experiment_findings(_thesis_like().iloc[:0], {}).values()
    assert v["n_cuts"] == 0 and not v["has_cuts"] and v["missing"] == []
    assert "feed_per_tooth_um_range" not in v and v["ref_robot"]
    found = experiment_findings(_thesis_like(), {"flutes": 2})
    v = found.values()
    assert v["missing"] == ["spindle_rpm"] and "feed_per_tooth_um_range" not in v
    assert v["n_cuts"] == 9 and v["feed_mm_s_range"] == [1.0, 3.0]
    write_findings(found, tmp_path / "findings.yaml")  # plain YAML, read back alike
    import yaml

    back = findings_from_dict(yaml.safe_load((tmp_path / "findings.yaml").read_text()))
    assert back.values() == v
