"""One study channel: chapter 4 takes each cut's own speed, depth, direction and tool from the
study (``results/ingest/study.yaml`` through :func:`robomill.study.read_study`), never from cut
ids or from the experiment's one speed. A free design (ids ``A7``, ``slot-3b``, per-cut
spindle speeds, directions in degrees) gets chapter 4's lobes, recommendations and findings
with every per-cut value present and each cut at the speed it was made at."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from robomill.chatter.findings import chatter_findings
from robomill.chatter.slot_lobes import study_lobes, study_slots
from robomill.chatter.tables import coupling_table
from robomill.io.manifest import parse_manifest
from robomill.study import read_study, write_study

#: a free design: ids that say nothing, speeds set per cut, one direction by name and three
#: by angle (two cuts share 45°), one cut with the experiment's speed
CUTS = [
    {"id": "A7", "direction_deg": 45.0, "feed_mm_s": 2.0, "depth_mm": 0.3,
     "spindle_rpm": 9000},
    {"id": "slot-3b", "direction_deg": 45.0, "feed_mm_s": 2.0, "depth_mm": 0.6,
     "spindle_rpm": 12000},
    {"id": "q.1", "direction_deg": 200.0, "feed_mm_s": 1.5, "depth_mm": 0.4},
    {"id": "Z", "direction": "py", "feed_mm_s": 1.0, "depth_mm": 0.2, "spindle_rpm": 7500},
]
EXPERIMENT = {"spindle_rpm": 10000, "flutes": 3, "tool_diameter_mm": 8.0,
              "cut_length_mm": 30.0}


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    folder = tmp_path_factory.mktemp("study")
    manifest = parse_manifest({"experiment": EXPERIMENT, "cuts": CUTS, "files": []},
                              folder / "manifest.yaml", require_sha256=False)
    return read_study(write_study(manifest, folder / "study.yaml"))


def test_the_study_gives_each_cut_its_own_process(study):
    by_id = {c.id: c for c in study.cuts}
    assert by_id["A7"].spindle_rpm == 9000 and by_id["slot-3b"].spindle_rpm == 12000
    assert by_id["q.1"].spindle_rpm == 10000  # the experiment's
    assert by_id["A7"].direction == "d45" and by_id["Z"].direction == "py"
    assert by_id["A7"].feed_xy == pytest.approx((math.sqrt(0.5), math.sqrt(0.5)))
    assert by_id["q.1"].feed_xy == pytest.approx((math.cos(math.radians(200)),
                                                  math.sin(math.radians(200))))
    assert all(c.flutes == 3 for c in study.cuts)
    slots = study_slots(study)
    # by angle: 45°, 90° (py), 200°; the two 45° cuts are one slot
    assert [s.name for s in slots] == ["d45", "py", "d200"]
    assert [c.id for c in slots[0].cuts] == ["A7", "slot-3b"]


def _modes():
    return pd.DataFrame({"f_n_hz": [40.0, 63.0, 70.0], "zeta": [0.04, 0.03, 0.03],
                         "k_modal_N_m": [6e5, 1.1e6, 1.0e6], "shape_x": [0.2, 1.0, 0.3],
                         "shape_y": [1.0, 0.2, 1.0]})


def _coefficients():
    return pd.DataFrame({"name": ["Ktc", "Krc"], "value": [1100.0, 290.0]})


@pytest.fixture(scope="module")
def chapter4(study):
    peaks = pd.DataFrame({"cut": ["A7", "slot-3b", "q.1", "Z"],
                          "dominant_hz": [75.0, 81.0, 64.0, 70.0]})
    cfg = {"spindle_rpm": {"start": 6000, "stop": 14000, "num": 9}, "depth_max_mm": 20.0,
           "safety_fraction": 0.2}
    return study_lobes(_modes(), _coefficients(), peaks, cfg, study=study, accuracy=0.05)


def test_chapter_4_rates_each_cut_at_its_own_speed_and_depth(study, chapter4):
    lobes, rec = chapter4
    slot_of = {c.id: s.name for s in study_slots(study) for c in s.cuts}
    th = rec[rec["kind"] == "thesis"]
    for c in study.cuts:
        rows = th[(th["direction"] == slot_of[c.id])
                  & np.isclose(th["axial_depth_mm"], c.depth_mm)]
        assert len(rows) == 2, (c.id, rows)  # zoa and sem
        assert (rows["spindle_rpm"] == c.spindle_rpm).all(), (c.id, rows["spindle_rpm"])
    # the speeds the cuts were made at are on the grid, exactly
    for n in (9000.0, 12000.0, 10000.0, 7500.0):
        assert n in lobes["spindle_rpm"].values
    numeric = ["spindle_rpm", "axial_depth_mm", "a_crit_mm", "stability_margin",
               "a_mode_coupling_mm", "a_limit_mm", "stability_margin_min",
               "force_peak_median_hz", "chatter_hz"]
    assert not rec[numeric].isna().any().any(), rec[numeric]
    assert list(lobes["direction"].values) == ["d45", "py", "d200"]
    # each slot's force peaks are its own cuts' (45°: A7 and slot-3b)
    assert lobes["force_peak_median_hz"].values == pytest.approx([78.0, 70.0, 64.0])
    assert lobes["study_spindle_rpm"].values == pytest.approx([9000.0, 7500.0, 10000.0])
    table = coupling_table(lobes)
    assert not table.select_dtypes("number").isna().any().any()
    assert "each slot's speed" in " ".join(table.columns)


def test_chapter_4_findings_name_every_speed_and_no_nan(chapter4):
    from test_chapter_findings import _chatter_inputs

    cases, sim, _, _ = _chatter_inputs()
    lobes, rec = chapter4
    v = chatter_findings(cases, sim, lobes, rec, safety_fraction=0.2).values()
    assert v["has_robot"] is True
    assert v["robot_rpms"] == [7500.0, 9000.0, 10000.0, 12000.0]
    assert v["robot_rpm"] is None and v["robot_speeds"] == "7500, 9000, 10000, 12000 rpm"
    assert v["n_cuts"] == 4
    assert any("d45 0.60 mm at 12000 rpm" in m for m in v["cut_margins"]), v["cut_margins"]
    for key in ("robot_worst_err_pct", "robot_worst_rpm", "robot_worst_err_mm"):
        assert np.isfinite(v[key]), key
    assert "nan" not in " ".join(v["cut_margins"] + v["recommendations"]).lower()
