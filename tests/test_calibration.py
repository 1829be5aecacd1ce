"""Chapter-1 calibration with exact truth: circle fit, eq. 1.4, identification on the virtual
robot (noise-free: every planted parameter; noisy: within 2x the instrument-noise floor)."""

import copy

import numpy as np
import pytest

from robomill import calibration as cal
from robomill.kinematics import rodrigues
from robomill.synth import ctrack as sc
from robomill.synth.cell import cell_from_config

ARCSEC = np.pi / 180 / 3600


def test_circle_fit_recovers_planted_axis_noise_free():
    e = np.array([0.3, -0.4, 0.866])
    e /= np.linalg.norm(e)
    centre = np.array([120.0, -40.0, 600.0])
    x0 = np.cross(e, [1.0, 0, 0])
    x0 = 350.0 * x0 / np.linalg.norm(x0) + 25.0 * e  # target off the centre's plane
    q = np.deg2rad(np.linspace(-50, 70, 15))
    P = centre + 25.0 * e * 0 + np.einsum("mij,j->mi", rodrigues(e, q), x0)
    f = cal.fit_circle(P)
    assert np.allclose(f.axis, e, atol=1e-9)  # sign: the points turn positively about e
    foot = centre + 25.0 * e
    assert np.allclose(f.centre, foot, atol=1e-9)
    assert f.radius == pytest.approx(350.0, abs=1e-9)
    assert f.rms_mm < 1e-9
    f2 = cal.fit_circle(P[::-1])
    assert np.allclose(f2.axis, -e, atol=1e-9)


def test_circle_fit_rejects_too_few_or_collinear_points():
    with pytest.raises(ValueError, match="at least 3"):
        cal.fit_circle(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="collinear"):
        cal.fit_circle(np.c_[np.arange(5.0), np.zeros(5), np.zeros(5)])


def test_vector_model_eq14_equals_dh(raw_config):
    from robomill.kinematics import robot_from_mapping

    robot = robot_from_mapping(raw_config["cell"]["robot"])
    vm = cal.vector_model_from_serial(robot)
    q = np.random.default_rng(3).uniform(-2, 2, size=(50, 6))
    assert np.abs(vm.tcp(q) - robot.fk(q)[:, :3, 3]).max() < 1e-9
    # every link point by the same product of exponentials
    R, t = vm.link_poses(q)
    F = robot.frames(q)
    x0 = robot.frames(np.zeros(6))[5, :3, 3]  # origin of frame 5 rides on link 5
    assert np.allclose(np.einsum("mij,j->mi", R[:, 4], x0) + t[:, 4], F[:, 5, :3, 3], atol=1e-9)


def test_joint_angle_eq15_and_base_eq16_signed():
    e = np.array([0.0, 0.0, 1.0])
    p0 = np.array([100.0, 0, 5])
    pm = np.einsum("mij,j->mi", rodrigues(e, np.array([-0.3, 0.2, 1.0])), p0)
    assert np.allclose(cal.joint_angle_eq15(np.zeros(3), e, p0, pm), [-0.3, 0.2, 1.0])
    v = np.array([100.0, 20.0, 0.0])  # P2P1 normal to the tilt axis
    d = cal.base_deflection_eq16(v, np.zeros(3), rodrigues(e, -1e-5) @ v, np.zeros(3), axis=e)
    assert d == pytest.approx(-1e-5, rel=1e-6)


def test_joint_error_fit_recovers_planted_fourier_and_polynomial():
    q = np.deg2rad(np.arange(-40, 40, 0.05))
    truth = 2e-5 * np.sin(8 * q + 0.3) + 1e-5 * np.sin(320 * q - 1.0) + 3e-6 - 4e-6 * q
    f = cal.fit_joint_error(2, q, truth, [8.0, 320.0], max_degree=3)
    assert np.abs(f(q) - truth).max() < 1e-12
    assert np.hypot(f.sin, f.cos) == pytest.approx([2e-5, 1e-5], rel=1e-8)
    assert f.validation["fourier+polynomial"] < 1e-12 < f.validation["polynomial"]


@pytest.fixture(scope="module")
def raw_config(repo):
    """config.yaml as written (its synth and calibration sections are complete), so these
    tests do not depend on the validation of other chapters' sections."""
    import yaml

    return yaml.safe_load((repo / "config.yaml").read_text())


@pytest.fixture(scope="module")
def study(raw_config):
    cfg = copy.deepcopy(raw_config)
    return cfg, cell_from_config(cfg)


def _cell_orders(cfg):
    """The Fourier orders from the cell's transmissions (as the pipeline derives them)."""
    from robomill.io.cell import cell_mapping, parse_cell

    return parse_cell(cell_mapping(cfg["cell"]), "cell.yaml").fourier_orders()


def _cell_masses(cfg):
    """The gravity model from the cell file's mass_model (as the pipeline reads it)."""
    from robomill.io.cell import cell_mapping, parse_cell

    return cal.mass_model_from_cell(parse_cell(cell_mapping(cfg["cell"]), "cell.yaml"))


def _identify(cfg, cell, noise, masses="cell"):
    tabs = {t: sc.simulate_table(cfg, cell, t, noise_mm=noise) for t in sc.TABLES}
    c = cfg["calibration"]
    ident = cal.identify(tabs["circles"], tabs["home"], tabs["steps"], tabs["loads"],
                         tabs["base"], masses=_cell_masses(cfg) if masses == "cell" else masses,
                         fixture_offset_mm=c["fixture_offset_mm"],
                         orders={i + 1: o for i, o in enumerate(_cell_orders(cfg))})
    return tabs, ident


def test_noise_free_identification_recovers_every_planted_parameter(study):
    cfg, cell = copy.deepcopy(study[0]), study[1]
    # base pivot on the joint-2 axis: the base tilt is then exactly a joint-2 deflection
    cfg["synth"]["ctrack"]["base_pivot_mm"] = [150.0, 486.5]
    tabs, ident = _identify(cfg, cell, 0.0)
    tr = sc.true_robot(cfg, cell)
    home = tr.home_geometry()
    geo = ident.model.geometry
    assert np.abs(geo.axes - home.axes).max() < 1e-7              # axes [rad]
    d = geo.centres - home.centres
    off_axis = d - (d * home.axes).sum(1)[:, None] * home.axes
    assert np.abs(off_axis).max() < 1e-3                            # centres on the axes [mm]
    assert np.allclose(geo.tcp_mm, home.tcp_mm, atol=1e-9)
    c_true = tr.compliance.copy()
    c_true[1] += tr.base_compliance                                 # lumped into joint 2
    assert ident.model.compliance[1:] == pytest.approx(c_true[1:], rel=1e-2)
    assert not ident.compliance_identifiable[0]
    assert ident.base_compliance == pytest.approx(tr.base_compliance, rel=1e-3)
    assert ident.backlash_rad == pytest.approx(tr.backlash_rad, abs=0.05 * ARCSEC)
    for f in ident.model.errors:                                   # gear amplitudes
        gears = [g for g in cell.gears if g.joint == f.joint]
        planted = {g.rev_per_joint_rev: g.runout_rad for g in gears}
        planted |= {g.rev_per_joint_rev * g.teeth: g.mesh_rad for g in gears}
        amp = dict(zip(f.orders, np.hypot(f.sin, f.cos), strict=True))
        for k, a in planted.items():
            assert amp[k] == pytest.approx(a, abs=0.02 * ARCSEC)
    pts = cal.accuracy_points(tabs["accuracy"], ident.model)
    assert pts["err_full_mm"].max() < 5e-3
    assert pts["err_nominal_mm"].mean() > 100 * pts["err_full_mm"].mean()


def test_noisy_calibration_within_twice_the_noise_floor(study):
    cfg, cell = study
    tabs, ident = _identify(cfg, cell, None)
    pts = cal.accuracy_points(tabs["accuracy"], ident.model)
    table = cal.accuracy_table(pts).set_index("model")
    sigma = cfg["synth"]["ctrack"]["target_noise_mm"]
    visits = pts["visits"].to_numpy()
    floor = np.sqrt(np.mean(3 * sigma**2 / visits))   # RMS 3-D noise of the mean reached point
    assert table.loc["full", "rms_mm"] < 2 * floor
    assert table.loc["nominal", "rms_mm"] > 10 * table.loc["full", "rms_mm"]
    assert table.loc["nominal", "rms_mm"] > table.loc["geometric", "rms_mm"] > \
        table.loc["full", "rms_mm"]


def test_model_roundtrip_through_dataset(study, tmp_path):
    cfg, cell = study
    tabs, ident = _identify(cfg, cell, 0.0)
    from robomill.io import open_artefact, write_artefact

    p = write_artefact(cal.model_to_dataset(ident), tmp_path / "model.nc", rule="test")
    back = cal.model_from_dataset(open_artefact(p))
    q = np.deg2rad(np.random.default_rng(0).uniform(-30, 30, (20, 6)))
    assert np.allclose(back.tcp(q), ident.model.tcp(q), atol=1e-9)


def test_simulator_truth_is_the_cells_mass_model_unless_a_deviation_is_planted(study):
    cfg, cell = copy.deepcopy(study[0]), study[1]
    documented = _cell_masses(cfg)
    tr = sc.true_robot(cfg, cell)
    assert cfg["synth"]["ctrack"]["true_mass_model"] is None
    np.testing.assert_array_equal(tr.masses.link, documented.link)
    np.testing.assert_array_equal(tr.masses.mass_kg, documented.mass_kg)
    np.testing.assert_array_equal(tr.masses.com_mm, documented.com_mm)
    # a planted deviation: the tool is 1 kg heavier than documented
    planted = copy.deepcopy(cfg["cell"]["mass_model"])
    planted["tool"]["mass_kg"] += 1.0
    cfg["synth"]["ctrack"]["true_mass_model"] = planted
    assert sc.true_robot(cfg, cell).masses.mass_kg[-1] == documented.mass_kg[-1] + 1.0
    cfg["synth"]["ctrack"]["true_mass_model"] = None
    cfg["cell"]["mass_model"] = None
    with pytest.raises(ValueError, match=r"needs the robot's true masses: set cell\.mass_model"):
        sc.true_robot(cfg, cell)


def test_without_a_mass_model_the_identification_leaves_gravity_out(study, tmp_path):
    """A cell file without mass_model: compliance from the load discs alone, no self-weight
    terms, base compliance not identified, and the artefact says so."""
    cfg, cell = copy.deepcopy(study[0]), study[1]
    cfg["synth"]["ctrack"]["base_pivot_mm"] = [150.0, 486.5]
    tabs, with_g = _identify(cfg, cell, 0.0)
    _, ident = _identify(cfg, cell, 0.0, masses=None)
    assert with_g.gravity and not ident.gravity
    assert np.isnan(ident.base_compliance) and np.isnan(ident.base_r2)
    assert ident.base["tau2_Nm"].isna().all()
    np.testing.assert_array_equal(ident.model.tau_home_Nm, 0.0)
    # the load discs' weight is known: the joint compliances are still identified
    tr = sc.true_robot(cfg, cell)
    c_true = tr.compliance.copy()
    c_true[1] += tr.base_compliance
    assert ident.model.compliance[1:] == pytest.approx(c_true[1:], rel=0.05)
    # the full model (joint errors + load compliance) still beats the nominal one by far, but
    # misses the self-weight deflection that the gravity term would have removed
    pts = cal.accuracy_points(tabs["accuracy"], ident.model)
    pts_g = cal.accuracy_points(tabs["accuracy"], with_g.model)
    assert pts["err_nominal_mm"].mean() > 10 * pts["err_full_mm"].mean()
    assert pts["err_full_mm"].mean() > 2 * pts_g["err_full_mm"].mean()
    from robomill.io import open_artefact, write_artefact

    ds = cal.model_to_dataset(ident)
    assert ds.attrs["gravity_model"].startswith("none: the cell file states no mass_model")
    assert cal.model_to_dataset(with_g).attrs["gravity_model"] == "cell mass_model"
    assert ds.sizes["mass"] == 0
    back = cal.model_from_dataset(open_artefact(write_artefact(ds, tmp_path / "m.nc",
                                                               rule="test")))
    q = np.deg2rad(np.random.default_rng(1).uniform(-30, 30, (10, 6)))
    assert np.allclose(back.tcp(q), ident.model.tcp(q), atol=1e-9)
