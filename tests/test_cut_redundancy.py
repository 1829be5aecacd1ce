"""A cut's redundancy angle: ``redundancy_deg``, the tool's rotation about its axis,
is a design key of the manifest (default 0: the cell's tool orientation) and the virtual cell's
simulators cut at it (their joint path, hence gear errors, torques and the Jacobian, follow it).
"""

import copy
import dataclasses

import numpy as np
import pytest

from robomill.errors import RawDataError
from robomill.experiment import Cut, cut_redundancy_deg, cuts_table, is_thesis_design
from robomill.io.manifest import parse_manifest
from robomill.synth.cell import cell_from_config

EXP = {"spindle_rpm": 28000, "flutes": 2, "tool_diameter_mm": 6.0, "cut_length_mm": 40.0}
CUT = {"id": "plan_01", "feed_mm_s": 10.0, "depth_mm": 0.2, "direction": "px",
       "start_mm": [580.0, -20.0, 200.0]}


def _parse(cuts):
    return parse_manifest({"experiment": EXP, "cuts": cuts, "files": []}, "manifest.yaml")


def test_redundancy_is_a_cut_key_default_zero_and_round_trips():
    a, b = _parse([CUT, {**CUT, "id": "plan_02", "redundancy_deg": 55}]).cuts
    assert a.redundancy_deg is None and cut_redundancy_deg(a) == 0.0
    assert "redundancy_deg" not in a.as_dict()            # the default study's manifest as is
    assert b.redundancy_deg == 55.0 and b.as_dict()["redundancy_deg"] == 55.0
    assert _parse([a.as_dict(), b.as_dict()]).cuts == [a, b]
    assert not is_thesis_design([b])
    assert list(cuts_table([a, b], 28000, 2)["redundancy_deg"]) == [0.0, 55.0]
    assert "redundancy_deg" not in cuts_table([a], 28000, 2)


@pytest.mark.parametrize(("value", "message"), [
    ("north", r"cuts\[0\]\.redundancy_deg: key 'redundancy_deg' is 'north' \(expected int or "
              r"float\)"),
    (400.0, r"cuts\[0\]\.redundancy_deg: redundancy_deg is 400\.0 \(expected the tool's "
            r"rotation about its axis .* within ±360 deg\)"),
    (float("nan"), r"cuts\[0\]\.redundancy_deg: redundancy_deg is nan"),
    (True, r"cuts\[0\]\.redundancy_deg: key 'redundancy_deg' is True"),
])
def test_a_bad_redundancy_angle_is_one_line(value, message):
    with pytest.raises(RawDataError, match=r"^manifest\.yaml: " + message) as err:
        _parse([{**CUT, "redundancy_deg": value}])
    assert "\n" not in str(err.value)


def _cell(tiny_config, tool_mm=None):
    cfg = copy.deepcopy(tiny_config)
    if tool_mm is not None:
        cfg["cell"]["robot"]["tool"] = tool_mm
    cell = cell_from_config(cfg)
    cell.experiment = {**cell.experiment, **EXP}
    return cell


def _rz(theta_deg):
    """Rotation about z by θ, written out (the hand computation)."""
    c, s = np.cos(np.deg2rad(theta_deg)), np.sin(np.deg2rad(theta_deg))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _cut(theta):
    return dataclasses.replace(_parse([CUT]).cuts[0], redundancy_deg=theta)


S_MM = np.linspace(0.0, 40.0, 5)


def test_theta_zero_is_the_cells_tool_orientation_exactly(tiny_config):
    cell = _cell(tiny_config)
    plain, zero = _cut(None), _cut(0.0)
    np.testing.assert_array_equal(cell.cut_tool_rotation(plain), cell.tool_rotation())
    np.testing.assert_array_equal(cell.joint_path_rad(plain, S_MM),
                                  cell.joint_path_rad(zero, S_MM))


@pytest.mark.parametrize("tool_mm", [None, [60.0, 0.0, 150.0]], ids=["on-axis", "offset"])
def test_the_simulators_pose_is_at_the_cuts_rotation(tiny_config, tool_mm):
    """Forward kinematics of the simulated joint path (independent of the IK) puts the tool at
    R0 Rz(θ) on the cut's path."""
    cell = _cell(tiny_config, tool_mm)
    theta = 40.0
    q = cell.joint_path_rad(_cut(theta), S_MM)
    R0 = cell.tool_rotation()
    np.testing.assert_allclose(cell.cut_tool_rotation(_cut(theta)), R0 @ _rz(theta),
                               atol=1e-12)
    T = cell.robot.fk(q)
    np.testing.assert_allclose(T[:, :3, :3], np.broadcast_to(R0 @ _rz(theta), (5, 3, 3)),
                               atol=1e-6)
    np.testing.assert_allclose(T[:, :3, 3], cell.cut_path_mm(_cut(theta), S_MM), atol=1e-4)


def test_on_the_tool_axis_only_the_last_joint_turns(tiny_config):
    """With the tool point on joint 6's axis (the tiny cell: no tool offset across it) the
    wrist centre is the tool point minus the tool length along the vertical tool axis, which a
    rotation about that axis leaves in place: joints 1–5 keep their angles, joint 6 turns by θ,
    and the translational Jacobian (hence the Cartesian stiffness) does not change."""
    cell = _cell(tiny_config)
    q0 = cell.joint_path_rad(_cut(None), S_MM)
    q = cell.joint_path_rad(_cut(40.0), S_MM)
    np.testing.assert_allclose(q[:, :5], q0[:, :5], atol=1e-6)
    turn = np.rad2deg(q[:, 5] - q0[:, 5])
    np.testing.assert_allclose(np.abs((turn + 180.0) % 360.0 - 180.0), 40.0, atol=1e-6)
    np.testing.assert_allclose(cell.robot.jacobian(q)[:, :3], cell.robot.jacobian(q0)[:, :3],
                               atol=1e-6)


def test_off_the_tool_axis_the_posture_and_its_stiffness_change(tiny_config):
    """A tool point 60 mm across joint 6's axis: turning the tool about its own axis moves the
    wrist centre on a circle of that radius about the tool point, so the arm joints move and
    the Cartesian compliance J K⁻¹ Jᵀ at the tool point changes."""
    cell = _cell(tiny_config, [60.0, 0.0, 150.0])
    q0 = cell.joint_path_rad(_cut(None), S_MM)
    q = cell.joint_path_rad(_cut(90.0), S_MM)
    assert np.abs(np.rad2deg(q[:, :3] - q0[:, :3])).max() > 1.0
    # the wrist centre (frame 5's origin) turned about the tool axis through the tool point:
    # the tool axis R0 e_z points down (−Z), so a turn θ about it is Rz(−θ) in the base frame
    assert np.allclose(cell.tool_rotation()[:, 2], [0.0, 0.0, -1.0])
    tcp = cell.cut_path_mm(_cut(0.0), S_MM)[0]
    w0 = cell.robot.frames(q0[0])[5, :3, 3] - tcp
    w = cell.robot.frames(q[0])[5, :3, 3] - tcp
    np.testing.assert_allclose(w, _rz(-90.0) @ w0, atol=1e-4)
    k_inv = np.diag([1e-6] * 6)                           # planted joint compliance [rad/Nm]
    C0 = _compliance(cell, q0[0], k_inv)
    C = _compliance(cell, q[0], k_inv)
    assert np.abs(C - C0).max() > 0.05 * np.abs(C0).max()


def _compliance(cell, q, k_inv):
    J = cell.robot.jacobian(q)[:3] * 1e-3                 # m per rad
    return J @ k_inv @ J.T


def test_redundancy_in_the_cut_type():
    assert Cut("c", None, None, "px", 1.0, 0.1).redundancy_deg is None


@pytest.mark.parametrize("theta", [0.0, 30.0])
def test_the_tracker_analysis_solves_the_run_at_its_cuts_rotation(monkeypatch, theta):
    """The gear lines of a tracker run are attributed along the joint path at the tool
    orientation of the run's cut: R0 Rz(θ)."""
    import types

    import robomill.straightness.study as study

    seen = {}
    monkeypatch.setattr(study, "analyse_run",
                        lambda *a, **kw: seen.update(kw) or ("prof", "spec", "gears", "peaks"))
    R0 = np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, -1.0]])
    cell = types.SimpleNamespace(to_base_mm=lambda instrument, p: p, robot="robot",
                                 transmissions=[], tool_rotation=R0, q_home_rad=np.zeros(6))
    out = study.analyse_tracker_run(None, np.zeros((3, 3)), cell, data_file="r.csv",
                                    redundancy_deg=theta)
    assert out == ("prof", "spec", "gears", "peaks")
    np.testing.assert_allclose(seen["tool_rotation"], R0 @ _rz(theta), atol=1e-12)


def test_the_analyses_cut_pose_follows_the_cuts_rotation(tiny_config):
    """robomill.experiment.cut_joint_path_rad (the plan's and chapter 5's poses of a study's
    cuts) solves each cut at R0 Rz(θ); at θ = 0 at R0 exactly."""
    from robomill.experiment import cut_joint_path_rad

    cell = _cell(tiny_config, [60.0, 0.0, 150.0])
    R0 = cell.tool_rotation()
    kw = {"tool_rotation": R0, "q0_rad": cell.q_home_rad}
    q = cut_joint_path_rad(cell.robot, _cut(30.0), EXP, S_MM, **kw)
    np.testing.assert_allclose(cell.robot.fk(q)[:, :3, :3],
                               np.broadcast_to(R0 @ _rz(30.0), (5, 3, 3)), atol=1e-6)
    np.testing.assert_allclose(q, cell.joint_path_rad(_cut(30.0), S_MM), atol=1e-9)
    np.testing.assert_array_equal(cut_joint_path_rad(cell.robot, _cut(None), EXP, S_MM, **kw),
                                  cell.joint_path_rad(_cut(None), S_MM))


def test_the_plan_predicts_a_study_cut_at_its_own_rotation(monkeypatch, repo):
    import robomill.plan.compare as compare
    from robomill.plan.measured import Measured
    from robomill.plan.request import read_request

    seen = []

    class Seen(Exception):
        pass

    def capture(req, measured, cell):
        seen.append(req.rotations_deg.tolist())
        raise Seen

    monkeypatch.setattr(compare, "predict_grid", capture)
    req = read_request(repo / "plan.yaml")
    for theta, want in ((None, [0.0]), (30.0, [30.0])):
        with pytest.raises(Seen):
            compare.study_cuts_table([_cut(theta)], EXP, req, Measured(), None)
        assert seen[-1] == want
