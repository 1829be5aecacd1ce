"""The controller program (robomill.plan.program*, .controller, .motion) against truths
written here from the controllers' published conventions, not from robomill's model:

* forward kinematics from the ROS-Industrial robot descriptions, whose joint angles and
  ``tool0`` frame are the controllers' own: ``ros-industrial/abb``,
  ``abb_irb1600_support/urdf/irb1600_8_145_macro.xacro`` (the IRB 1600 x/1.45 arm; link_6 →
  tool0 rpy (0, 90°, 0), tool0 = ABB's tool0) and ``ros-industrial/kuka_experimental``,
  ``kuka_kr6_support/urdf/kr6r900sixx_macro.xacro`` (tool0 = KUKA's $FLANGE); the joint
  origins and axes below are transcribed from them (both BSD/Apache-licensed);
* ABB's confdata (cf1/cf4/cf6 quadrants; cfx from the wrist centre relative to axis 1 and to
  the lower arm, and the sign of axis 5) and KUKA's Status and Turn, written from the
  manuals' definitions on the robot descriptions' frames;
* a small grammar of the RAPID and KRL statements the programs use.
"""

import math
import re

import numpy as np
import pandas as pd
import pytest
import yaml

from robomill.errors import RawDataError
from robomill.io.cell import cell_mapping, parse_cell
from robomill.plan.controller import abb_confdata, kuka_status_turn
from robomill.plan.cutpath import plan_cut_path
from robomill.plan.measured import Measured
from robomill.plan.outputs import cell_of
from robomill.plan.program import program_cell, write_program
from robomill.plan.request import parse_request

ANGLED = {"xyz_mm": [150.0, 0.0, 120.0], "rpy_deg": [0.0, 90.0, 0.0]}
K_JOINT = np.array([1e6, 8e5, 4e5, 6e4, 5e4, 3e4])

# ---- the published descriptions: (joint origin xyz [mm] in the parent, axis) ---------------
IRB1600_URDF = [((0, 0, 0), (0, 0, 1)), ((150, 0, 486.5), (0, 1, 0)), ((0, 0, 700), (0, 1, 0)),
                ((300, 0, 0), (1, 0, 0)), ((300, 0, 0), (0, 1, 0)), ((65, 0, 0), (1, 0, 0))]
KR6_URDF = [((0, 0, 400), (0, 0, -1)), ((25, 0, 0), (0, 1, 0)), ((455, 0, 0), (0, 1, 0)),
            ((0, 0, 35), (-1, 0, 0)), ((420, 0, 0), (0, 1, 0)), ((80, 0, 0), (-1, 0, 0))]


def _axis_rot(axis, a):
    k = np.asarray(axis, float)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(a) * K + (1 - math.cos(a)) * K @ K


def _hom(R, p):
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


def urdf_links(desc, q_deg):
    """Base → link_i transforms (i = 1..6) of a description at controller angles."""
    T, out = np.eye(4), []
    for (o, ax), q in zip(desc, q_deg, strict=True):
        T = T @ _hom(np.eye(3), o) @ _hom(_axis_rot(ax, math.radians(q)), [0, 0, 0])
        out.append(T)
    return out


def tool0(desc, q_deg):
    """The controller's flange: link_6 · Ry(90°) (both descriptions)."""
    return urdf_links(desc, q_deg)[-1] @ _hom(_axis_rot((0, 1, 0), math.pi / 2), [0, 0, 0])


def _quat_R(w, x, y, z):
    """Rotation of a quaternion, normalized first as the controller does (the file prints 9
    decimals: |q| differs from 1 by ~1e-9, which alone would read as ~0.003°)."""
    w, x, y, z = np.array([w, x, y, z]) / np.linalg.norm([w, x, y, z])
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _abc_R(a, b, c):
    a, b, c = (math.radians(v) for v in (a, b, c))
    return _axis_rot((0, 0, 1), a) @ _axis_rot((0, 1, 0), b) @ _axis_rot((1, 0, 0), c)


def _angle_deg(R1, R2):
    """The angle of R1ᵀR2 [deg] (atan2 of its sine and cosine: exact near 0)."""
    D = R1.T @ R2
    s = 0.5 * np.linalg.norm([D[2, 1] - D[1, 2], D[0, 2] - D[2, 0], D[1, 0] - D[0, 1]])
    return math.degrees(math.atan2(s, (np.trace(D) - 1) / 2))


# ---- the published configuration rules -----------------------------------------------------
def abb_rule(q_ctrl):
    """ABB confdata of the IRB 1600 at controller angles: quadrants of axes 1, 4, 6; cfx =
    4·(wrist centre behind axis 1) + 2·(behind the lower arm) + (axis 5 < 0)."""
    L = urdf_links(IRB1600_URDF, q_ctrl)
    w = L[4][:3, 3]                                   # link_5: the wrist centre
    behind1 = w @ L[0][:3, 0] < 0                     # x of link_1 (turns with axis 1)
    p2, p3 = L[1][:3, 3], L[2][:3, 3]
    front = np.cross(L[1][:3, 1], p3 - p2)            # y₂ × lower arm: forward at q = 0
    behind_arm = (w - p2) @ front < 0
    quad = [math.floor(q_ctrl[j] / 90.0) for j in (0, 3, 5)]
    return quad + [4 * behind1 + 2 * behind_arm + (q_ctrl[4] < 0)]


def kuka_rule(q_ctrl):
    """KUKA Status of the KR 6 R900 sixx: bit 0 overhead (wrist x in the A1 system < 0),
    bit 1 A3 ≥ φ (φ = atan(35/420), the wrist on the link arm's line), bit 2 A5 in
    [−180°, 0°) or ≥ 180°; Turn bit j: axis j+1 < 0."""
    L = urdf_links(KR6_URDF, q_ctrl)
    w = L[4][:3, 3] - L[0][:3, 3]
    phi = math.degrees(math.atan2(35.0, 420.0))
    a5 = q_ctrl[4]
    s = int(w @ L[0][:3, 0] < 0) + 2 * int(q_ctrl[2] >= phi) + 4 * int(
        -180 <= a5 < 0 or a5 >= 180)
    t = sum(1 << j for j, v in enumerate(q_ctrl) if v < 0)
    return s, t


# ---- cells ---------------------------------------------------------------------------------
def kuka_cell(**extra):
    """A KR 6 R900 sixx in the model's D-H (positions checked against the description) with
    its controller conventions; the data-sheet ranges converted to model angles."""
    sign = np.array([-1, 1, 1, -1, 1, -1.0])
    off = np.array([0, -90, 90, 0, 0, 0.0])
    ctrl = np.array([[-170, 170], [-190, 45], [-120, 156], [-185, 185], [-120, 120],
                     [-350, 350]], float)
    model = np.sort((ctrl - off[:, None]) * sign[:, None], axis=1)
    return {"robot": {"name": "kr6r900sixx", "convention": "dh", "length_unit": "mm",
                      "angle_unit": "deg",
                      "joints": [{"a": 25.0, "alpha": -90.0, "d": 400.0, "theta_offset": 0.0},
                                 {"a": 455.0, "alpha": 0.0, "d": 0.0, "theta_offset": -90.0},
                                 {"a": 35.0, "alpha": -90.0, "d": 0.0, "theta_offset": 0.0},
                                 {"a": 0.0, "alpha": 90.0, "d": 420.0, "theta_offset": 0.0},
                                 {"a": 0.0, "alpha": -90.0, "d": 0.0, "theta_offset": 0.0},
                                 {"a": 0.0, "alpha": 0.0, "d": 80.0, "theta_offset": 0.0}],
                      "tool": {"xyz_mm": [0.0, 0.0, 120.0], "rpy_deg": [0.0, 0.0, 0.0]},
                      "joint_limits_deg": model.tolist(),
                      "joint_speed_limits_deg_s": [360, 300, 360, 381, 388, 615],
                      "controller": "kuka"},
            "q_home_deg": [0.0, 20.0, 10.0, 0.0, 60.0, 0.0],
            "tool_rotation": [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]],
            "transmissions": [{"joint": 1, "stage": "motor", "rev_per_joint_rev": 100.0,
                               "teeth": 10}],
            "mass_model": {"links": [{"link": 1, "mass_kg": 10.0, "com_mm": [0, 0, 300]}],
                           "tool": {"mass_kg": 2.5, "com_mm": [575.0, 8.0, 760.0]}},
            "controller_frames": {"flange": {"xyz_mm": [0, 0, 0], "rpy_deg": [0, 0, 180]},
                                  "joint_sign": sign.astype(int).tolist(),
                                  "joint_offset_deg": off.tolist()},
            **extra}


def abb_cell(tool=None, **extra):
    cs = yaml.safe_load(open("config.yaml"))["cell"]
    if tool is not None:
        cs["robot"]["tool"] = tool
        cs["q_home_deg"] = [0.0, 50.0, 20.0, 0.0, 105.0, 0.0]
    cs.update(extra)
    return cs


def plan(cs, *, point, direction="py", rotations=(-55.0, 55.0, 12), length=40.0,
         wobj=None, program=None):
    cf = parse_cell(cell_mapping(cs), "cell.yaml")
    reqd = {"kind": "plan", "operation": {"length_mm": length, "directions": [direction]},
            "tool": {"diameter_mm": 6, "flutes": 2},
            "placement": {"points_mm": [list(point)]},
            "rotations_deg": {"min": rotations[0], "max": rotations[1], "n": rotations[2]},
            "spindle_rpm": [27979.79798], "depth_mm": [0.5], "feed_mm_s": [5],
            "max_rotation_step_deg": 10, "path_stations": 5}
    if wobj is not None:
        reqd["work_object"] = wobj
    if program is not None:
        reqd["program"] = program
    req = parse_request(reqd, "p.yaml")
    joints = pd.DataFrame({"joint": np.arange(1, 7), "k_Nm_rad": K_JOINT,
                           "ci95_low_Nm_rad": K_JOINT, "ci95_high_Nm_rad": K_JOINT,
                           "observable": True})
    cell = cell_of(cf, req, np.array([list(point)]))
    w = req.work_object
    p = plan_cut_path("plan_01", np.array(point, float), float(req.direction_deg[0]), 0.5, 5.0,
                      27979.79798, req, Measured(joints=joints), cell, w)
    assert p.refused is None, p.refused
    pc = program_cell(cf.robot, w.T_base_part, cf.mass_model, frames=cf.controller_frames,
                      spindle=cf.spindle, motion=req.motion, q_home_deg=cf.q_home_deg)
    return cf, req, p, pc


WOBJ = {"frame": {"xyz_mm": [600.0, -120.0, 200.0], "rpy_deg": [0.0, 0.0, 0.0]},
        "block_mm": {"min": [0, 0, -50], "max": [300, 250, 0]}}
KUKA_WOBJ = {"frame": {"xyz_mm": [450.0, -100.0, 150.0], "rpy_deg": [0.0, 0.0, 90.0]},
             "block_mm": {"min": [0, 0, -50], "max": [200, 200, 0]}}
CASES = {
    "default": lambda **k: plan(abb_cell(**k), point=(750.0, 85.0, 200.0), wobj=WOBJ),
    "angled": lambda **k: plan(abb_cell(ANGLED, **k), point=(750.0, 85.0, 200.0), wobj=WOBJ,
                               rotations=(-90.0, 90.0, 19)),
    "kuka": lambda **k: plan(kuka_cell(**k), point=(520.0, 0.0, 150.0), direction="px",
                             wobj=KUKA_WOBJ),
}


def _nums(s):
    return [float(x) for x in s.split(",")]


def parse_rapid(text):
    tool = re.search(r"PERS tooldata tSpindle := \[TRUE,\[\[([^\]]+)\],\[([^\]]+)\]\],"
                     r"\[([^,]+),\[([^\]]+)\]", text)
    wobj = re.search(r'PERS wobjdata wPart := \[FALSE,TRUE,"",\[\[([^\]]+)\],\[([^\]]+)\]\]',
                     text)
    joints = {n: _nums(v) for n, v in re.findall(r"CONST jointtarget j_(\w+) := \[\[([^\]]+)\]",
                                                 text)}
    targets = {n: (_nums(p), _nums(q), [int(c) for c in _nums(c)]) for n, p, q, c in re.findall(
        r"CONST robtarget p_(\w+) := \[\[([^\]]+)\],\[([^\]]+)\],\[([^\]]+)\]", text)}
    return (_hom(_quat_R(*_nums(tool.group(2))), _nums(tool.group(1))), float(tool.group(3)),
            np.array(_nums(tool.group(4))), _hom(_quat_R(*_nums(wobj.group(2))),
                                                 _nums(wobj.group(1))), joints, targets)


def _kv(body):
    return dict(re.findall(r"([A-Z]\d?) (-?[\d.]+)", body))


def _frame(v):
    return _hom(_abc_R(*(float(v[k]) for k in "ABC")), [float(v[k]) for k in "XYZ"])


def parse_krl(src, dat):
    tool = _frame(_kv(re.search(r"DECL FRAME F_SPINDLE=\{([^}]+)\}", dat).group(1)))
    base = _frame(_kv(re.search(r"DECL FRAME F_PART=\{([^}]+)\}", dat).group(1)))
    axes = {n: [float(_kv(b)[f"A{j}"]) for j in range(1, 7)]
            for n, b in re.findall(r"DECL E6AXIS XJ_(\w+)=\{([^}]+)\}", dat)}
    poses = {n: (_kv(b), re.search(r"S 'B([01]+)',T 'B([01]+)'", b).groups())
             for n, b in re.findall(r"DECL E6POS XP_(\w+)=\{([^}]+)\}", dat)}
    mass = float(re.search(r"\$LOAD\.M=([\d.]+)", src).group(1))
    cm = _kv(re.search(r"\$LOAD\.CM=\{([^}]+)\}", src).group(1))
    return tool, base, axes, poses, mass, np.array([float(cm[k]) for k in "XYZ"])


def _write(case, tmp_path, **kw):
    cf, req, p, pc = CASES[case](**kw)
    files = write_program([p], cf.controller, pc, tmp_path, header="test")
    return cf, req, p, pc, files


# ---- 1. the controller's frames --------------------------------------------------------------
@pytest.mark.parametrize("case", list(CASES))
def test_every_target_agrees_with_the_controllers_own_kinematics(tmp_path, case):
    """Each joint target through the description's forward kinematics and the tool data as
    emitted lands on its Cartesian target (0.01 mm, 0.01°); the tool points down into the part
    along the controller's tool direction (ABB z, KUKA x); the load's centre of mass is the
    cell's, moved into the controller's flange; every joint inside the limits with the margin
    and no configuration change within the cut."""
    cf, req, p, pc, files = _write(case, tmp_path)
    st = p.stations
    com0 = np.asarray(cf.mass_model.tool.com_mm, float)
    q_zero_ctrl = cf.controller_frames.joints_deg(np.zeros(6))
    if case == "kuka":
        src, dat = (f.read_text() for f in files[1:])
        tool, base, axes, poses, mass, cog = parse_krl(src, dat)
        desc, tool_dir = KR6_URDF, 0
        items = [(axes[n], base @ _frame(v)) for n, (v, _) in poses.items()]
        conf = [int(s[0], 2) for _, (_, s) in poses.items()]
    else:
        tool, mass, cog, wobj, joints, targets = parse_rapid(files[1].read_text())
        desc, tool_dir = IRB1600_URDF, 2
        items = [(joints[n], wobj @ _hom(_quat_R(*qq), pos)) for n, (pos, qq, _) in
                 targets.items()]
        conf = [tuple(c) for _, (_, _, c) in targets.items()]
    assert len(items) == len(st)
    if case == "kuka":                  # Status and Turn as emitted: the manual's rule
        for n, (_, (s_bits, t_bits)) in poses.items():
            assert (int(s_bits, 2), int(t_bits, 2)) == kuka_rule(axes[n])
    else:                               # confdata as emitted: the manual's rule
        for n, (_, _, c) in targets.items():
            assert list(c) == abb_rule(joints[n])
    for q, target in items:
        T = tool0(desc, q) @ tool
        assert np.linalg.norm(T[:3, 3] - target[:3, 3]) < 0.01
        assert _angle_deg(T[:3, :3], target[:3, :3]) < 0.01
        assert np.allclose(T[:3, tool_dir], [0, 0, -1], atol=1e-6)     # down into the part
    assert mass == pytest.approx(float(cf.mass_model.tool.mass_kg))
    F0 = tool0(desc, q_zero_ctrl)                     # the model's zero posture
    assert np.allclose(F0[:3, :3] @ cog + F0[:3, 3], com0, atol=1e-3)
    q = st[[f"q{j}_deg" for j in range(1, 7)]].to_numpy(float)
    lim = cf.joint_limits_deg
    assert np.all((q >= lim[:, 0] + 5.0 - 1e-9) & (q <= lim[:, 1] - 5.0 + 1e-9))
    inside = st["move"].isin(["entry", "cut"]).to_numpy()
    within = np.array([c for c, m in zip(conf, inside, strict=True) if m])
    if case == "kuka":
        assert len(set(within.tolist())) == 1              # one Status along the cut
    else:                                                  # one cfx; quadrants step by ≤ 1
        assert len(set(within[:, 3])) == 1
        assert np.abs(np.diff(within[:, :3], axis=0)).max() <= 1


# ---- 2. configuration data by the controllers' definitions ---------------------------------
def test_abb_confdata_follows_the_manual_on_random_postures():
    cf = parse_cell(cell_mapping(abb_cell()), "cell.yaml")
    lim = cf.joint_limits_deg
    q = np.random.default_rng(7).uniform(lim[:, 0], lim[:, 1], (3000, 6))
    got = abb_confdata(cf.robot, cf.controller_frames, q)
    want = np.array([abb_rule(cf.controller_frames.joints_deg(qq)) for qq in q])
    assert np.array_equal(got, want)
    assert len(set(want[:, 3])) == 8                   # every cfx case occurs


def test_kuka_status_and_turn_follow_the_manual_on_random_postures():
    cf = parse_cell(cell_mapping(kuka_cell()), "cell.yaml")
    lim = cf.joint_limits_deg
    q = np.random.default_rng(8).uniform(lim[:, 0], lim[:, 1], (3000, 6))
    s, t = kuka_status_turn(cf.robot, cf.controller_frames, q)
    want = np.array([kuka_rule(cf.controller_frames.joints_deg(qq)) for qq in q])
    assert np.array_equal(s, want[:, 0]) and np.array_equal(t, want[:, 1])
    assert len(set(want[:, 0])) == 8
    # the home posture of every KUKA robot: S 'B010'
    home = cf.controller_frames.model_deg(np.array([0, -90, 90, 0, 0, 0.0]))
    assert kuka_status_turn(cf.robot, cf.controller_frames, home)[0] == 2


def test_turn_and_quadrants_use_the_angles_as_printed():
    cf = parse_cell(cell_mapping(kuka_cell()), "cell.yaml")
    q = cf.controller_frames.model_deg(np.array([-2.8e-14, -90, 90, -1e-9, 30, 2.8e-14]))
    assert kuka_status_turn(cf.robot, cf.controller_frames, q)[1] == 0b000010
    ca = parse_cell(cell_mapping(abb_cell()), "cell.yaml")
    conf = abb_confdata(ca.robot, ca.controller_frames, np.array([-2.8e-14, 0, 0, -1e-9, 30, 0]))
    assert conf[:3].tolist() == [0, 0, 0]


# ---- 3. motion as a programmer writes it -----------------------------------------------------
@pytest.mark.parametrize("case", ["default", "kuka"])
def test_motion_safe_height_ramp_zones_and_retract(tmp_path, case):
    cf, req, p, pc, files = _write(case, tmp_path)
    st = p.stations
    assert list(dict.fromkeys(st["move"])) == ["safe_in", "approach", "entry", "cut",
                                               "retract", "safe_out"]
    safe = st[st["move"].isin(["safe_in", "safe_out"])]
    assert (safe["z_part_mm"] >= 50.0 - 1e-6).all()
    path = st[st["move"].isin(["entry", "cut"])][["x_part_mm", "y_part_mm",
                                                  "z_part_mm"]].to_numpy()
    d = np.diff(path, axis=0)
    slope = np.degrees(np.arctan2(-d[:, 2], np.hypot(d[:, 0], d[:, 1])))
    assert slope.max() <= 3.0 + 1e-6 and slope.max() > 2.9         # the stated angle
    assert path[0, 2] == pytest.approx(1.0) and path[:, 2].min() == pytest.approx(-0.5)
    last, ret = st[st["move"] == "cut"].iloc[-1], st[st["move"] == "retract"].iloc[0]
    up = np.array([ret[f"{a}_part_mm"] - last[f"{a}_part_mm"] for a in "xyz"])
    assert np.allclose(up[:2], 0.0, atol=1e-9) and up[2] > 0     # along the tool axis
    if case == "kuka":
        src = files[1].read_text()
        cutting = re.findall(r"LIN XP_PLAN_01_[ES]\d\d( C_DIS)?", src)
        assert cutting and all(c == " C_DIS" for c in cutting)
        assert "$APO.CDIS=0.1" in src and "$VEL.CP=0.005" in src
    else:
        text = files[1].read_text()
        cutting = re.findall(r"MoveL p_plan_01_[es]\d\d,vFeed_plan_01,(\w+),", text)
        assert cutting and set(cutting) == {"zCut"}
        assert "CONST zonedata zCut := [FALSE,0.1,0.1,0.1,0.01,0.1,0.01];" in text
        assert "ConfJ \\On;" in text and "ConfL \\On;" in text
        assert "PROC run_plan_01()" in text and "main" not in text


def test_stated_motion_settings_reach_the_program(tmp_path):
    cf, req, p, pc = plan(abb_cell(), point=(750.0, 85.0, 200.0), wobj=WOBJ,
                          program={"safe_height_mm": 80.0, "ramp_angle_deg": 5.0,
                                   "zone_cut_mm": 0.5})
    st = p.stations
    assert st.loc[st["move"] == "safe_in", "z_part_mm"].iloc[0] == pytest.approx(80.0)
    text = write_program([p], "abb", pc, tmp_path, header="t")[1].read_text()
    assert "zCut := [FALSE,0.5," in text
    with pytest.raises(Exception, match=r"p\.yaml: program\.safe_height_mm: expected at least 50"):
        plan(abb_cell(), point=(750.0, 85.0, 200.0), program={"safe_height_mm": 20.0})


# ---- 4. the spindle as the cell wires it -----------------------------------------------------
def test_spindle_started_waited_for_and_stopped(tmp_path):
    wired = {"speed": "aoSpindleSpeed", "start": "doSpindleOn", "ready": "diSpindleAtSpeed"}
    *_, files = _write("default", tmp_path / "abb", spindle=wired)
    lines = [ln.strip() for ln in files[1].read_text().splitlines()]
    i_app = lines.index("MoveL p_plan_01_app,vAir,zAir,tSpindle\\WObj:=wPart;")
    assert lines[i_app - 3:i_app] == ["SetAO aoSpindleSpeed, 27980;", "SetDO doSpindleOn, 1;",
                                      "WaitDI diSpindleAtSpeed, 1;"]
    assert lines[i_app - 4].startswith("MoveJ p_plan_01_sin,vAir,fine,")
    assert "SetDO doSpindleOn, 0;" in lines[i_app:]
    *_, files = _write("kuka", tmp_path / "kuka", spindle={"speed": 3, "speed_per_rpm": 1 / 30000,
                                                          "start": 12, "runup_s": 4.0})
    src = files[1].read_text()
    assert re.search(r"PTP XP_PLAN_01_SIN\n  WAIT SEC 0\n  \$ANOUT\[3\]=0\.932667\n  "
                     r"\$OUT\[12\]=TRUE\n  WAIT SEC 4\n  LIN XP_PLAN_01_APP", src)
    assert "LIN XP_PLAN_01_SOUT C_DIS\n  WAIT SEC 0\n  $OUT[12]=FALSE" in src


def test_without_a_spindle_interface_the_program_stops_before_the_first_cut(tmp_path):
    *_, files = _write("default", tmp_path / "abb")
    text = files[1].read_text()
    stop = text.index("Stop;")
    assert text.index('TPWrite "Set the spindle to 27980 rpm and start it') < stop
    assert stop < text.index("MoveL p_plan_01_app")
    *_, files = _write("kuka", tmp_path / "kuka")
    src = files[1].read_text()
    assert src.index("HALT") < src.index("LIN XP_PLAN_01_APP")
    assert "27980 rpm" in src


@pytest.mark.parametrize("spindle, msg", [
    ({"start": "doOn"}, r"spindle\.runup_s: .*a run-up time"),
    ({"start": 3, "runup_s": 2}, r"spindle\.start: .*an ABB signal name"),
    ({"start": "doOn", "runup_s": -1}, r"spindle\.runup_s"),
    ({"speed": "ao", "colour": 1}, r"spindle: .*keys speed"),
])
def test_bad_spindle_is_one_line(spindle, msg):
    with pytest.raises(RawDataError, match=msg) as e:
        parse_cell(cell_mapping(abb_cell(spindle=spindle)), "cell.yaml")
    assert "\n" not in str(e.value) and "cell.yaml" in str(e.value)


def test_bad_controller_frames_is_one_line():
    with pytest.raises(RawDataError, match=r"controller_frames\.joint_sign") as e:
        parse_cell(cell_mapping(kuka_cell(controller_frames={"joint_sign": [1, 2, 1, 1, 1, 1]})),
                   "cell.yaml")
    assert "\n" not in str(e.value)


# ---- 5. KRL complete -------------------------------------------------------------------------
def test_krl_load_velocities_and_no_negative_zero(tmp_path):
    *_, files = _write("kuka", tmp_path)
    src, dat = (f.read_text() for f in files[1:])
    lines = [ln.strip() for ln in src.splitlines()]
    i = lines.index("BAS(#INITMOV,0)")
    assert lines[i + 1].startswith("BAS(#VEL_PTP,") and lines[i + 2].startswith("BAS(#ACC_PTP,")
    assert "$LOAD.M=2.5" in src
    assert not re.search(r"(?<![\d.])-0(?![.\d])", src + dat)
    # Turn from the printed axis angles
    axes = dict(re.findall(r"DECL E6AXIS XJ_(\w+)=\{([^}]+)\}", dat))
    for name, body in re.findall(r"DECL E6POS XP_(\w+)=\{([^}]+)\}", dat):
        a = [float(_kv(axes[name])[f"A{j}"]) for j in range(1, 7)]
        t = re.search(r"T 'B([01]+)'", body).group(1)
        assert int(t, 2) == sum(1 << j for j, v in enumerate(a) if v < 0)


# ---- 6. frames as documented -----------------------------------------------------------------
def test_feed_directions_are_in_the_part_frame():
    """The KUKA case's work object is yawed 90°: its px cut runs along the base's +y."""
    cf, req, p, pc = CASES["kuka"]()
    cut = p.stations[p.stations["move"] == "cut"]
    d = cut[["x_base_mm", "y_base_mm"]].iloc[-1].to_numpy() - cut[
        ["x_base_mm", "y_base_mm"]].iloc[0].to_numpy()
    assert np.allclose(d / np.linalg.norm(d), [0.0, 1.0], atol=1e-9)
    dp = cut[["x_part_mm", "y_part_mm"]].iloc[-1].to_numpy() - cut[
        ["x_part_mm", "y_part_mm"]].iloc[0].to_numpy()
    assert np.allclose(dp / np.linalg.norm(dp), [1.0, 0.0], atol=1e-9)


def test_one_joint_limit_table_per_robot():
    """The load tests' IRB 1600 range is the cell's table itself (one YAML anchor)."""
    cfg = yaml.safe_load(open("config.yaml"))
    irb = [r for r in cfg["synth"]["loadtests"]["robots"] if r["name"] == "irb1600"][0]
    assert irb["limits_deg"] == cfg["cell"]["robot"]["joint_limits_deg"]
    assert open("config.yaml").read().count("IRB 1600 data sheet") == 0


# ---- 8. a small grammar of the statements the programs use ----------------------------------
NUM = r"-?\d+(\.\d+)?"
VEC = rf"\[{NUM}(,{NUM})*\]"
EXT = r"\[9E\+09(,9E\+09){5}\]"
RAPID = [r"MODULE \w+", r"ENDMODULE", r"! .*", r"PROC \w+\(\)", r"ENDPROC",
         rf"PERS tooldata \w+ := \[TRUE,\[{VEC},{VEC}\],\[{NUM},{VEC},\[1,0,0,0\],0,0,0\]\];",
         rf'PERS wobjdata \w+ := \[FALSE,TRUE,"",\[{VEC},{VEC}\],\[\[0,0,0\],\[1,0,0,0\]\]\];',
         rf"CONST zonedata \w+ := \[FALSE(,{NUM}){{6}}\];",
         rf"CONST speeddata \w+ := \[{NUM},{NUM},{NUM},{NUM}\];",
         rf"CONST jointtarget \w+ := \[{VEC},{EXT}\];",
         rf"CONST robtarget \w+ := \[{VEC},{VEC},\[-?\d+,-?\d+,-?\d+,[0-7]\],{EXT}\];",
         r"Conf[JL] \\On;", r"MoveAbsJ \w+,\w+,fine,\w+\\WObj:=\w+;",
         r"Move[JL] \w+,\w+,\w+,\w+\\WObj:=\w+;", rf"SetAO \w+, {NUM};", r"SetDO \w+, [01];",
         r"WaitDI \w+, 1;", rf"WaitTime {NUM};", r'TPWrite "[^"]*";', r"Stop;"]
KRL_SRC = [r"&ACCESS RVP", r"DEF \w+\(\)", r"END", r"; .*", r"BAS\(#\w+,\d+(\.\d+)?\)",
           rf"\$VEL\.CP={NUM}", rf"\$ACC\.CP={NUM}", rf"\$APO\.CDIS={NUM}", r"\$TOOL=\w+",
           r"\$BASE=\w+",
           rf"\$LOAD\.M={NUM}", rf"\$LOAD\.CM=\{{X {NUM},Y {NUM},Z {NUM},A 0,B 0,C 0\}}",
           r"\$LOAD\.J=\{X 0,Y 0,Z 0\}", r"PTP \w+", r"LIN \w+ C_DIS",
           rf"\$ANOUT\[\d+\]={NUM}", r"\$OUT\[\d+\]=(TRUE|FALSE)", r"WAIT FOR \$IN\[\d+\]",
           rf"WAIT SEC {NUM}", r"HALT"]
KRL_DAT = [r"&ACCESS RVP", r"DEFDAT \w+ PUBLIC", r"ENDDAT", r"; .*",
           rf"DECL FRAME \w+=\{{X {NUM},Y {NUM},Z {NUM},A {NUM},B {NUM},C {NUM}\}}",
           rf"DECL E6AXIS \w+=\{{A1 {NUM},A2 {NUM},A3 {NUM},A4 {NUM},A5 {NUM},A6 {NUM},"
           r"E1 0,E2 0,E3 0,E4 0,E5 0,E6 0\}",
           rf"DECL E6POS \w+=\{{X {NUM},Y {NUM},Z {NUM},A {NUM},B {NUM},C {NUM},"
           r"S 'B[01]{3}',T 'B[01]{6}',E1 0,E2 0,E3 0,E4 0,E5 0,E6 0\}"]


def check_grammar(text, rules):
    """Every non-empty line matches one statement of the grammar; names declared before use
    (RAPID: every target moved to is declared)."""
    pat = [re.compile(r) for r in rules]
    bad = [ln for ln in text.splitlines() if ln.strip()
           and not any(p.fullmatch(ln.strip()) for p in pat)]
    assert not bad, bad[:3]


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("wired", [False, True])
def test_every_emitted_program_parses(tmp_path, case, wired):
    spindle = None
    if wired:
        spindle = ({"speed": 1, "speed_per_rpm": 1 / 30000, "start": 2, "ready": 3}
                   if case == "kuka" else {"speed": "aoS", "start": "doS", "runup_s": 3.0})
    *_, files = _write(case, tmp_path, **({"spindle": spindle} if spindle else {}))
    if case == "kuka":
        src, dat = (f.read_text() for f in files[1:])
        check_grammar(src, KRL_SRC)
        check_grammar(dat, KRL_DAT)
        declared = set(re.findall(r"DECL \w+ (\w+)=", dat))
        assert set(re.findall(r"(?:PTP|LIN) (\w+)", src)) <= declared
    else:
        text = files[1].read_text()
        check_grammar(text, RAPID)
        declared = set(re.findall(r"(?:CONST|PERS) \w+ (\w+) :=", text))
        used = set(re.findall(r"Move\w+ (\w+),(\w+),(\w+),(\w+)", text))
        names = {n for u in used for n in u} - {"fine"}
        assert names <= declared


# ---- 7. one set of predictions ---------------------------------------------------------------
def _measured_with_modes():
    joints = pd.DataFrame({"joint": np.arange(1, 7), "k_Nm_rad": K_JOINT,
                           "ci95_low_Nm_rad": K_JOINT, "ci95_high_Nm_rad": K_JOINT,
                           "observable": True})
    modes = pd.DataFrame({"f_n_hz": [40.0, 60.0], "zeta": [0.04, 0.05],
                          "k_modal_N_m": [1e6, 2e6], "shape_x": [1.0, 0.0],
                          "shape_y": [0.0, 1.0], "shape_z": [0.0, 0.0]})
    rows = [("Ktc", 800.0), ("Krc", 240.0), ("Kac", 200.0), ("Kte", 25.0), ("Kre", 30.0),
            ("Kae", 6.0)]
    coef = pd.DataFrame({"name": [r[0] for r in rows], "value": [r[1] for r in rows],
                         "ci_low": [0.9 * r[1] for r in rows],
                         "ci_high": [1.1 * r[1] for r in rows]})
    return Measured(modes=modes, coefficients=coef, joints=joints)


def _grid_margin(req, m, cell, top_point, rotation_deg, direction_deg, rpm, depth, feed,
                 reach=None):
    """The candidate grid's pessimistic margin of one candidate (predict_grid itself, widened
    by apply_extrapolation where the study does not reach)."""
    from dataclasses import replace

    from robomill.plan.predict import apply_extrapolation, predict_grid

    sub = replace(req, placements_mm=np.asarray([top_point], float),
                  rotations_deg=np.array([rotation_deg]), direction_deg=np.array([direction_deg]),
                  direction_names=("x",), spindle_rpm=np.array([rpm]),
                  depth_mm=np.array([depth]), feed_mm_s=np.array([feed]), length_mm=1e-3)
    cand = predict_grid(sub, m, cell)
    if reach is not None:
        cand = apply_extrapolation(cand, sub, m, cell, reach)
    return float(cand["stability_margin_low"].values.ravel()[0])


@pytest.mark.parametrize("reach", [None, "speed outside the study"])
def test_no_station_below_the_grids_margin_is_emitted(tmp_path, reach):
    """Angled spindle (the rotation moves the arm and so the margin): with the limit between
    the grid's worst and best node, every emitted station's margin is the grid's own
    prediction at that pose (widened where the study's speeds do not reach 20 000 rpm) and
    meets the limit, though nodes below it exist."""
    from robomill.plan.extrapolation import StudyReach

    if reach is not None:
        reach = StudyReach(spindle_rpm=(10000.0, 15000.0))
    cf = parse_cell(cell_mapping(abb_cell(ANGLED)), "cell.yaml")
    m = _measured_with_modes()
    point = np.array([750.0, 85.0, 200.0])

    def run(limit):
        req = parse_request({
            "kind": "plan", "operation": {"length_mm": 40.0, "directions": ["py"]},
            "tool": {"diameter_mm": 6, "flutes": 2}, "placement": {"points_mm": [point.tolist()]},
            "rotations_deg": {"min": -90.0, "max": 90.0, "n": 19}, "spindle_rpm": [20000],
            "depth_mm": [0.5], "feed_mm_s": [5], "max_rotation_step_deg": 10,
            "path_stations": 5, "work_object": WOBJ,
            "constraints": {"min_stability_margin": limit}}, "p.yaml")
        cell = cell_of(cf, req, point[None])
        return req, cell, plan_cut_path("plan_01", point, 90.0, 0.5, 5.0, 20000.0, req, m, cell,
                                        req.work_object, reach=reach)

    req, cell, free = run(-1.0)
    nodes = np.asarray(free.nodes["stability_margin_low"], float)
    fin = nodes[np.isfinite(nodes)]
    limit = float(np.quantile(fin, 0.4))
    req, cell, p = run(limit)
    assert p.refused is None
    assert (nodes[np.asarray(free.nodes["feasible"])] < limit).any()     # the limit bites
    cut = p.stations[p.stations["move"] == "cut"]
    for _, r in cut.iterrows():
        top = np.array([r["x_base_mm"], r["y_base_mm"], r["z_base_mm"] + 0.5])
        g = _grid_margin(req, m, cell, top, r["rotation_deg"], 90.0, 20000.0, 0.5, 5.0, reach)
        assert r["stability_margin_low"] == pytest.approx(g, rel=1e-3)   # batch: see below
        assert g >= limit
        if reach is not None:                     # the widening took effect
            assert g < _grid_margin(req, m, cell, top, r["rotation_deg"], 90.0, 20000.0,
                                    0.5, 5.0)


# ---- 8. the figures a programmer looks at ----------------------------------------------------
def test_joint_figure_draws_every_limit_and_margin(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from robomill.plan.pathplot import joints_figure, path_figure

    cf, req, p, pc = CASES["default"]()
    lim = cf.joint_limits_deg
    fig = joints_figure(p.stations, lim, 5.0, 5.0)
    for j, ax in enumerate(fig.axes[:6]):
        ys = sorted(ln.get_ydata()[0] for ln in ax.lines if ln.get_color() == "r")
        assert ys == pytest.approx(sorted([lim[j, 0], lim[j, 1], lim[j, 0] + 5, lim[j, 1] - 5]))
        data = next(ln for ln in ax.lines if ln.get_color() != "r").get_ydata()
        assert np.allclose(data, p.stations[f"q{j + 1}_deg"])
    fig2 = path_figure(p.stations, [0, 0, -50], [300, 250, 0])
    assert len(fig2.axes) == 2


def test_the_path_and_the_plan_state_one_margin_at_the_middle_station():
    """A whole plan with the study's reach (speeds outside it: flagged and widened with the
    distance from the evidence): each runnable cut's middle station carries exactly the plan row's
    pessimistic margin (the candidate the grid chose), and no station is below the limit."""
    from robomill.plan.extrapolation import StudyReach
    from robomill.plan.make import make_plan

    cf = parse_cell(cell_mapping(abb_cell()), "cell.yaml")
    reqd = yaml.safe_load(open("plan.yaml"))
    reqd.update({"spindle_rpm": {"min": 10000.0, "max": 30000.0, "n": 12},
                 "rotations_deg": [-20.0, 0.0, 20.0], "n_cuts": 3})
    reqd["constraints"].update({"max_waviness_um": None, "min_stability_margin": 0.2})
    req = parse_request(reqd, "plan.yaml")
    cell = cell_of(cf, req, None)
    plan = make_plan(req, _measured_with_modes(), cell, [], {"tool_diameter_mm": 6.0},
                     reach=StudyReach(spindle_rpm=(9000.0, 9500.0), modal_band_hz=(5.0, 300.0)))
    rows = plan.plan.set_index("cut")
    runnable = [p for p in plan.paths if p.refused is None]
    assert runnable
    assert (rows["extrapolation_code"].astype(int) & 1).all()    # speed outside the study's
    assert (rows["interval_widening"].astype(float) > 1).all()   # widened
    for p in runnable:
        cut = p.stations[p.stations["move"] == "cut"]
        mid = cut.iloc[len(cut) // 2]
        # rel 1e-3: the grid evaluates the lobes on a frequency grid spanning its whole batch
        # of poses (robomill.plan.lobes.frequency_grid), so one pose's critical depth moves
        # with the batch by that grid's discretization (up to ~3e-4 here); the widening and
        # the speed's widening (a factor 2 and more here) lies far outside it
        assert mid["stability_margin_low"] == pytest.approx(
            float(rows.loc[p.cut, "stability_margin_low"]), rel=1e-3)
        assert (cut["stability_margin_low"] >= 0.2).all()
