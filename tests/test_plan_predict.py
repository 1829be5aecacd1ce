"""The planner's predictions (robomill.plan.lobes, .measured, .predict) against truths written
independently: the package's own single-tool solvers, the closed-form scaling of a single
mode's lobes with its stiffness, and a planted gear error carried through the Jacobian."""

import numpy as np
import pandas as pd
import pytest
import yaml

from robomill.chatter import CuttingModel, ModeXY, tool_from_modes, zoa_lobes
from robomill.chatter.coupling import coupling_depth
from robomill.chatter.lobes_zoa import default_frequency_grid
from robomill.chatter.slot_model import mode_coupling
from robomill.kinematics import robot_from_mapping
from robomill.plan.lobes import batch_zoa_lobes
from robomill.plan.measured import Measured, gear_joint_amplitudes, waviness_um
from robomill.plan.predict import Cell, critical_depth_m, predict_grid
from robomill.plan.request import parse_request
from robomill.stiffness import solve_poses

MODES = [ModeXY(250.0, 0.03, 8e6, (0.9, 0.3)), ModeXY(320.0, 0.025, 1.2e7, (0.2, 1.0))]


def _arrays(modes, n=1):
    fn = np.array([[m.f_hz for m in modes]] * n)
    k = np.array([[m.k_N_m for m in modes]] * n)
    z = np.array([m.zeta for m in modes])
    sh = np.array([[m.shape for m in modes]] * n)
    return fn, z, k, sh


def test_batch_lobes_match_the_single_tool_solver():
    cut = CuttingModel.from_immersion(3, 7e8, 0.3, 0.5, "down")
    rpm = np.linspace(3000, 15000, 300)
    tool = tool_from_modes(MODES)
    f = default_frequency_grid(tool)
    a_ref, _ = zoa_lobes(tool, cut, rpm, f_hz=f)
    a = batch_zoa_lobes(*_arrays(MODES, 3), cut, rpm, f_hz=f)
    assert a.shape == (3, 300)
    ok = np.isfinite(a_ref)
    assert ok.sum() > 250
    assert np.allclose(a[1][ok], a_ref[ok], rtol=1e-9)
    # on its own frequency grid: the same lobes but for the sharp lobe intersections
    a_own = batch_zoa_lobes(*_arrays(MODES, 1), cut, rpm)[0]
    assert np.quantile(np.abs(a_own[ok] / a_ref[ok] - 1), 0.95) < 1e-3


def test_one_coupling_routine_serves_the_batch_and_the_thesis_check():
    """The delay-free depth by the one routine, against the instability of A + a B W̄ C built
    here by hand (two modes): stable just below, unstable just above."""
    modes = [ModeXY(20.0, 0.04, 8e5, (0.29, 0.94)), ModeXY(35.0, 0.035, 1.2e6, (0.94, 0.19))]
    cut = CuttingModel(2, 7.96e8, 0.21, 0.0, np.pi)
    ref = mode_coupling(modes, cut, depth_max_m=0.02)["a_mc_m"]
    a = coupling_depth(*_arrays(modes, 2), cut, rtol=1e-6)
    assert np.isfinite(ref)
    assert np.allclose(a, ref, rtol=0.01)    # the thesis check's own resolution

    def rate(depth):
        n = 2 * len(modes)
        A, B, C = np.zeros((n, n)), np.zeros((n, 2)), np.zeros((2, n))
        for r, m in enumerate(modes):
            w = 2 * np.pi * m.f_hz
            A[2 * r, 2 * r + 1], A[2 * r + 1, 2 * r] = 1.0, -w**2
            A[2 * r + 1, 2 * r + 1] = -2 * m.zeta * w
            B[2 * r + 1] = np.asarray(m.shape) * w**2 / m.k_N_m
            C[:, 2 * r] = m.shape
        return np.linalg.eigvals(A + depth * B @ cut.mean_matrix() @ C).real.max()

    assert rate(a[0] * 0.999) < 0 < rate(a[0] * 1.001)


@pytest.fixture(scope="module")
def robot():
    cfg = yaml.safe_load(open("config.yaml"))
    return robot_from_mapping(cfg["cell"]["robot"]), cfg["cell"]


def _coefficients():
    rows = [("Ktc", 800.0), ("Krc", 240.0), ("Kac", 200.0), ("Kte", 25.0), ("Kre", 30.0),
            ("Kae", 6.0)]
    return pd.DataFrame({"name": [r[0] for r in rows], "value": [r[1] for r in rows],
                         "ci_low": [r[1] for r in rows], "ci_high": [r[1] for r in rows]})


def test_robot_mode_scales_with_the_pose_stiffness(robot):
    """One robot mode along base Y: its lobes' minimum depth scales with the joint model's
    stiffness along Y, k_y(q)/k_y(q_ref) = (yᵀ C_ref y)/(yᵀ C(q) y), computed here from the
    Jacobian column by column."""
    rb, cellspec = robot
    R0 = np.asarray(cellspec["tool_rotation"], float)
    q0 = np.deg2rad(cellspec["q_home_deg"])
    k_joint = np.array([1e6, 8e5, 4e5, 6e4, 5e4, 3e4])
    joints = pd.DataFrame({"joint": np.arange(1, 7), "k_Nm_rad": k_joint,
                           "ci95_low_Nm_rad": k_joint, "ci95_high_Nm_rad": k_joint,
                           "observable": True})
    modes = pd.DataFrame({"f_n_hz": [40.0], "zeta": [0.04], "k_modal_N_m": [1e6],
                          "shape_x": [0.0], "shape_y": [1.0], "shape_z": [0.0]})
    ref = np.array([650.0, 0.0, 200.0])
    pts = np.array([[450.0, 0.0, 300.0], [950.0, 0.0, 150.0]])
    req = parse_request({"kind": "plan", "operation": {"length_mm": 20, "directions": ["px"]},
                         "tool": {"diameter_mm": 6, "flutes": 2},
                         "placement": {"points_mm": pts.tolist()}, "spindle_rpm": [1000],
                         "depth_mm": [0.1], "feed_mm_s": [1]})
    cell = Cell(rb, R0, q0, ref)
    m = Measured(modes=modes, coefficients=_coefficients(), joints=joints)
    q, ok = solve_poses(rb, np.vstack([ref, pts]), R0, q0)
    assert ok.all()

    def kx(qq):
        J = np.asarray(rb.jacobian(qq))[:3] * 1e-3
        return 1.0 / sum(J[1, j] ** 2 / k_joint[j] for j in range(6))

    truth = np.array([kx(q[1]) / kx(q[0]), kx(q[2]) / kx(q[0])])
    assert abs(truth[0] - truth[1]) > 0.5                       # the poses differ
    frames = np.broadcast_to(np.eye(3)[:, [1, 0, 2]], (2, 3, 3))  # feed Y, normal X
    rpm = np.linspace(200, 2000, 3000)
    a = critical_depth_m(m, cell, req, q[1:], frames, rpm, corners=False)["nominal"]
    a_ref = critical_depth_m(Measured(modes=modes, coefficients=_coefficients()), cell, req,
                             q[1:], frames, rpm, corners=False)["nominal"]
    assert np.allclose(a_ref.min(1), a_ref.min(1)[0], rtol=1e-3)  # no joints: no pose effect
    assert np.allclose(a.min(1) / a_ref.min(1), truth, rtol=0.01)


def test_gear_error_carried_to_a_new_pose(robot):
    """A planted 5 µrad error of joint 2 seen on one tracker path is predicted on a path
    elsewhere as 5 µrad × |nᵀ J_v[:, 2]| there."""
    rb, cellspec = robot
    R0 = np.asarray(cellspec["tool_rotation"], float)
    q0 = np.deg2rad(cellspec["q_home_deg"])
    q, ok = solve_poses(rb, np.array([[700.0, 0.0, 200.0], [600.0, -150.0, 200.0]]), R0, q0)
    assert ok.all()
    dq = 5e-6
    u_meas = np.array([0.0, 1.0, 0.0])          # the tracker path: along +Y
    lateral = np.cross([0, 0, 1.0], u_meas)
    J_meas = np.asarray(rb.jacobian(q[0]))[:3, 1] * 1e3          # µm/rad
    peaks = pd.DataFrame({"mechanism": ["gear"], "joint": [2], "stage": ["motor"],
                          "order": ["mesh"], "component": ["lateral"], "cut": ["c1"],
                          "amplitude_um": [dq * abs(lateral @ J_meas)]})
    gears = gear_joint_amplitudes(peaks, rb, {"c1": (q[0], u_meas)})
    assert len(gears) == 1
    assert gears.loc[0, "dq_urad"] == pytest.approx(5.0, rel=1e-9)
    n_new = np.cross([0.0, 0.0, 1.0], [1.0, 0.0, 0.0])     # the new path along +X: wall normal
    w = waviness_um(rb, q[1], n_new, gears)["nominal"]
    J_new = np.asarray(rb.jacobian(q[1]))[:3, 1] * 1e3
    assert w == pytest.approx(dq * abs(n_new @ J_new), rel=1e-9)
    # the element counts as waviness only if it completes >= 2.5 periods along the 40 mm cut:
    # dq2/ds from the Jacobian, order × |dq2/ds| × 40 / 2π cycles
    Jsi = np.asarray(rb.jacobian(q[1])) * np.r_[1e-3, 1e-3, 1e-3, 1, 1, 1][:, None]
    rate = abs(np.linalg.solve(Jsi, np.r_[1e-3, 0, 0, 0, 0, 0])[1])
    fast, slow = 5.0 / (rate * 40 / (2 * np.pi)), 1.0 / (rate * 40 / (2 * np.pi))
    kw = {"direction": np.array([1.0, 0, 0]), "length_mm": 40.0}
    key = (2, "motor", "mesh")
    assert waviness_um(rb, q[1], n_new, gears, orders={key: fast}, **kw)["nominal"] == \
        pytest.approx(w, rel=1e-12)
    assert waviness_um(rb, q[1], n_new, gears, orders={key: slow}, **kw)["nominal"] == 0.0


def test_missing_measurements_leave_nan_and_say_so(robot):
    rb, cellspec = robot
    req = parse_request({"kind": "plan", "operation": {"length_mm": 20, "directions": ["py"]},
                         "tool": {"diameter_mm": 6, "flutes": 2},
                         "placement": {"points_mm": [[650, 0, 200]]},
                         "rotations_deg": [0, 30], "spindle_rpm": [20000, 25000],
                         "depth_mm": [0.1], "feed_mm_s": [1, 2]})
    cell = Cell(rb, np.asarray(cellspec["tool_rotation"], float),
                np.deg2rad(cellspec["q_home_deg"]), np.array([650.0, 0, 200]))
    ds = predict_grid(req, Measured(coefficients=_coefficients()), cell)
    assert bool(ds["reachable"].all())
    assert ds["stability_margin_low"].isnull().all() and ds["waviness_um"].isnull().all()
    assert ds["deflection_normal_um"].isnull().all()
    assert np.isfinite(ds["force_N"]).all()
    assert "stability_margin: no impact test" in ds.attrs["missing_predictions"]
    assert "waviness: no tracker runs" in ds.attrs["missing_predictions"]
    assert float(ds["mrr_mm3_s"].sel(depth_mm=0.1, feed_mm_s=2)) == pytest.approx(0.1 * 6 * 2)
