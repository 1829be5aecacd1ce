"""The planner's reference pose (where the impact test's modes hold) comes from the impact
test's files: the manifest key ``tcp_mm`` of the impact entries, carried by the modal stage
as ``frf_synth.nc`` ``impact_tcp_mm`` (robomill.io.impact, robomill.plan.inputs)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import xarray as xr
import yaml

from robomill.errors import RawDataError
from robomill.io.cell import cell_mapping, parse_cell
from robomill.io.impact import stated_tcp_mm
from robomill.plan.inputs import modal_fit_band_and_pose, require_reference_pose
from robomill.plan.measured import Measured
from robomill.plan.outputs import cell_of
from robomill.plan.request import parse_request
from robomill.plan.tooltip import mode_scalings

K_JOINT = np.array([1e6, 8e5, 4e5, 6e4, 5e4, 2e4])


def test_the_virtual_impact_entries_state_where_the_cell_was_hit(config):
    from robomill.io.synthetic_layout import instrument_files
    from robomill.synth.cell import cell_from_config

    entries = instrument_files(config, "impact")
    point = config["synth"]["process"]["reference_point_mm"]
    assert entries and all(e["tcp_mm"] == pytest.approx(point, abs=1e-12) for e in entries)
    cell = cell_from_config(config)
    # the cell's impact pose puts its TCP at that point
    np.testing.assert_allclose(cell.robot.fk(cell.q_reference_rad)[:3, 3], point, atol=1e-6)
    assert stated_tcp_mm("manifest.yaml", entries) == pytest.approx(tuple(point))


def test_one_test_states_one_pose():
    e = [{"path": "impact/a.csv", "direction": "X", "tcp_mm": [700.0, 0.0, 200.0]},
         {"path": "impact/b.csv", "direction": "Y"},
         {"path": "impact/c.csv", "direction": "Z", "tcp_mm": [700.0, 0.0, 200.0]}]
    assert stated_tcp_mm("m.yaml", e) == (700.0, 0.0, 200.0)
    assert stated_tcp_mm("m.yaml", [{"path": "impact/a.csv", "direction": "X"}]) is None
    e[2]["tcp_mm"] = [700.0, 0.0, 250.0]
    with pytest.raises(RawDataError) as err:
        stated_tcp_mm("m.yaml", e)
    assert "\n" not in str(err.value) and "files[2].tcp_mm" in str(err.value)
    e[2]["tcp_mm"] = [700.0, "up", 200.0]
    with pytest.raises(RawDataError, match=r"files\[2\]\.tcp_mm.*\[x, y, z\] in mm"):
        stated_tcp_mm("m.yaml", e)


def _fit(path, tcp):
    ds = xr.Dataset({"H_synth": ("frequency", np.zeros(3))})
    ds.attrs["band_hz"] = np.array([10.0, 100.0])
    if tcp is not None:
        ds.attrs["impact_tcp_mm"] = np.asarray(tcp, float)
    ds.to_netcdf(path)
    return str(path)


def _cell_and_request(reference_point_mm=None):
    cfg = yaml.safe_load(open("config.yaml"))
    cf = parse_cell(cell_mapping(cfg["cell"]), "cell.yaml")
    req = parse_request({
        "kind": "plan", "operation": {"length_mm": 30.0, "directions": ["py"]},
        "tool": {"diameter_mm": 6, "flutes": 2},
        "placement": {"points_mm": [[730.0, -30.0, 200.0]]},
        "spindle_rpm": [20000], "depth_mm": [0.5], "feed_mm_s": [5],
        **({"reference_point_mm": reference_point_mm} if reference_point_mm else {})},
        "p.yaml")
    return cf, req


def test_the_planner_takes_its_reference_pose_from_the_impact_files(tmp_path):
    cf, req = _cell_and_request(reference_point_mm=[650.0, 50.0, 250.0])
    measured = Measured(joints=pd.DataFrame({
        "joint": np.arange(1, 7), "k_Nm_rad": K_JOINT, "ci95_low_Nm_rad": K_JOINT,
        "ci95_high_Nm_rad": K_JOINT, "observable": True}))
    shapes = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    scalings = []
    for k, tcp in enumerate(([730.0, -28.0, 200.0], [800.0, 60.0, 150.0])):
        band, point = modal_fit_band_and_pose(_fit(tmp_path / f"fit{k}.nc", tcp))
        assert band == [10.0, 100.0]
        cell = cell_of(cf, req, point)
        # the file's pose, not the request's fallback nor the placements
        np.testing.assert_allclose(cell.reference_point_mm, tcp, atol=1e-12)
        q = np.deg2rad([[5.0, 30.0, 30.0, 0.0, 30.0, 0.0]])
        scalings.append(mode_scalings(measured, cell, q, np.ones(3, bool), shapes,
                                      corners=False)["nominal"])
    # a different pose in the impact files moves the modes differently to the same cut
    assert np.abs(scalings[0] / scalings[1] - 1.0).max() > 0.01
    # impact files without a pose: the request's reference_point_mm (documented fallback)
    _, point = modal_fit_band_and_pose(_fit(tmp_path / "bare.nc", None))
    assert point is None
    np.testing.assert_allclose(cell_of(cf, req, point).reference_point_mm, [650.0, 50.0, 250.0])


def test_impact_files_without_a_pose_and_no_fallback_stop_the_plan_in_one_line():
    cf, req = _cell_and_request()
    joints = pd.DataFrame({"joint": np.arange(1, 7), "k_Nm_rad": K_JOINT, "observable": True})
    modes = pd.DataFrame({"f_n_hz": [40.0], "zeta": [0.04], "k_modal_N_m": [1e6],
                          "shape_x": [1.0], "shape_y": [0.0], "shape_z": [0.0]})
    with pytest.raises(RawDataError) as err:
        require_reference_pose(None, req, Measured(modes=modes, joints=joints), "fit.nc")
    msg = str(err.value)
    assert "\n" not in msg and "fit.nc" in msg and "tcp_mm" in msg
    assert "reference_point_mm in p.yaml" in msg
    # a pose from either source, or nothing to move (no joint model), plans on
    require_reference_pose(np.zeros(3), req, Measured(modes=modes, joints=joints), "fit.nc")
    require_reference_pose(None, _cell_and_request([700.0, 0.0, 200.0])[1],
                           Measured(modes=modes, joints=joints), "fit.nc")
    require_reference_pose(None, req, Measured(modes=modes), "fit.nc")
