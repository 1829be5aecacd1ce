"""Chapter 5's findings (robomill.stiffness.findings) from planted artefacts, and the chapter's
sentences following altered findings (src/robomill/data/templates/ch5.yaml, no kernel)."""

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from robomill import references
from robomill.findings import Findings
from robomill.pipeline.prose import Prose, load_templates
from robomill.stiffness.findings import stiffness_findings


def _maps():
    ws = np.array([[-1.0, 2.0, 3.0], [4.0, -5.0, 6.0], [0.0, 0.0, -7.0]])
    wxz = np.array([[-10.0, 0.0, 20.0], [30.0, 0.0, -40.0], [0.0, 0.0, 5.0]])
    k = np.ones((2, 2, 2, 2, 3)) * 1e6
    k[1, 0, 1, 1, 2] = 5e6  # largest Z: 5 N/µm
    k[0, 1, 0, 0, 1] = 4e6  # largest Y: 4 N/µm
    return xr.Dataset(
        {"k_N_m": (("height_mm", "redundancy_deg", "y", "x", "axis"), k),
         "workspace_mm": (("sample", "axis3"), ws),
         "workspace_xz_mm": (("sample", "axis3"), wxz),
         "annulus_inner_diameter_mm": ("height_mm", [600.0, 500.0]),
         "annulus_outer_diameter_mm": ("height_mm", [3000.0, 3500.0])},
        coords={"height_mm": [1600.0, 1200.0], "redundancy_deg": [0.0, 30.0],
                "y": [0.0, 1.0], "x": [0.0, 1.0], "axis": ["X", "Y", "Z"]},
        attrs={"robot": "kr360"})


OPTIMAL = pd.DataFrame({
    "robot": ["kr360"] * 6, "height_mm": [1200, 1200, 1200, 1600, 1600, 1600],
    "pose": ["optimal", "random_1", "random_2", "optimal", "random_1", "random_2"],
    "redundancy_deg": [60, 0, 30, 0, 30, 60], "x_mm": [0, 1, 2, -300, 3, 4],
    "y_mm": [400, 1, 2, -100, 3, 4], "S_N_m": [2.5e6, 1e6, 1e6, 3.5e6, 1e6, 1e6],
    "deformation_um": [150.0, 300.0, 250.0, 120.0, 400.0, 600.0]})


def _beamframe(K0):
    return xr.Dataset(
        {"K0": (("dof", "dof2"), np.asarray(K0, float)),
         "node_m": (("node", "axis"), np.zeros((3, 3))),
         "element_J_m4": ("element", [1.0, 2.0]),
         "cantilever_tip_m": 2.0e-6, "cantilever_closed_form_m": 2.5e-6,
         "F_n_N": 20.0, "F_v_N": 6.0})


JOINTS = pd.DataFrame({"joint": [1, 2, 3], "k_Nm_rad": [1e6, 2e6, 3e6],
                       "ci95_low_Nm_rad": [0.9e6, 1.9e6, 2.9e6],
                       "ci95_high_Nm_rad": [1.1e6, 2.1e6, 3.1e6],
                       "observable": [True, True, False]})
VALIDATION = pd.DataFrame({"pose": ["p1", "p2", "p1", "p2"],
                           "model": ["all", "all", "plane", "plane"],
                           "error_pct": [-1.0, 3.0, 2.0, -4.0],
                           "vector_error_pct": [1.0, 1.0, 5.0, 7.0]})


def _slots(k_normal_py=1e6, k_normal_my=2e6):
    rows = []
    for d, kn, kf in (("py", k_normal_py, 3e6), ("my", k_normal_my, 3e6), ("px", 4e6, 0.5e6)):
        for model in ("joint", "combined"):
            rows.append({"cut": f"s1_{d}", "direction": d, "model": model, "k_feed_N_m": kf,
                         "k_normal_N_m": kn, "k_axial_N_m": 9e6})
    return pd.DataFrame(rows)


WAVINESS = pd.DataFrame({"s1_py": [4.0, 4.0], "s1_my": [2.0, 2.0], "s1_px": [1.0, 1.5]},
                        index=pd.Index([1, 2], name="segment"))
CUTS = pd.DataFrame({"cut": ["c1", "c2"], "k_feed_N_m": [3e6, 2e6],
                     "k_normal_N_m": [4e6, 0.5e6], "k_axial_N_m": [6e6, 7e6]})


def _found(K0=((2.0, -1.0), (-1.0, 2.0)), **kw):
    kw = {"planted_k_Nm_rad": [1.05e6, 2.5e6, 3.0e6], "slots": _slots(), "waviness": WAVINESS,
          "thesis_joints": JOINTS, "slot_asymmetry_pct": 20.0, **kw}
    return stiffness_findings(_maps(), OPTIMAL, _beamframe(K0), JOINTS, VALIDATION, **kw)


def test_workspace_identification_maps_and_poses_from_planted_artefacts():
    v = _found().values()
    assert v["map_robot"] == "kr360" and v["workspace_samples"] == 3
    assert v["workspace_x_mm"] == [-1.0, 4.0] and v["workspace_y_mm"] == [-5.0, 2.0]
    assert v["workspace_z_mm"] == [-7.0, 6.0]
    assert v["workspace_xz_plane_x_mm"] == [-10.0, 30.0]
    assert v["workspace_xz_plane_z_mm"] == [-40.0, 20.0]
    assert (v["annulus_inner_mm"], v["annulus_outer_mm"]) == (500.0, 3500.0)
    assert v["joint_k_kNm_rad"] == [1000.0, 2000.0, 3000.0] and v["n_joints"] == 3
    assert v["n_planted_in_ci"] == 2  # 2.5e6 lies outside joint 2's interval
    assert v["n_validation_poses"] == 2 and v["validation_models"] == ["all", "plane"]
    assert v["validation_error_pct"] == [2.0, 3.0]  # mean |error|
    assert v["validation_vector_error_pct"] == [1.0, 6.0]
    assert v["k_z_max_N_um"] == pytest.approx(5.0) and v["k_y_max_N_um"] == pytest.approx(4.0)
    assert v["k_y_over_z"] == pytest.approx(0.8)
    assert v["optimal_height_mm"] == [1200.0, 1600.0]
    assert v["optimal_x_mm"] == [0.0, -300.0] and v["optimal_redundancy_deg"] == [60.0, 0.0]
    assert v["optimal_S_N_um"] == pytest.approx([2.5, 3.5])
    assert v["optimal_deformation_um"] == [150.0, 120.0]
    assert v["random_deformation_min_um"] == [250.0, 400.0]
    assert v["random_deformation_max_um"] == [300.0, 600.0]


def test_seed_numbers_come_from_references():
    v = _found().values()
    assert v["seed_optimal_deformation_um"] == [63.0, 92.0]  # [Yi 2025, §5], H = 1.2 / 1.6 m
    assert v["seed_k_plane_kNm_rad"] == [6890.0, 4530.0, 3400.0]  # three joints here
    assert v["seed_y_over_z"] == pytest.approx(98000.6e-6 / 4.5308)
    assert v["seed_workspace_z_mm"] == references.value("seed001.workspace_extent_mm.z")
    assert v["seed_bf_K_size"] == 42


def test_beam_frame_checks():
    v = _found().values()
    assert v["bf_K_size"] == 2 and v["bf_n_nodes"] == 3 and v["bf_n_elements"] == 2
    assert v["bf_eig_min"] == pytest.approx(1.0) and v["bf_positive_definite"] is True
    assert v["bf_asymmetry"] == 0.0
    assert v["cantilever_tip_um"] == pytest.approx(2.0)
    assert v["cantilever_closed_form_um"] == pytest.approx(2.5)
    indefinite = _found(K0=((1.0, 2.0), (2.0, 1.0))).values()
    assert indefinite["bf_eig_min"] == pytest.approx(-1.0)
    assert indefinite["bf_positive_definite"] is False


def test_slot_asymmetry_verdict_and_its_threshold():
    """+Y waviness 4 µm against −Y 2 µm (+100 %); +Y normal stiffness 1 against 2 N/µm
    (−50 %): the rougher slot is the less stiff one by more than 20 %."""
    f = _found()
    v = f.values()
    assert v["slot_directions"] == ["my", "px", "py"]
    assert v["slot_k_normal_N_um"] == [2.0, 4.0, 1.0]
    assert v["slot_weakest_axis"] == ["normal", "feed", "normal"]
    assert v["normal_spread_pct"] == pytest.approx(-50.0)
    assert v["waviness_spread_pct"] == pytest.approx(100.0)
    assert v["waviness_px_um"] == pytest.approx(1.25)
    assert v["unobservable_joints"] == [3]
    assert v["verdict_y_asymmetry_explained"] == "explained"
    assert f["y_asymmetry_explained"].config_key == "stiffness.slot_asymmetry_pct"
    assert v["threshold_y_asymmetry_explained"] == 20.0
    same = _found(slots=_slots(2e6, 2e6)).values()
    assert same["verdict_y_asymmetry_explained"] == "not_explained"
    assert _found(slot_asymmetry_pct=60.0).values()[
        "verdict_y_asymmetry_explained"] == "not_explained"  # a 50 % stiffness gap is too small
    assert _found(slot_asymmetry_pct=150.0).values()["verdict_y_asymmetry_explained"] == "none"


def test_partial_study_cut_stiffness_without_slots_or_truth():
    v = _found(planted_k_Nm_rad=None, slots=None, waviness=None, thesis_joints=None,
               cut_stiffness=CUTS).values()
    assert v["has_planted"] is False and "n_planted_in_ci" not in v
    assert v["has_slots"] is False and "verdict_y_asymmetry_explained" not in v
    assert v["has_cut_stiffness"] is True
    assert v["cut_k_normal_N_um"] == [0.5, 4.0] and v["cut_k_feed_N_um"] == [2.0, 3.0]
    assert (v["weakest_cut"], v["weakest_axis"]) == ("c2", "normal")
    assert v["weakest_k_N_um"] == pytest.approx(0.5)
    empty = stiffness_findings(_maps(), OPTIMAL, _beamframe([[1.0]]), JOINTS,
                               VALIDATION.iloc[:0], slot_asymmetry_pct=20.0).values()
    assert empty["n_validation_poses"] == 0 and "validation_error_pct" not in empty


def _refs():
    return {f"ref_{k}": f"[{k}]" for k in (
        "workspace_ranges", "workspace", "joints", "identification", "validation", "maps",
        "maxima", "optimal", "optimal_poses", "beamframe", "cut_stiffness", "slots",
        "thesis_slots")}


def _chapters_5_and_6_2(found):
    """The text of chapter 5 (the study's cuts) and chapter 6.2 (Yi 2025's and Cai 2015's models),
    both rendered from the one stiffness findings file."""
    says = [Prose(load_templates(c), found) for c in ("ch5", "ch6_stiffness")]
    return " ".join(" ".join(say(*say.templates, **_refs()).split()) for say in says)


def test_chapter_5_prose_follows_its_findings():
    text = _chapters_5_and_6_2(_found())
    assert "inner diameter 500 mm, outer 3500 mm" in text
    assert "2 of 3 lie within the 95 % interval" in text
    assert "all, plane 2.00, 3.00 %" in text
    assert "largest Z stiffness over the plane is 5.00 N/µm" in text
    assert "deformation under the end load 150, 120 µm" in text
    assert "It is positive definite." in text
    assert "their normal stiffness differs by -50.0 %" in text
    assert "rougher of the ±Y slots is the less stiff one, by at least 20 %" in text
    assert "not observable in its load tests: 3" in text
    assert "{" not in text
    alike = Prose(load_templates("ch5"), _found(slot_asymmetry_pct=150.0))
    assert "no asymmetry" in alike("slot_verdict")
    bent = Prose(load_templates("ch6_stiffness"), _found(K0=((1.0, 2.0), (2.0, 1.0))))
    assert "not positive definite" in bent("beamframe_definite")
    other = Prose(load_templates("ch5"), _found(slots=None, cut_stiffness=CUTS))
    text = " ".join(other("cut_stiffness", "no_cuts", "slots", **_refs()).split())
    assert "normal direction of cut `c2` (0.500 N/µm)" in text and "this run has none" not in text
    bare = _found(slots=None, planted_k_Nm_rad=None)
    assert "this run has none" in " ".join(Prose(load_templates("ch5"), bare)("no_cuts").split())
    assert Prose(load_templates("ch6_stiffness"), bare)("planted") == ""
    assert "holds no check" in Prose(load_templates("ch6_stiffness"), Findings("stiffness"))(
        "against_rows")
    rows = _found()
    rows.comparisons = [{"verdict": "pass"}, {"verdict": "miss"}]
    assert "1 of 2 within" in " ".join(Prose(load_templates("ch6_stiffness"), rows)("against_rows")
                                       .split())
    assert "not compared with the thesis'" in Prose(load_templates("ch5"), rows)("against")
    rows.add("thesis_study", True)
    assert "chapter 6.2" in " ".join(Prose(load_templates("ch5"), rows)("against").split())
