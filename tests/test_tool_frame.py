"""The spindle as mounted (robomill.io.tool_frame, SerialRobot.tool_R): both forms of
``robot.tool`` read, one-line errors, and — checked against a Jacobian computed here by finite
differences of a forward kinematics written here — the rotation about the tool axis leaves
the Cartesian stiffness of a spindle on the flange axis unchanged and changes that of an
off-axis, angled spindle."""

import math

import numpy as np
import pytest
import yaml

from robomill.errors import RawDataError
from robomill.io.cell import cell_mapping, parse_cell
from robomill.io.robots import parse_robot
from robomill.io.tool_frame import rpy_matrix
from robomill.kinematics import robot_from_mapping
from robomill.plan.poses import compliance_grid
from robomill.stiffness import solve_poses, tool_rotation_redundancy


@pytest.fixture(scope="module")
def cellspec():
    return yaml.safe_load(open("config.yaml"))["cell"]


def _dh_fk(spec, q_deg, tool_xyz, tool_rpy_deg):
    """Standard D-H forward kinematics written out with math only: T_i = Rz(θ) Tz(d) Tx(a)
    Rx(α), then the tool frame Rz(yaw) Ry(pitch) Rx(roll) at tool_xyz."""
    T = np.eye(4)
    for j, q in zip(spec["joints"], q_deg, strict=True):
        th, al = math.radians(q + j.get("theta_offset", 0.0)), math.radians(j["alpha"])
        ct, st, ca, sa = math.cos(th), math.sin(th), math.cos(al), math.sin(al)
        A = np.array([[ct, -st * ca, st * sa, j["a"] * ct],
                      [st, ct * ca, -ct * sa, j["a"] * st],
                      [0.0, sa, ca, j["d"]],
                      [0.0, 0.0, 0.0, 1.0]])
        T = T @ A
    r, p, y = (math.radians(v) for v in tool_rpy_deg)
    Rx = np.array([[1, 0, 0], [0, math.cos(r), -math.sin(r)], [0, math.sin(r), math.cos(r)]])
    Ry = np.array([[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]])
    Rz = np.array([[math.cos(y), -math.sin(y), 0], [math.sin(y), math.cos(y), 0], [0, 0, 1]])
    Tt = np.eye(4)
    Tt[:3, :3], Tt[:3, 3] = Rz @ Ry @ Rx, tool_xyz
    return T @ Tt


def test_rpy_by_hand():
    # pitch 90°: the tool axis (z) turns onto the flange's +x, x onto −z
    assert np.allclose(rpy_matrix([0, 90, 0]), [[0, 0, 1], [0, 1, 0], [-1, 0, 0]], atol=1e-15)
    # yaw 90°: x onto +y
    assert np.allclose(rpy_matrix([0, 0, 90]), [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)


def test_both_tool_forms_give_the_same_robot(cellspec):
    old = dict(cellspec["robot"], tool=[0.0, 0.0, 180.0])
    new = dict(cellspec["robot"], tool={"xyz_mm": [0.0, 0.0, 180.0], "rpy_deg": [0, 0, 0]})
    q = np.deg2rad([10, 30, 20, 15, 40, -25])
    assert np.array_equal(robot_from_mapping(parse_robot(old, "c.yaml")).fk(q),
                          robot_from_mapping(parse_robot(new, "c.yaml")).fk(q))


def test_angled_tool_matches_fk_written_here(cellspec):
    tool = {"xyz_mm": [150.0, 0.0, 120.0], "rpy_deg": [0.0, 90.0, 0.0]}
    spec = dict(cellspec["robot"], tool=tool)
    rb = robot_from_mapping(parse_robot(spec, "c.yaml"))
    for q in ([0, 0, 0, 0, 0, 0], [10, 30, 20, 15, 40, -25], [-40, 5, -30, 120, -70, 200]):
        ref = _dh_fk(spec, q, tool["xyz_mm"], tool["rpy_deg"])
        assert np.allclose(rb.fk(np.deg2rad(q)), ref, atol=1e-9)
    # by hand: at the zero posture the flange sits at (150 + 600 + 65, 0, 486.5 + 700) with
    # its z along base +x and its x along base +z; the spindle axis (flange x) points up and
    # the tool point lies 120 mm ahead of the flange and 150 mm above its axis
    T0 = rb.fk(np.zeros(6))
    assert np.allclose(T0[:3, 2], [0, 0, 1], atol=1e-12)
    assert np.allclose(T0[:3, 3], [815.0 + 120.0, 0.0, 1186.5 + 150.0], atol=1e-9)


@pytest.mark.parametrize("value, msg", [
    ({"xyz_mm": [0, 0]}, r"robot\.tool\.xyz_mm: tool\.xyz_mm is \[0, 0\]"),
    ({"xyz_mm": [0, 0, 1], "rpy": [0, 0, 0]}, r"robot\.tool: unknown key\(s\) rpy"),
    ({"rpy_deg": [0, 0, 0]}, r"robot\.tool: key 'xyz_mm' is missing"),
    ({"xyz_mm": [0, 0, 1], "rpy_deg": [0, "x", 0]},
     r"robot\.tool\.rpy_deg\[1\]: value 'x' is not a number"),
    ("long", r"robot\.tool: tool is 'long'"),
])
def test_bad_tool_frame_is_one_line(cellspec, value, msg):
    cell = cell_mapping(cellspec)
    cell["robot"]["tool"] = value
    with pytest.raises(RawDataError, match=msg) as e:
        parse_cell(cell, "raw/cell.yaml")
    assert "\n" not in str(e.value) and str(e.value).startswith("raw/cell.yaml: ")


@pytest.mark.parametrize("key, value, msg", [
    ("joint_limits_deg", [[-10, 10]] * 5, r"robot\.joint_limits_deg: .*6 pairs"),
    ("joint_limits_deg", [[-10, 10]] * 5 + [[5, -5]], r"joint_limits_deg\[5\]: low 5 is not"),
    ("joint_speed_limits_deg_s", [100] * 5 + [0], r"joint_speed_limits_deg_s\[5\]: speed 0"),
    ("controller", "fanuc", r"robot\.controller: controller is 'fanuc' \(expected one of abb"),
])
def test_bad_limits_and_controller_are_one_line(cellspec, key, value, msg):
    cell = cell_mapping(cellspec)
    cell["robot"][key] = value
    with pytest.raises(RawDataError, match=msg):
        parse_cell(cell, "raw/cell.yaml")


def test_shipped_cells_state_limits_and_controller(cellspec):
    cell = parse_cell(cell_mapping(cellspec), "cell.yaml")
    assert cell.controller == "abb"
    assert cell.joint_limits_deg.shape == (6, 2)
    assert np.all(cell.joint_limits_deg[:, 0] < np.deg2rad(0) + cell.q_home_deg)
    other = yaml.safe_load(open("examples/other_cell/config.yaml"))["cell"]
    merged = dict(cellspec, **other)
    pc = parse_cell(cell_mapping(merged), "cell.yaml")
    assert pc.controller == "kuka" and pc.joint_speed_limits_deg_s is None
    assert np.all((pc.q_home_deg >= pc.joint_limits_deg[:, 0])
                  & (pc.q_home_deg <= pc.joint_limits_deg[:, 1]))


def _fd_jacobian_v(spec, q_deg, tool):
    """Linear-velocity Jacobian [mm/rad] by central differences of the FK written here."""
    h = 1e-6
    J = np.zeros((3, 6))
    for i in range(6):
        dq = np.zeros(6)
        dq[i] = math.degrees(h)
        p1 = _dh_fk(spec, np.add(q_deg, dq), tool["xyz_mm"], tool["rpy_deg"])[:3, 3]
        p0 = _dh_fk(spec, np.subtract(q_deg, dq), tool["xyz_mm"], tool["rpy_deg"])[:3, 3]
        J[:, i] = (p1 - p0) / (2 * h)
    return J


@pytest.mark.parametrize("tool, changes", [
    ({"xyz_mm": [0.0, 0.0, 180.0], "rpy_deg": [0.0, 0.0, 0.0]}, False),
    ({"xyz_mm": [150.0, 0.0, 120.0], "rpy_deg": [0.0, 90.0, 0.0]}, True),
    ({"xyz_mm": [80.0, 0.0, 180.0], "rpy_deg": [0.0, 0.0, 0.0]}, True),   # off axis only
])
def test_rotation_changes_cartesian_stiffness_only_off_axis(cellspec, tool, changes):
    """k_n = 1/(nᵀ J_v K_θ⁻¹ J_vᵀ n) along the wall normal n = base y, from the Jacobian
    computed here, at rotations 0° and 40° about the (vertical) tool axis."""
    spec = dict(cellspec["robot"], tool=tool)
    rb = robot_from_mapping(parse_robot(spec, "c.yaml"))
    R0 = np.asarray(cellspec["tool_rotation"], float)
    c = 1.0 / np.array([1e6, 8e5, 4e5, 6e4, 5e4, 3e4])
    n = np.array([0.0, 1.0, 0.0])
    k = []
    for theta in (0.0, 40.0):
        R = tool_rotation_redundancy(R0, np.deg2rad(theta))
        q, ok = solve_poses(rb, np.array([[750.0, 0.0, 200.0]]), R,
                            np.deg2rad(cellspec["q_home_deg"]))
        assert ok[0]
        Jv = _fd_jacobian_v(spec, np.rad2deg(q[0]), tool) * 1e-3          # m/rad
        C = Jv @ np.diag(c) @ Jv.T
        k_here = 1.0 / (n @ C @ n)
        k_lib = 1.0 / (n @ compliance_grid(rb, q[0], c) @ n)
        assert k_lib == pytest.approx(k_here, rel=1e-6)
        k.append(k_here)
    effect = abs(k[1] / k[0] - 1)
    if changes:
        assert effect > 0.01
    else:
        assert effect < 1e-8
