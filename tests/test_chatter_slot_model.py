"""Thesis robot: slot frames, mode coupling naming the coupled pair, recommendations."""

import numpy as np
import pandas as pd
import pytest

from robomill.chatter.model import CuttingModel, ModeXY
from robomill.chatter.slot_model import mode_coupling, modes_in_slot_frame, recommend


def _modes():
    return pd.DataFrame({"mode": [1, 2, 3], "f_n_hz": [20.0, 67.0, 70.0],
                         "zeta": [0.04, 0.02, 0.02], "k_modal_N_m": [8e5, 1.1e6, 1.0e6],
                         "m_modal_kg": [0, 0, 0], "shape_x": [0.0, 1.0, 0.3],
                         "shape_y": [1.0, 0.2, 1.0], "shape_z": [0.0, 0.0, 0.0]})


def test_slot_frames():
    px = modes_in_slot_frame(_modes(), (1.0, 0.0))
    py = modes_in_slot_frame(_modes(), (0.0, 1.0))
    my = modes_in_slot_frame(_modes(), (0.0, -1.0))
    assert px[0].shape == pytest.approx((0.0, 1.0, 0.0))
    assert py[0].shape == pytest.approx((1.0, 0.0, 0.0))
    assert my[0].shape == pytest.approx((-1.0, 0.0, 0.0))  # in-plane axes reversed: same lobes
    # the axial component is the base Z one in every frame; without a shape_z column the
    # shapes are in-plane
    tilted = _modes().assign(shape_z=[0.5, -0.25, np.nan])
    d45 = modes_in_slot_frame(tilted, (np.sqrt(0.5), np.sqrt(0.5)))
    assert [m.shape[2] for m in d45] == pytest.approx([0.5, -0.25, 0.0])
    assert d45[1].shape[:2] == pytest.approx((1.2 * np.sqrt(0.5), -0.8 * np.sqrt(0.5)))
    assert modes_in_slot_frame(_modes().drop(columns="shape_z"), (1.0, 0.0))[0].shape == \
        pytest.approx((0.0, 1.0))


def test_mode_coupling_names_the_close_pair():
    """Two close modes (67, 70 Hz) with non-parallel shapes couple under the oriented cutting
    stiffness; a far mode (20 Hz) does not take part."""
    modes = [ModeXY(20.0, 0.04, 8e5, (0.0, 1.0)), ModeXY(67.0, 0.002, 1.1e6, (1.0, 0.2)),
             ModeXY(70.0, 0.002, 1.0e6, (0.3, 1.0))]
    cut = CuttingModel(2, 8e8, 0.21, 0.0, np.pi)
    out = mode_coupling(modes, cut, depth_max_m=0.05)
    assert np.isfinite(out["a_mc_m"])
    assert sorted(out["pair"]) == [1, 2]
    assert 60 < out["frequency_hz"] < 80
    # a single mode cannot flutter without delay
    single = mode_coupling(modes[:1], cut, depth_max_m=0.05)
    assert np.isnan(single["a_mc_m"])


def test_recommend_margin_and_best_speed():
    rpm = np.array([26000.0, 28000.0, 30000.0])
    a = np.array([1.0e-3, 0.4e-3, 2.0e-3])
    rows = recommend(a, rpm, np.array([70.0, 71.0, 72.0]), "px",
                     study_points=[(28000.0, 0.25e-3), (28000.0, 0.5e-3)],
                     safety_fraction=0.2, solver="sdm")
    th = [r for r in rows if r["kind"] == "thesis"]
    assert th[0]["stability_margin"] == pytest.approx(0.6)
    assert th[1]["chatter_free"] is False
    best = [r for r in rows if r["kind"] == "recommended"][0]
    assert best["spindle_rpm"] == 30000.0
    assert best["axial_depth_mm"] == pytest.approx(1.6)
    assert best["stability_margin"] == pytest.approx(0.25)
    # each cut at its own speed: a cut at 26 000 rpm is rated at 26 000 rpm
    rows = recommend(a, rpm, np.array([70.0, 71.0, 72.0]), "px",
                     study_points=[(26000.0, 0.5e-3), (30000.0, 0.5e-3)],
                     safety_fraction=0.2, solver="sdm")
    th = [r for r in rows if r["kind"] == "thesis"]
    assert [r["spindle_rpm"] for r in th] == [26000.0, 30000.0]
    assert [r["stability_margin"] for r in th] == pytest.approx([1.0, 3.0])


def test_recommend_applies_the_safety_fraction_on_top_of_the_error():
    """With an error estimate the best speed is the one with the largest a_crit − error and
    the recommended depth is (1 − safety)(a_crit − error); the thesis depth is chatter-free
    only if it is below a_crit − error."""
    rpm = np.array([26000.0, 28000.0, 30000.0])
    a = np.array([1.9e-3, 0.5e-3, 2.0e-3])
    err = np.array([0.0, 0.01e-3, 0.2e-3])  # 30 000 rpm is deeper but less certain
    rows = recommend(a, rpm, np.array([70.0, 71.0, 72.0]), "px",
                     study_points=[(28000.0, 0.495e-3)], safety_fraction=0.2, solver="sem",
                     a_error_m=err)
    th = [r for r in rows if r["kind"] == "thesis"][0]
    assert th["a_crit_error_mm"] == pytest.approx(0.01)
    assert th["stability_margin"] > 0 and th["chatter_free"] is False
    best = [r for r in rows if r["kind"] == "recommended"][0]
    assert best["spindle_rpm"] == 26000.0
    assert best["axial_depth_mm"] == pytest.approx(0.8 * 1.9)
    nan_err = recommend(a, rpm, np.zeros(3), "px", study_points=[(28000.0, 1e-4)],
                        safety_fraction=0.2, solver="zoa")
    assert all(np.isnan(r["a_crit_error_mm"]) for r in nan_err)


def test_non_physical_modes_are_left_out_of_the_tool_model():
    """A negative modal stiffness (a non-physical mode, e.g. the real pyuff beam's negative
    modal constants) is no oscillator: left out; none positive is a clear error."""
    modes = pd.DataFrame({"f_n_hz": [50.0, 140.0], "zeta": [0.02, 0.03],
                          "k_modal_N_m": [4e5, -5e6], "shape_x": [1.0, 0.5],
                          "shape_y": [0.0, 0.5]})
    out = modes_in_slot_frame(modes, (1.0, 0.0))
    assert [m.f_hz for m in out] == [50.0]
    modes.loc[0, "shape_y"] = np.nan  # responses along X only: y not measured
    assert modes_in_slot_frame(modes, (0.0, 1.0))[0].shape == (0.0, -1.0)  # x is py's normal
    with pytest.raises(ValueError, match="positive modal stiffness"):
        modes_in_slot_frame(modes[modes.k_modal_N_m < 0], (1.0, 0.0))
