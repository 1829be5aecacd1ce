"""Per-cut tables grouped by what varies, and the thesis gate (robomill.pipeline.design_tables,
issue 20): the thesis design, a spindle-speed series, one cut, a design where nothing varies."""

import pandas as pd
import pytest

from robomill.experiment import cuts_table, plan_cuts
from robomill.pipeline.design_tables import (
    describe_design,
    design_factors,
    direction_label,
    per_cut_table,
    thesis_gate,
    with_design,
)

THESIS_EXP = {"spindle_rpm": 28000, "flutes": 2}


def thesis_cuts():
    sets = [{"set": s, "depth_mm": d, "feeds_mm_s": [1, 2, 4, 8, 10]}
            for s, d in ((1, 0.25), (2, 0.5), (3, 1.0))]
    return cuts_table(plan_cuts(sets), 28000, 2)


def spindle_series():
    """The other_cell example's design: 3 speeds along −X at 2 mm/s, one at 6 mm/s, two 45°
    cuts at 24 000 rpm; half-immersion down milling, 3 flutes."""
    rows = [("n12k_mx_v2", "mx", None, 12000, 2.0), ("n18k_mx_v2", "mx", None, None, 2.0),
            ("n24k_mx_v2", "mx", None, 24000, 2.0), ("n18k_mx_v6", "mx", None, None, 6.0),
            ("n24k_d45_v2", None, 45.0, 24000, 2.0), ("n24k_d45_v6", None, 45.0, 24000, 6.0)]
    return pd.DataFrame([{"cut": c, "direction": d, "direction_deg": g, "spindle_rpm": n,
                          "feed_mm_s": v, "depth_mm": 0.5, "radial_immersion": 0.5,
                          "milling": "down"} for c, d, g, n, v in rows])


OTHER_EXP = {"spindle_rpm": 18000, "flutes": 3, "tool_diameter_mm": 8.0}


def test_thesis_design_groups_by_set_segment_direction():
    d = design_factors(thesis_cuts(), THESIS_EXP)
    assert d.n_cuts == 45
    assert d.grouping == ["set", "segment", "direction"]
    assert d.dependent == ["depth_mm", "feed_mm_s"]  # depth by set, feed by segment
    assert d.constant == {"spindle_rpm": 28000, "flutes": 2, "radial_immersion": 1.0,
                          "milling": "slot"}
    assert d.levels["direction"] == ["+X", "+Y", "−Y"]


def test_thesis_description_reproduces_sets_by_segments():
    text = describe_design(thesis_cuts(), THESIS_EXP)
    assert text.startswith("45 cuts: 3 sets × 5 segments × 3 directions (")
    assert "depth by set" in text and "feed by set and segment" in text
    assert "combinations" not in text  # a full factorial
    assert text.endswith("constant: 28000 rpm, 2 flutes, a_e/D 1, slotting")


def test_thesis_per_cut_table_is_sets_by_segments():
    cuts = thesis_cuts()
    res = cuts[["cut"]].assign(rms_um=range(45))
    tab = per_cut_table(res, ["rms_um"], cuts, THESIS_EXP)
    assert list(tab.index.names) == ["set", "segment", "direction"]
    assert list(tab.columns) == ["cut", "depth_mm", "feed_mm_s", "rms_um"]
    assert tab.loc[(2, 4, "+Y"), "cut"] == "s2_g4_py"
    assert tab.loc[(2, 4, "+Y"), "rms_um"] == int(cuts.index[cuts.cut == "s2_g4_py"][0])
    assert tab.loc[(3, 5, "−Y"), "feed_mm_s"] == 10 and tab.loc[(3, 5, "−Y"), "depth_mm"] == 1


def test_spindle_series_groups_by_speed_then_direction_then_feed():
    cuts = spindle_series()
    d = design_factors(cuts, OTHER_EXP)
    assert d.grouping == ["spindle_rpm", "direction", "feed_mm_s"]
    assert d.dependent == []
    assert d.levels["spindle_rpm"] == [12000, 18000, 24000]  # 18000 from the experiment
    assert d.levels["direction"] == ["45°", "−X"]
    assert d.constant == {"flutes": 3, "tool_diameter_mm": 8.0, "radial_immersion": 0.5,
                          "milling": "down", "depth_mm": 0.5}
    text = describe_design(cuts, OTHER_EXP)
    assert text == ("6 cuts: 3 spindle speeds × 2 directions × 2 feeds (6 of the 12 "
                    "combinations); constant: 3 flutes, tool Ø 8 mm, a_e/D 0.5, down milling, "
                    "depth 0.5 mm")
    tab = per_cut_table(cuts[["cut"]].assign(Ra_um=[1, 2, 3, 4, 5, 6]), ["Ra_um"], cuts,
                        OTHER_EXP)
    assert list(tab.index.names) == ["spindle_rpm", "direction", "feed_mm_s"]
    assert list(tab["cut"]) == ["n12k_mx_v2", "n18k_mx_v2", "n18k_mx_v6", "n24k_d45_v2",
                                "n24k_d45_v6", "n24k_mx_v2"]
    assert list(tab["Ra_um"]) == [1, 2, 4, 5, 6, 3]


def test_a_single_cut_has_no_grouping_factor():
    cuts = spindle_series().iloc[[4]]
    d = design_factors(cuts, OTHER_EXP)
    assert d.grouping == [] and d.dependent == []
    assert d.constant["direction"] == "45°" and d.constant["spindle_rpm"] == 24000
    assert describe_design(cuts, OTHER_EXP).startswith("1 cut; constant: 24000 rpm, 3 flutes")
    tab = per_cut_table(cuts[["cut"]].assign(x=[7.0]), ["x"], cuts, OTHER_EXP)
    assert list(tab.index) == ["n24k_d45_v2"] and list(tab.columns) == ["x"]


def test_repeats_where_nothing_varies_are_listed_by_cut():
    cuts = pd.DataFrame({"cut": ["r3", "r1", "r2"], "direction": "px", "feed_mm_s": 4.0,
                         "depth_mm": 0.5})
    d = design_factors(cuts)
    assert d.grouping == [] and d.levels == {}
    assert d.constant == {"direction": "+X", "depth_mm": 0.5, "feed_mm_s": 4.0}
    assert describe_design(cuts) == ("3 cuts; constant: +X, depth 0.5 mm, feed 4 mm/s")
    tab = per_cut_table(cuts.assign(v=[3, 1, 2]), ["v"])
    assert list(tab.index) == ["r1", "r2", "r3"] and list(tab["v"]) == [1, 2, 3]


def test_experiment_defaults_fill_missing_process_keys():
    cuts = spindle_series()
    filled = with_design(cuts, OTHER_EXP)
    assert list(filled["spindle_rpm"]) == [12000, 18000, 24000, 18000, 24000, 24000]
    assert list(filled["direction_deg"]) == [180.0, 180.0, 180.0, 180.0, 45.0, 45.0]
    assert with_design(filled, OTHER_EXP)["direction"].tolist() == filled["direction"].tolist()
    slot = with_design(pd.DataFrame({"cut": ["a"], "direction": ["py"], "feed_mm_s": [1.0]}),
                       THESIS_EXP)
    assert slot.loc[0, "radial_immersion"] == 1.0 and slot.loc[0, "milling"] == "slot"


def test_artefact_path_directions_are_labelled():
    assert direction_label("45 deg") == "45°" and direction_label("mx") == "−X"
    t = with_design(pd.DataFrame({"cut": ["a", "b"], "direction": ["45 deg", "mx"],
                                  "feed_mm_s": [2.0, 2.0]}))
    assert list(t["direction"]) == ["45°", "−X"] and list(t["direction_deg"]) == [45.0, 180.0]


def test_bad_inputs():
    with pytest.raises(ValueError, match="neither a direction name"):
        direction_label(None, None)
    cuts = spindle_series()
    with pytest.raises(KeyError, match="no column"):
        per_cut_table(cuts[["cut"]], ["Ra_um"], cuts)


def test_thesis_gate():
    assert thesis_gate(True)(" (thesis: 13 Hz)") == " (thesis: 13 Hz)"
    assert thesis_gate(None)("x") == "x"  # a notebook run without the parameter
    assert thesis_gate(False)(" (thesis: 13 Hz)") == ""
    assert thesis_gate(False).shown is False


def test_dominant_wavelengths_take_the_largest_peak_per_band():
    from robomill.pipeline.design_tables import dominant_wavelengths

    peaks = pd.DataFrame({"cut": ["a", "a", "a", "b"],
                          "band": ["waviness", "waviness", "roughness", "waviness"],
                          "f_spatial_per_mm": [0.4, 0.5, 8.0, 0.25],
                          "amplitude_um": [1.0, 2.0, 0.1, 3.0]})
    out = dominant_wavelengths(peaks)
    assert out.loc["a", "waviness_wavelength_mm"] == pytest.approx(2.0)
    assert out.loc["a", "roughness_wavelength_mm"] == pytest.approx(0.125)
    assert out.loc["b", "waviness_wavelength_mm"] == pytest.approx(4.0)
    assert pd.isna(out.loc["b", "roughness_wavelength_mm"])


def test_span():
    from robomill.pipeline.design_tables import span

    assert span([3.333, 3.3331]) == "3.33"
    assert span([1.667, 6.667]) == "1.67–6.67"
    assert span([600, 1200], ".0f") == "600–1200"
    assert span([]) == "none"
    assert span([-0.88, -0.66]) == "-0.88 to -0.66"
