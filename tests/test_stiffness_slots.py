"""Chapter-5 slot table: mean stiffness per direction beside Table 2.1, and the ±Y spread."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from robomill import stiffness


def test_slot_table_means_and_waviness_and_spread():
    slots = pd.DataFrame({"model": ["combined"] * 4, "direction": ["py", "py", "my", "px"],
                          "k_feed_N_m": [1e6, 3e6, 2e6, 4e6],
                          "k_normal_N_m": [1.1e6, 1.1e6, 1.0e6, 5e6],
                          "k_axial_N_m": [9e6] * 4})
    wav = pd.DataFrame({"s1_px": [0.5, 0.7], "s1_py": [2.0, 4.0], "s2_py": [3.0, 3.0],
                        "s1_my": [1.0, 1.0]}, index=pd.Index([1, 2], name="segment"))
    t = stiffness.slot_stiffness_table(slots, wav)
    assert t.loc[("combined", "py"), "k feed N/µm"] == pytest.approx(2.0)
    assert t.loc[("combined", "py"), "waviness RMS µm (Table 2.1, mean)"] == pytest.approx(3.0)
    assert t.loc[("combined", "px"), "waviness RMS µm (Table 2.1, mean)"] == pytest.approx(0.6)
    kn = t.loc["combined"]["k normal N/µm"]
    assert stiffness.stiffness_spread_pct(kn) == pytest.approx(10.0)
    assert np.isnan(stiffness.stiffness_spread_pct(kn.drop("my")))
    assert np.isnan(stiffness.waviness_by_direction(wav[["s1_px"]])["py"])


def test_cut_stiffness_of_a_lone_compliant_base_joint_is_k_over_r_squared():
    """Only joint 1 (vertical axis through the base origin) compliant: a force along the
    tangent at horizontal radius r turns it by F·r/k1 and moves the TCP by F·r²/k1, so the
    stiffness is k1/r² along the tangent and the radial and vertical directions are rigid
    (every other joint rigid) — whatever the cut's direction is called (name or degrees)."""
    from robomill.experiment import Cut
    from robomill.kinematics import robot_from_mapping

    robot = robot_from_mapping({
        "name": "r", "convention": "dh", "length_unit": "mm", "angle_unit": "deg",
        "joints": [{"a": 150.0, "alpha": -90.0, "d": 486.5, "theta_offset": 0.0},
                   {"a": 700.0, "alpha": 0.0, "d": 0.0, "theta_offset": -90.0},
                   {"a": 0.0, "alpha": -90.0, "d": 0.0, "theta_offset": 0.0},
                   {"a": 0.0, "alpha": 90.0, "d": 600.0, "theta_offset": 0.0},
                   {"a": 0.0, "alpha": -90.0, "d": 0.0, "theta_offset": 0.0},
                   {"a": 0.0, "alpha": 0.0, "d": 65.0, "theta_offset": 0.0}],
        "tool": [0.0, 0.0, 180.0]})
    q = np.deg2rad([30.0, 20.0, 10.0, 0.0, 60.0, 0.0])
    p_m = robot.fk(q)[:3, 3] * 1e-3
    r_m = np.hypot(p_m[0], p_m[1])
    tangent_deg = np.rad2deg(np.arctan2(p_m[1], p_m[0])) + 90.0
    k1 = 2.0e6
    c = np.array([1.0 / k1, 0, 0, 0, 0, 0])
    cuts = [Cut(id="tangent", set=None, segment=None, direction=None, feed_mm_s=1.0,
                depth_mm=0.5, direction_deg=tangent_deg),
            Cut(id="radial", set=None, segment=None, direction=None, feed_mm_s=1.0,
                depth_mm=0.5, direction_deg=tangent_deg - 90.0)]
    with np.errstate(divide="ignore"):  # the vertical is exactly rigid: 1/0
        t = stiffness.cut_stiffness_table(robot, c, cuts, np.stack([q, q])).set_index("cut")
    assert list(t.columns) == ["k_feed_N_m", "k_normal_N_m", "k_axial_N_m"]
    assert t.loc["tangent", "k_feed_N_m"] == pytest.approx(k1 / r_m**2, rel=1e-9)
    assert t.loc["radial", "k_normal_N_m"] == pytest.approx(k1 / r_m**2, rel=1e-9)
    assert abs(t.loc["radial", "k_feed_N_m"]) > 1e6 * t.loc["tangent", "k_feed_N_m"]  # rigid
