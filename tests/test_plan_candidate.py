"""A study cut becomes a planning candidate through one adapter
(:mod:`robomill.plan.candidate`), with the process the ingestion rule resolved into
``study.yaml``. A free design (ids ``A7``, ``slot-3b``, per-cut spindle speeds, directions in
degrees) gets the plan's study-cut predictions with every per-cut value present and each cut
at the speed it was made at; the default design's cuts are predicted as before the adapter."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pandas as pd
import pytest
import xarray as xr
import yaml

from robomill.experiment import cut_endpoints_mm, cut_process, cut_redundancy_deg
from robomill.io.manifest import parse_manifest
from robomill.kinematics import robot_from_mapping
from robomill.plan.candidate import study_candidate
from robomill.plan.compare import STUDY_COLUMNS, study_cuts_table
from robomill.plan.measured import Measured
from robomill.plan.predict import Cell, predict_grid
from robomill.plan.request import parse_request
from robomill.study import read_study, write_study

#: a free design: ids that say nothing, speeds set per cut, directions by angle and by name,
#: one cut at the experiment's speed; each cut placed by its own start
CUTS = [
    {"id": "A7", "direction_deg": 45.0, "feed_mm_s": 2.0, "depth_mm": 0.3,
     "spindle_rpm": 9000, "start_mm": [640.0, -30.0, 199.7]},
    {"id": "slot-3b", "direction_deg": 45.0, "feed_mm_s": 2.0, "depth_mm": 0.6,
     "spindle_rpm": 12000, "start_mm": [640.0, 10.0, 199.4]},
    {"id": "q.1", "direction_deg": 200.0, "feed_mm_s": 1.5, "depth_mm": 0.4,
     "start_mm": [670.0, 40.0, 199.6]},
    {"id": "Z", "direction": "py", "feed_mm_s": 1.0, "depth_mm": 0.2, "spindle_rpm": 7500,
     "start_mm": [660.0, -60.0, 199.8]},
]
EXPERIMENT = {"spindle_rpm": 10000, "flutes": 2, "tool_diameter_mm": 6.0,
              "cut_length_mm": 20.0}
PER_CUT = ["p_stable", "a_crit_mm", "a_crit_low_mm", "a_crit_high_mm", "force_N",
           "deflection_normal_um", "deflection_axial_um", "stability_margin",
           "feed_per_tooth_mm", "mrr_mm3_s"]


@pytest.fixture(scope="module")
def cell():
    cfg = yaml.safe_load(open("config.yaml"))["cell"]
    return Cell(robot_from_mapping(cfg["robot"]), np.asarray(cfg["tool_rotation"], float),
                np.deg2rad(cfg["q_home_deg"]), np.array([650.0, 0.0, 200.0]))


def _measured():
    coef = [("Ktc", 800.0), ("Krc", 240.0), ("Kac", 200.0), ("Kte", 25.0), ("Kre", 30.0),
            ("Kae", 6.0)]
    coefficients = pd.DataFrame({"name": [c[0] for c in coef], "value": [c[1] for c in coef],
                                 "ci_low": [c[1] * 0.99 for c in coef],
                                 "ci_high": [c[1] * 1.01 for c in coef]})
    f, zeta, k = np.array([40.0, 63.0]), np.array([0.04, 0.03]), np.array([1.0e6, 1.5e6])
    modes = pd.DataFrame({"f_n_hz": f, "zeta": zeta, "k_modal_N_m": k,
                          "shape_x": [1.0, 0.3], "shape_y": [0.2, 1.0], "shape_z": [0.0, 0.0],
                          "f_n_hz_low": f * 0.995, "f_n_hz_high": f * 1.005,
                          "zeta_low": zeta * 0.95, "zeta_high": zeta * 1.05,
                          "k_modal_N_m_low": k * 0.97, "k_modal_N_m_high": k * 1.03})
    return Measured(modes=modes, coefficients=coefficients)


def _request():
    return parse_request({"kind": "plan", "operation": {"length_mm": 20, "directions": ["py"]},
                          "tool": {"diameter_mm": 6, "flutes": 2},
                          "placement": {"points_mm": [[650, 0, 200]]},
                          "spindle_rpm": {"min": 5000, "max": 15000, "n": 11},
                          "depth_mm": [0.05, 0.5], "feed_mm_s": [1, 4]})


def _study(folder, experiment=EXPERIMENT, cuts=CUTS):
    manifest = parse_manifest({"experiment": experiment, "cuts": cuts, "files": []},
                              folder / "manifest.yaml", require_sha256=False)
    return read_study(write_study(manifest, folder / "study.yaml"))


@pytest.fixture(scope="module")
def table(tmp_path_factory, cell):
    study = _study(tmp_path_factory.mktemp("free"))
    return study_cuts_table(study.cuts, study.experiment, _request(), _measured(), cell,
                            stability=pd.Series({"A7": 1.0, "slot-3b": 0.0}))


def test_a_free_study_gets_every_per_cut_value_at_each_cuts_own_speed(table):
    assert list(table.columns) == STUDY_COLUMNS
    assert list(table["cut"]) == ["A7", "slot-3b", "q.1", "Z"]
    # each cut at the speed it was made at (q.1: the experiment's)
    assert list(table["spindle_rpm"]) == [9000.0, 12000.0, 10000.0, 7500.0]
    assert list(table["depth_mm"]) == [0.3, 0.6, 0.4, 0.2]
    assert table["reachable"].all()
    missing = table[PER_CUT].isna()
    assert not missing.to_numpy().any(), table.loc[:, PER_CUT][missing.any(axis=1)]
    # feed per tooth c = v / (N n), computed here from the design
    want = [60 * c["feed_mm_s"] / (2 * c.get("spindle_rpm", 10000)) for c in CUTS]
    np.testing.assert_allclose(table["feed_per_tooth_mm"], want, rtol=1e-12)
    assert list(table["verdict"]) == ["stable", "chatter", "", ""]
    assert ((table["p_stable"] >= 0) & (table["p_stable"] <= 1)).all()


def test_a_cut_with_its_own_speed_ignores_the_experiments(tmp_path, cell, table):
    """Another experiment speed moves only the cut that takes the experiment's speed."""
    other = _study(tmp_path, {**EXPERIMENT, "spindle_rpm": 13500})
    again = study_cuts_table(other.cuts, other.experiment, _request(), _measured(), cell,
                             stability=pd.Series({"A7": 1.0, "slot-3b": 0.0}))
    own = ["A7", "slot-3b", "Z"]
    pd.testing.assert_frame_equal(again[again["cut"].isin(own)].reset_index(drop=True),
                                  table[table["cut"].isin(own)].reset_index(drop=True))
    q = again.set_index("cut").loc["q.1"]
    assert q["spindle_rpm"] == 13500.0
    assert q["a_crit_mm"] != table.set_index("cut").loc["q.1", "a_crit_mm"]


def test_the_candidate_takes_the_process_resolved_in_the_study_file(tmp_path):
    """The study file's resolved process is what the planner predicts, never resolved again
    from the cut's keys and the experiment."""
    study = _study(tmp_path)
    path = tmp_path / "study.yaml"
    data = yaml.safe_load(path.read_text())
    data["cuts"][2]["process"]["spindle_rpm"] = 11111.0  # q.1: resolved as 11 111 rpm
    data["cuts"][2]["process"]["flutes"] = 4
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    edited = read_study(path)
    c = study_candidate(edited.cut("q.1"), edited.experiment)
    assert (c.spindle_rpm, c.flutes) == (11111.0, 4)
    assert study_candidate(study.cut("q.1"), study.experiment).spindle_rpm == 10000.0
    # a listed cut no ingestion resolved (robomill predict's cut list): resolved once, as
    # the ingestion rule resolves the study's
    assert study_candidate(study.cut("q.1").cut, study.experiment) == \
        study_candidate(study.cut("q.1"), study.experiment)
    a7 = study_candidate(edited.cut("A7"), edited.experiment)
    assert (a7.id, a7.spindle_rpm, a7.direction_deg, a7.length_mm) == ("A7", 9000.0, 45.0,
                                                                       20.0)
    np.testing.assert_allclose(a7.placement_mm, np.array(CUTS[0]["start_mm"])
                               + 10.0 * np.array([np.sqrt(0.5), np.sqrt(0.5), 0.0]))


def _before(cut, experiment, req):
    """The study cut's one-point request as the planner built it before the adapter (the cut's
    process resolved again by :func:`robomill.experiment.cut_process`)."""
    p = cut_process(cut, experiment)
    a, b = cut_endpoints_mm(cut, experiment)
    return replace(req, milling=p["milling"] if p["milling"] in ("slot", "up", "down")
                   else "slot", radial_immersion=float(p["radial_immersion"]),
                   length_mm=float(np.linalg.norm(b - a)),
                   direction_deg=np.array([float(p["direction_deg"])]),
                   direction_names=(cut.id,),
                   tool_diameter_mm=float(p["tool_diameter_mm"] or req.tool_diameter_mm),
                   flutes=int(p["flutes"]), placements_mm=((a + b) / 2)[None],
                   rotations_deg=np.array([cut_redundancy_deg(cut)]),
                   spindle_rpm=np.array([p["spindle_rpm"]]), depth_mm=np.array([cut.depth_mm]),
                   feed_mm_s=np.array([cut.feed_mm_s]), path_stations=3,
                   joint_limit_margin_deg=0.0, min_wrist_angle_deg=0.0)


def test_the_default_designs_cuts_are_predicted_as_before(tmp_path, cell):
    """The default study's design (ids ``s{set}_g{segment}_{dir}``, the experiment's speed,
    the block layout): the adapter's prediction equals the one before it, to the bit."""
    experiment = yaml.safe_load(open("config.yaml"))["experiment"]
    experiment = {k: experiment[k] for k in ("spindle_rpm", "flutes", "tool_diameter_mm",
                                             "cut_length_mm", "layout")}
    cuts = [{"id": f"s{s}_g{g}_{d}", "set": s, "segment": g, "direction": d,
             "feed_mm_s": float(g), "depth_mm": depth}
            for s, depth in ((1, 0.25), (2, 0.5)) for g in (1, 5) for d in ("py", "px", "my")]
    study = _study(tmp_path, experiment, cuts)
    req, m = _request(), _measured()
    for sc in study.cuts:
        new = study_candidate(sc, study.experiment).grid(req)
        old = _before(sc.cut, study.experiment, req)
        xr.testing.assert_identical(predict_grid(new, m, cell), predict_grid(old, m, cell))
