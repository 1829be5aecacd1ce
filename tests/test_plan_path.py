"""The rotation along the whole path (robomill.plan.path, .cutpath) and the controller program
(robomill.plan.program*), against truths written here: hand-worked score grids for the
dynamic programming, a forward kinematics and a Jacobian written here (not the IK solver's),
and quaternions and KUKA angles worked by hand."""

import math
import re

import numpy as np
import pandas as pd
import pytest
import yaml

from robomill.io.cell import cell_mapping, parse_cell
from robomill.plan.cutpath import plan_cut_path
from robomill.plan.measured import Measured
from robomill.plan.outputs import cell_of
from robomill.plan.path import best_fixed, best_path, edges, prefer_nominal
from robomill.plan.program import program_cell, quaternion_wxyz, write_program, zyx_abc_deg
from robomill.plan.request import parse_request
from robomill.plan.workobject import BASE, parse_work_object

ANGLED = {"xyz_mm": [150.0, 0.0, 120.0], "rpy_deg": [0.0, 90.0, 0.0]}
K_JOINT = np.array([1e6, 8e5, 4e5, 6e4, 5e4, 3e4])


# ---- hand-written kinematics (independent of robomill.kinematics) --------------------------
def _rx(a):
    return np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])


def _ry(a):
    return np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])


def _rz(a):
    return np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])


def _quat_to_R(w, x, y, z):
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _flange(spec, q_deg):
    """Standard D-H: T_i = Rz(θ_i + offset) Tz(d_i) Tx(a_i) Rx(α_i), written out."""
    T = np.eye(4)
    for j, q in zip(spec["joints"], q_deg, strict=True):
        A = np.eye(4)
        th = math.radians(q + j.get("theta_offset", 0.0))
        A[:3, :3] = _rz(th) @ _rx(math.radians(j["alpha"]))
        A[:3, 3] = [j["a"] * math.cos(th), j["a"] * math.sin(th), j["d"]]
        T = T @ A
    return T


def _hom(R, p):
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


# ---- the dynamic programming on hand-worked grids --------------------------------------------
def test_path_follows_a_drifting_optimum_that_no_fixed_rotation_reaches():
    """score = −|θ − target(s)|, the target drifting 0 → 40° over 5 stations; steps ≤ 10°: the
    path tracks it exactly (worst 0), the best fixed rotation (20°) is 20° off at both ends."""
    th = np.arange(-20.0, 61.0, 10.0)
    target = np.array([0.0, 10.0, 20.0, 30.0, 40.0])
    score = -np.abs(th[None, :] - target[:, None])
    ok = np.ones(score.shape, bool)
    E = edges(th, np.zeros((5, len(th), 6)), np.zeros(score.shape, int), max_step_deg=10.0,
              dt_s=None, speed_limits_deg_s=None)
    idx, worst = best_path([score], ok, E, th)
    assert list(th[idx]) == [0.0, 10.0, 20.0, 30.0, 40.0] and worst == [0.0]
    r, fworst = best_fixed([score], ok, np.ones(len(th), bool), th)
    assert th[r] == 20.0 and fworst == [-20.0]


def test_step_limit_and_configuration_are_obeyed():
    th = np.array([0.0, 10.0, 20.0, 30.0])
    score = np.array([[0, 0, 0, 9], [0, 0, 0, 0], [9, 0, 0, 0]], float)  # wants 30 → 0
    ok = np.ones(score.shape, bool)
    cfg = np.zeros(score.shape, int)
    E = edges(th, np.zeros((3, 4, 6)), cfg, max_step_deg=10.0, dt_s=None,
              speed_limits_deg_s=None)
    idx, _ = best_path([score], ok, E, th)
    assert np.all(np.abs(np.diff(th[idx])) <= 10.0)
    # a configuration change at station 2 for rotations 0° and 10°: the path avoids them
    cfg[2, :2] = 1
    E = edges(th, np.zeros((3, 4, 6)), cfg, max_step_deg=30.0, dt_s=None,
              speed_limits_deg_s=None)
    idx, _ = best_path([-np.abs(th[None, :] - 0.0) + 0 * score], ok & (cfg == 0), E, th)
    assert th[idx][2] >= 20.0
    # every rotation flips between stations 1 and 2: no path (the cut is refused)
    cfg[2, :] = 1
    E = edges(th, np.zeros((3, 4, 6)), cfg, max_step_deg=30.0, dt_s=None,
              speed_limits_deg_s=None)
    assert best_path([score], ok, E, th)[0] is None


def test_joint_speed_limits_the_step():
    th = np.array([0.0, 10.0])
    q = np.zeros((2, 2, 6))
    q[1, 1, 5] = np.deg2rad(10.0)             # joint 6 turns 10° going to rotation 10°
    E = edges(th, q, np.zeros((2, 2), int), max_step_deg=10.0, dt_s=1.0,
              speed_limits_deg_s=np.full(6, 5.0))
    assert not E[0, 0, 1] and E[0, 0, 0]
    E = edges(th, q, np.zeros((2, 2), int), max_step_deg=10.0, dt_s=2.0,
              speed_limits_deg_s=np.full(6, 5.0))
    assert E[0, 0, 1]


def test_noise_ties_go_to_the_nominal_orientation_exactly():
    """Scores equal but for rounding noise that favours 50°: the path stays at 0° everywhere,
    and so does the choice among candidates differing only by rotation."""
    th = np.array([-50.0, -10.0, 0.0, 10.0, 50.0])
    score = 0.3 + 1e-12 * np.array([0.0, 1.0, 0.5, 2.0, 3.0])[None, :] * np.ones((4, 1))
    ok = np.ones(score.shape, bool)
    E = edges(th, np.zeros((4, 5, 6)), np.zeros(score.shape, int), max_step_deg=60.0,
              dt_s=None, speed_limits_deg_s=None)
    idx, _ = best_path([score, 1e5 + 1e-9 * score], ok, E, th)
    assert list(th[idx]) == [0.0] * 4
    t = pd.DataFrame({"placement": 0, "direction": "px", "spindle_rpm": 1e4, "depth_mm": 0.1,
                      "feed_mm_s": 1.0, "rotation_deg": th,
                      "form_error_high_um": 5.0 - 1e-12 * np.arange(5),
                      "stability_margin_low": 0.3 + 1e-13 * np.arange(5)})
    assert prefer_nominal(t)["rotation_deg"].tolist() == [0.0]
    # a real difference (1e-3 of the value) is not a tie
    t.loc[4, "form_error_high_um"] = 4.99
    assert prefer_nominal(t)["rotation_deg"].tolist() == [50.0]


# ---- whole cuts on the shipped cell and an angled spindle ---------------------------------
def _setup(tool=None, *, rotations=(-90.0, 90.0, 19), length=300.0, direction="py",
           point=(750.0, 0.0, 200.0), stations=9, margin=True, tool_com_mm=None, **extra):
    cfg = yaml.safe_load(open("config.yaml"))
    cs = cfg["cell"]
    if tool is not None:
        cs["robot"]["tool"] = tool
    if tool_com_mm is not None:      # the spindle's mass elsewhere (the modes' mass moves with it)
        cs["mass_model"]["tool"]["com_mm"] = list(tool_com_mm)
    cf = parse_cell(cell_mapping(cs), "cell.yaml")
    req = parse_request({
        "kind": "plan", "operation": {"length_mm": length, "directions": [direction]},
        "tool": {"diameter_mm": 6, "flutes": 2}, "placement": {"points_mm": [list(point)]},
        "rotations_deg": {"min": rotations[0], "max": rotations[1], "n": rotations[2]},
        "spindle_rpm": [20000], "depth_mm": [0.5], "feed_mm_s": [5],
        "max_rotation_step_deg": 10, "path_stations": stations, **extra}, "p.yaml")
    joints = pd.DataFrame({"joint": np.arange(1, 7), "k_Nm_rad": K_JOINT,
                           "ci95_low_Nm_rad": K_JOINT, "ci95_high_Nm_rad": K_JOINT,
                           "observable": True})
    m = Measured(joints=joints)
    if margin:
        modes = pd.DataFrame({"f_n_hz": [40.0, 60.0], "zeta": [0.04, 0.05],
                              "k_modal_N_m": [1e6, 2e6], "shape_x": [1.0, 0.0],
                              "shape_y": [0.0, 1.0], "shape_z": [0.0, 0.0]})
        rows = [("Ktc", 800.0), ("Krc", 240.0), ("Kac", 200.0), ("Kte", 25.0), ("Kre", 30.0),
                ("Kae", 6.0)]
        coef = pd.DataFrame({"name": [r[0] for r in rows], "value": [r[1] for r in rows],
                             "ci_low": [r[1] for r in rows], "ci_high": [r[1] for r in rows]})
        m = Measured(modes=modes, coefficients=coef, joints=joints)
    cell = cell_of(cf, req, np.array([list(point)]))
    return cs, cf, req, m, cell


def _plan(tool=None, wobj=BASE, **kw):
    cs, cf, req, m, cell = _setup(tool, **kw)
    p = plan_cut_path("cut_a", np.array(kw.get("point", (750.0, 0.0, 200.0))),
                      float(req.direction_deg[0]), 0.5, 5.0, 20000.0, req, m, cell, wobj)
    return cs, cf, p


def _k_normal_here(spec, q_deg, tool, n):
    """1/(nᵀ J_v K⁻¹ J_vᵀ n) with J_v by central differences of the FK written here."""
    Tt = _hom(_rz(math.radians(tool["rpy_deg"][2])) @ _ry(math.radians(tool["rpy_deg"][1]))
              @ _rx(math.radians(tool["rpy_deg"][0])), tool["xyz_mm"])
    J = np.zeros((3, 6))
    for i in range(6):
        d = np.zeros(6)
        d[i] = math.degrees(1e-6)
        J[:, i] = ((_flange(spec, np.add(q_deg, d)) @ Tt)[:3, 3]
                   - (_flange(spec, np.subtract(q_deg, d)) @ Tt)[:3, 3]) / 2e-6 * 1e-3
    C = J @ np.diag(1.0 / K_JOINT) @ J.T
    return 1.0 / (n @ C @ n)


def test_angled_spindle_path_beats_the_best_fixed_rotation():
    """IRB 1600 with the spindle at 90° to the flange, 150 mm off axis; a 300 mm cut along +Y.
    The stiffness normal to the wall along the emitted stations, recomputed here from the
    joint angles, has a worst value ≥ 2 % above that of every fixed rotation (each recomputed
    here at the planner's postures of that rotation)."""
    cs, cf, p = _plan(ANGLED, margin=False)
    assert p.refused is None
    cut = p.stations[p.stations["move"] == "cut"]
    n = np.array([-1.0, 0.0, 0.0])               # wall normal of a +Y cut: ẑ × ŷ = −x̂
    k_path = [_k_normal_here(cs["robot"], r[[f"q{j}_deg" for j in range(1, 7)]].to_numpy(float),
                             ANGLED, n) for _, r in cut.iterrows()]
    assert min(k_path) == pytest.approx(p.summary["path_worst_k_normal_low_N_m"], rel=1e-6)
    nodes = p.nodes
    fixed = []
    for r, th in enumerate(nodes["rotation_deg"]):
        if not nodes["feasible"][:, r].all():
            continue
        from robomill.stiffness import solve_poses, tool_rotation_redundancy
        R = tool_rotation_redundancy(np.asarray(cs["tool_rotation"], float), np.deg2rad(th))
        pts = cut[["x_base_mm", "y_base_mm", "z_base_mm"]].to_numpy()
        q, ok = solve_poses(cf.robot, pts, R, np.deg2rad(cs["q_home_deg"]))
        fixed.append(min(_k_normal_here(cs["robot"], np.rad2deg(qq), ANGLED, n) for qq in q))
    assert len(fixed) >= 3
    assert min(k_path) > 1.02 * max(fixed)
    assert len(set(cut["rotation_deg"])) > 1          # the rotation changes along the path


def test_on_axis_spindle_keeps_the_nominal_rotation():
    """A spindle on the flange axis with its mass on the axis: turning it about the tool axis
    turns joint 6 alone and moves neither the tool tip's stiffness nor the modes' mass, so
    every rotation ties and the nominal one is kept. The shipped cell's spindle mass sits
    10 mm off the axis: turning it moves the modal mass (the margin by about 1 % over ±55°),
    and the planner takes the better rotation."""
    on_axis = [880.0, 0.0, 1186.5]
    cs, cf, p = _plan(None, rotations=(-55.0, 55.0, 12), length=40.0, stations=5,
                      tool_com_mm=on_axis)
    assert p.refused is None
    assert set(p.stations["rotation_deg"]) == {0.0}
    assert p.summary["fixed_rotation_deg"] == 0.0
    cs, cf, p = _plan(None, rotations=(-55.0, 55.0, 12), length=40.0, stations=5)
    margin = p.nodes["stability_margin_low"]
    assert 0.005 < np.ptp(margin) / margin.max() < 0.05
    assert set(p.stations["rotation_deg"]) != {0.0}


def test_a_path_through_the_wrist_singularity_is_refused_and_never_emitted(tmp_path):
    """Tool down over x = 560 … 660 mm at z = 150 mm the IRB 1600's wrist angle q5 passes
    through 0 (−3° → +2°): the configuration flips. Rotating about an on-axis tool cannot avoid
    it, so the cut is refused and the program leaves it out."""
    for wrist_min in (0.0, 5.0):
        cs, cf, p = _plan(None, rotations=(-30.0, 30.0, 7), length=100.0, direction="px",
                          point=(610.0, 0.0, 150.5), stations=11,
                          min_wrist_angle_deg=wrist_min)
        assert p.refused is not None
        files = write_program([p], "abb", program_cell(cf.robot, np.eye(4)), tmp_path,
                              header="refused")
        text = files[1].read_text()
        assert "cut_a" not in text
        assert len(pd.read_csv(files[0])) == 0


# ---- the program ------------------------------------------------------------------------------
def test_quaternions_and_kuka_angles_by_hand():
    s = math.sqrt(0.5)
    assert np.allclose(quaternion_wxyz(np.diag([1.0, -1.0, -1.0])), [0, 1, 0, 0])  # tool down
    assert np.allclose(quaternion_wxyz(_rz(math.radians(90))), [s, 0, 0, s])
    assert np.allclose(quaternion_wxyz(_ry(math.radians(90))), [s, 0, s, 0])
    assert np.allclose(quaternion_wxyz(np.diag([-1.0, -1.0, 1.0])), [0, 0, 0, 1])
    # half turn about (cos 20°, −sin 20°, 0): written with its first non-zero part positive
    c, sn = math.cos(math.radians(20)), math.sin(math.radians(20))
    ax = np.array([c, -sn, 0.0])
    R = 2 * np.outer(ax, ax) - np.eye(3)
    assert np.allclose(quaternion_wxyz(R), [0, c, -sn, 0])
    assert np.allclose(quaternion_wxyz(2 * np.outer(-ax, -ax) - np.eye(3)), [0, c, -sn, 0])
    # 120° about (1, 1, 1)/√3: w = cos 60° = 0.5, (x, y, z) = sin 60°/√3 = 0.5 each
    R = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    assert np.allclose(quaternion_wxyz(R), [0.5, 0.5, 0.5, 0.5])
    # a rotation of −90° about z written with w < 0 is returned with w > 0
    q = quaternion_wxyz(_rz(math.radians(-90)))
    assert q[0] > 0 and np.allclose(q, [s, 0, 0, -s])
    assert np.allclose(zyx_abc_deg(np.diag([1.0, -1.0, -1.0])), [0, 0, 180])
    R = _rz(math.radians(30)) @ _ry(math.radians(20)) @ _rx(math.radians(10))
    assert np.allclose(zyx_abc_deg(R), [30, 20, 10])
    assert np.allclose(zyx_abc_deg(_ry(math.radians(-45))), [0, -45, 0])


def _num_list(s):
    return [float(x) for x in s.split(",")]


def _check_abb(text, spec, tol_mm=0.01):
    tool = re.search(r"PERS tooldata tSpindle := \[TRUE,\[\[([^\]]+)\],\[([^\]]+)\]\]", text)
    wobj = re.search(r'PERS wobjdata wPart := \[FALSE,TRUE,"",\[\[([^\]]+)\],\[([^\]]+)\]\]',
                     text)
    Tt = _hom(_quat_to_R(*_num_list(tool.group(2))), _num_list(tool.group(1)))
    Tw = _hom(_quat_to_R(*_num_list(wobj.group(2))), _num_list(wobj.group(1)))
    joints = dict(re.findall(r"CONST jointtarget j_(\w+) := \[\[([^\]]+)\]", text))
    targets = re.findall(r"CONST robtarget p_(\w+) := \[\[([^\]]+)\],\[([^\]]+)\]", text)
    assert targets and set(joints) == {t[0] for t in targets}
    for name, pos, quat in targets:
        T = _flange(spec, _num_list(joints[name])) @ Tt
        target = Tw @ _hom(_quat_to_R(*_num_list(quat)), _num_list(pos))
        assert np.linalg.norm(T[:3, 3] - target[:3, 3]) < tol_mm, name
        assert np.allclose(T[:3, :3], target[:3, :3], atol=1e-6), name
    return len(targets)


def _abc_R(a, b, c):
    return _rz(math.radians(a)) @ _ry(math.radians(b)) @ _rx(math.radians(c))


def _check_kuka(src, dat, spec, tol_mm=0.01):
    def frame(text):
        v = dict(re.findall(r"([XYZABC]) (-?[\d.e+-]+)", text))
        return _hom(_abc_R(*(float(v[k]) for k in "ABC")), [float(v[k]) for k in "XYZ"])

    Tt = frame(re.search(r"DECL FRAME F_SPINDLE=\{([^}]+)\}", dat).group(1))
    Tw = frame(re.search(r"DECL FRAME F_PART=\{([^}]+)\}", dat).group(1))
    axes = {n: [float(x) for x in re.findall(r"A\d (-?[\d.e+-]+)", body)[:6]]
            for n, body in re.findall(r"DECL E6AXIS XJ_(\w+)=\{([^}]+)\}", dat)}
    poses = re.findall(r"DECL E6POS XP_(\w+)=\{([^}]+)\}", dat)
    assert poses and set(axes) == {n for n, _ in poses}
    for name, body in poses:
        T = _flange(spec, axes[name]) @ Tt
        target = Tw @ frame(body)
        assert np.linalg.norm(T[:3, 3] - target[:3, 3]) < tol_mm, name
        assert np.allclose(T[:3, :3], target[:3, :3], atol=1e-5), name
    for name, _ in poses:
        assert f"LIN XP_{name}" in src or f"PTP XP_{name}" in src
    return len(poses)


@pytest.mark.parametrize("tool", [None, ANGLED])
def test_every_program_target_lands_on_its_cartesian_target(tmp_path, tool):
    """RAPID and KRL: each joint target through the FK written here (with the tool and work
    object the program itself states) reaches its Cartesian target within 0.01 mm; no
    station leaves the joint limits or changes configuration."""
    wobj = parse_work_object({"frame": {"xyz_mm": [600.0, -120.0, 200.0],
                                        "rpy_deg": [0.0, 0.0, 30.0]},
                              "block_mm": {"min": [-300, -300, -60], "max": [400, 400, 0]}},
                             "p.yaml")
    kw = ({"rotations": (-55.0, 55.0, 12), "length": 40.0, "stations": 5} if tool is None
          else {})
    cs, cf, p = _plan(tool, wobj=wobj, **kw)
    assert p.refused is None
    st = p.stations
    q = st[[f"q{j}_deg" for j in range(1, 7)]].to_numpy(float)
    lim = cf.joint_limits_deg
    assert np.all((q >= lim[:, 0] + 5.0) & (q <= lim[:, 1] - 5.0))
    assert st["configuration"].nunique() == 1
    # the slot floor: 0.5 mm below the block's top; approach and retract above the part
    cut = st[st["move"] == "cut"]
    assert np.allclose(cut["z_part_mm"], -0.5, atol=1e-6)
    assert (st.loc[~st["move"].isin(["cut", "entry"]), "z_part_mm"] > 0).all()
    assert (st.loc[st["move"] == "entry", "z_part_mm"] >= -0.5 - 1e-9).all()
    # the model's own frames (no controller_frames): the FK of the model written here
    pc = program_cell(cf.robot, wobj.T_base_part, cf.mass_model)
    abb = write_program([p], "abb", pc, tmp_path / "abb", header="test")
    assert _check_abb(abb[1].read_text(), cs["robot"]) == len(st)
    text = abb[1].read_text()
    assert text.count("MoveJ") == 1 and text.count("MoveL") == len(st) - 1
    assert "vFeed_cut_a := [5," in text and "Set the spindle to 20000 rpm" in text
    kuka = write_program([p], "kuka", pc, tmp_path / "kuka", header="test")
    src, dat = (f.read_text() for f in kuka[1:])
    assert _check_kuka(src, dat, cs["robot"]) == len(st)
    assert "$VEL.CP=0.005" in src and "20000 rpm" in src


# ---- the part and the slots -----------------------------------------------------------------
def test_segment_distance_by_hand():
    from robomill.plan.slots import segment_distance_mm

    assert segment_distance_mm([0, 0], [10, 0], [5, -5], [5, 5]) == 0.0          # crossing
    assert segment_distance_mm([0, 0], [10, 0], [0, 3], [10, 3]) == pytest.approx(3.0)
    assert segment_distance_mm([0, 0], [10, 0], [13, 4], [20, 4]) == pytest.approx(5.0)  # 3-4-5


def test_planned_slots_lie_on_the_block_and_cross_nothing():
    """The whole plan on a small grid: every planned slot's floor stations lie inside the
    block at their depth, and no two slots (nor a slot and the study's cut placed across the
    best placement) come closer than a tool diameter."""
    from robomill.experiment import Cut
    from robomill.plan.make import make_plan
    from robomill.plan.slots import segment_distance_mm

    cs, cf, _, m, _ = _setup(None)
    reqd = yaml.safe_load(open("plan.yaml"))
    reqd.update({"spindle_rpm": {"min": 10000.0, "max": 30000.0, "n": 20},
                 "rotations_deg": [-20.0, 0.0, 20.0]})
    reqd["constraints"]["max_waviness_um"] = None
    req = parse_request(reqd, "plan.yaml")
    # the study's cut is an earlier plan's (plan_02): the planned ids number on after it, and
    # its verdict enters as evidence on the stability limit
    study = [Cut(id="plan_02", set=None, segment=None, feed_mm_s=1.0, depth_mm=0.25,
                 direction="px", spindle_rpm=1e4,
                 flutes=2, tool_diameter_mm=6.0, start_mm=(680.0, 90.0, 199.75))]
    cell = cell_of(cf, req, None)
    plan = make_plan(req, m, cell, study, {"cut_length_mm": 100.0, "tool_diameter_mm": 6.0},
                     stability=pd.Series({"plan_02": 1.0}))
    ids = list(plan.plan["cut"])
    assert ids == [f"plan_{i:02d}" for i in range(3, 3 + len(ids))]
    assert [p.cut for p in plan.paths] == ids == [c["id"] for c in plan.manifest["cuts"]]
    assert plan.evidence["cut"].tolist() == ["plan_02"]
    assert plan.candidates.attrs["stability_evidence_cuts"] == int(plan.evidence["used"].sum())
    wobj = req.work_object
    slots = [((680.0, 90.0), (780.0, 90.0))]
    for p in plan.paths:
        assert p.refused is None
        cut = p.stations[p.stations["move"] == "cut"]
        part = cut[["x_part_mm", "y_part_mm", "z_part_mm"]].to_numpy()
        depth = float(plan.plan.set_index("cut").loc[p.cut, "depth_mm"])
        assert np.allclose(part[:, 2], wobj.block_max_mm[2] - depth, atol=1e-6)
        assert np.all(part[:, :2] - 3.0 >= wobj.block_min_mm[:2] - 1e-6)
        assert np.all(part[:, :2] + 3.0 <= wobj.block_max_mm[:2] + 1e-6)
        slots.append((tuple(cut[["x_base_mm", "y_base_mm"]].iloc[0]),
                      tuple(cut[["x_base_mm", "y_base_mm"]].iloc[-1])))
    for i in range(len(slots)):
        for j in range(i):
            assert segment_distance_mm(*slots[i], *slots[j]) >= 6.0 - 1e-6
    starts = [c["start_mm"] for c in plan.manifest["cuts"]]
    for s, p in zip(starts, plan.paths, strict=True):
        first = p.stations[p.stations["move"] == "cut"].iloc[0]
        assert np.allclose(s, first[["x_base_mm", "y_base_mm", "z_base_mm"]].to_numpy(float))


@pytest.mark.parametrize("value, msg", [
    ({"frame": {"xyz_mm": [0, 0]}}, r"p\.yaml: work_object\.frame\.xyz_mm: expected \[x, y, z\]"),
    ({"frame": {"xyz_mm": [0, 0, 0], "rpy_deg": [10, 0, 0]}},
     r"work_object\.frame\.rpy_deg: expected roll = pitch = 0"),
    ({"frame": {"xyz_mm": [0, 0, 0]}, "block_mm": {"min": [0, 0, 0], "max": [1, 1, 0]}},
     r"work_object\.block_mm\.max: expected every coordinate above min's"),
    ({"block_mm": {}}, r"work_object: expected a mapping \{frame"),
])
def test_bad_work_object_is_one_line(value, msg):
    from robomill.plan.request import PlanRequestError

    reqd = yaml.safe_load(open("plan.yaml"))
    reqd["work_object"] = value
    with pytest.raises(PlanRequestError, match=msg) as e:
        parse_request(reqd, "p.yaml")
    assert "\n" not in str(e.value)


def test_the_nominal_rotation_is_always_a_candidate():
    reqd = yaml.safe_load(open("plan.yaml"))
    reqd["rotations_deg"] = {"min": -55.0, "max": 55.0, "n": 12}     # 0 is not on this grid
    assert 0.0 in parse_request(reqd, "p.yaml").rotations_deg


def test_path_summary_says_why_the_rotation_stays_nominal():
    from robomill.plan.pathout import path_summary, pose_failure_table, summary_values

    failures = pd.DataFrame({"reason": ["ok", "ik", "joint_limit", "singularity",
                                        "configuration_change"], "count": [8, 0, 1, 2, 1]})
    plan = pd.DataFrame({"cut": ["plan_01", "plan_02"], "redundancy_path_deg": ["0;0;0", "0;0"],
                         "path_gain_a_crit": [1.0, 1.0], "path_gain_stiffness": [1.0, 1.0],
                         "path_refused": ["", "no path"]})
    v = summary_values(path_summary(failures, plan, 4.9e-7, ["plan_02: moved to placement 3"]))
    assert v["rotation_case"] == "nominal_tie" and v["path_gain_case"] == "none"
    assert v["candidates"] == 12 and v["candidates_singularity"] == 2
    assert v["cuts_runnable"] == 1 and v["cuts_refused"] == 1 and v["slots_moved"] == 1
    # the rotation matters (0.5 %) but 0° is still best; a turned path
    assert summary_values(path_summary(failures, plan, 0.5))["rotation_case"] == "nominal_best"
    plan.loc[0, "redundancy_path_deg"] = "0;10;10"
    plan.loc[0, "path_gain_stiffness"] = 1.03
    v = summary_values(path_summary(failures, plan, 0.5))
    assert v["rotation_case"] == "turned" and v["path_gain_case"] == "gain"
    assert v["path_gain_stiffness_cut"] == "plan_01"
    assert pose_failure_table(xr_status(np.array([0, 0, 3, 4, 2]))).set_index("reason")[
        "count"].to_dict() == {"ok": 2, "ik": 0, "joint_limit": 1, "singularity": 1,
                               "configuration_change": 1}


def xr_status(codes):
    import xarray as xr

    return xr.Dataset({"pose_status": (("placement",), codes)})


def test_an_unbounded_margin_is_the_best_score_not_an_unusable_node():
    """+inf (no finite critical depth) ranks above every finite score; NaN stays unusable."""
    th = np.array([0.0, 10.0, 20.0])
    score = np.array([[1.0, np.inf, 2.0], [1.0, np.inf, np.nan], [1.0, np.inf, 2.0]])
    E = edges(th, np.zeros((3, 3, 6)), np.zeros((3, 3), int), max_step_deg=10.0, dt_s=None,
              speed_limits_deg_s=None)
    idx, worst = best_path([score], np.ones((3, 3), bool), E, th)
    assert list(th[idx]) == [10.0, 10.0, 10.0] and worst == [np.inf]
    r, _ = best_fixed([score], np.ones((3, 3), bool), np.ones(3, bool), th)
    assert th[r] == 10.0


def test_a_station_below_the_margin_constraint_refuses_the_cut():
    """The pessimistic margin is checked at every station, not only at the cut's middle."""
    cs, cf, p = _plan(None, rotations=(-20.0, 20.0, 5), length=40.0, stations=5)
    worst = p.summary["path_worst_stability_margin_low"]
    best = max(p.stations["stability_margin_low"].dropna())
    assert worst < best
    cs, cf, p = _plan(None, rotations=(-20.0, 20.0, 5), length=40.0, stations=5,
                      constraints={"min_stability_margin": (worst + best) / 2})
    assert p.refused is not None and "stability margin at every station" in p.refused


def test_path_summary_says_when_only_the_path_runs_a_cut():
    """A runnable cut no fixed rotation can run (fixed rotation NaN, gain NaN) is named, and
    with no ratio at all the gain case says so instead of "not computed"."""
    from robomill.plan.pathout import path_summary, summary_values

    failures = pd.DataFrame({"reason": ["ok"], "count": [3]})
    plan = pd.DataFrame({"cut": ["plan_01", "plan_02"], "redundancy_path_deg": ["0;10", "0;0"],
                         "fixed_rotation_deg": [np.nan, 0.0],
                         "path_gain_a_crit": [np.nan, 1.0], "path_gain_stiffness": [np.nan, 1.0],
                         "path_refused": ["", ""]})
    v = summary_values(path_summary(failures, plan, 0.5))
    assert v["cuts_path_only"] == 1 and v["path_only_cuts"] == "plan_01"
    assert v["path_gain_case"] == "none"
    plan.loc[1, ["fixed_rotation_deg", "path_gain_a_crit", "path_gain_stiffness"]] = np.nan
    v = summary_values(path_summary(failures, plan, 0.5))
    assert v["path_gain_case"] == "path_only" and v["path_only_cuts"] == "plan_01;plan_02"
