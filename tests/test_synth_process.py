"""The closed-loop cut of the virtual cell (robomill.synth.process, robomill.synth.structure).

Truths are written independently of the simulator: the critical depth of a planted structure
from the converged spectral-element lobe (robomill.chatter.lobes_sem, a linear model of its
own), the mean force of an undisturbed cut from the closed form of Altintas 2012 eq. 2.25, the
joints' compliance from the load tests' deflection model (robomill.stiffness.model).
"""

from __future__ import annotations

import copy
import dataclasses

import numpy as np
import pytest
from point_masses import kinetic_energy_J

from robomill.io.synthetic_layout import synthetic_cuts
from robomill.synth.cell import cell_from_config
from robomill.synth.process import simulate_cut


def _study(config, **experiment):
    c = copy.deepcopy(config)
    c["experiment"].update(experiment)
    return c


def _cut(config, cut_id, **changes):
    cut = next(c for c in synthetic_cuts(config) if c.id == cut_id)
    return dataclasses.replace(cut, **changes)


def _spindle_non_harmonic_line(sim, band_hz=(10.0, 5000.0), halfwidth_hz=20.0):
    """Largest line of the cross-feed force spectrum (second half of the cut, Hann window)
    farther than ``halfwidth_hz`` from every spindle harmonic (tooth passing and run-out):
    (amplitude [N], frequency [Hz])."""
    x = sim.force_N[sim.t_s.size // 2:, 1]
    x = x - x.mean()
    w = np.hanning(x.size)
    spec = 2 * np.abs(np.fft.rfft(x * w)) / w.sum()
    f = np.fft.rfftfreq(x.size, 1 / sim.fs_hz)
    spindle_hz = sim.tooth_hz / 2
    harm = np.abs(f / spindle_hz - np.round(f / spindle_hz)) * spindle_hz <= halfwidth_hz
    ok = (f >= band_hz[0]) & (f <= band_hz[1]) & ~harm
    i = int(np.argmax(np.where(ok, spec, -1.0)))
    return float(spec[i]), float(f[i])


@pytest.fixture(scope="module")
def one_mode_cell(config):
    """A planted cell whose structure is one symmetric mode pair (x, y) at 800 Hz, without
    spindle modes, pose dependence or edge forces: the linear lobe's own assumptions, so that
    its critical depth is the truth's (the edge force's forced vibration lets teeth leave the
    cut below the linear limit: that nonlinearity the linear lobe does not describe)."""
    c = _study(config, cut_length_mm=5.0)
    mode = {"f_hz": 800.0, "zeta": 0.03, "k_N_m": 2.0e7}
    c["synth"]["modes"] = [{**mode, "shape": [1.0, 0.0, 0.0]}, {**mode, "shape": [0.0, 1.0, 0.0]}]
    c["synth"]["process"]["spindle_modes"] = []
    c["synth"]["loadtests"]["robots"] = []
    c["synth"]["cutting"].update(Kte_N_mm=0.0, Kre_N_mm=0.0, Kae_N_mm=0.0)
    return c, cell_from_config(c)


def test_a_cut_above_the_converged_lobe_chatters_and_one_below_does_not(one_mode_cell):
    from robomill.chatter.lobes_sem import critical_depth
    from robomill.chatter.model import CuttingModel, ModeXY, tool_from_modes

    config, cell = one_mode_cell
    k = cell.cutting
    tool = tool_from_modes([ModeXY(800.0, 0.03, 2.0e7, (1.0, 0.0)),
                            ModeXY(800.0, 0.03, 2.0e7, (0.0, 1.0))])
    lobe = critical_depth(tool, CuttingModel(2, k["Ktc_N_mm2"] * 1e6,
                                             k["Krc_N_mm2"] / k["Ktc_N_mm2"], 0.0, np.pi),
                          float(config["experiment"]["spindle_rpm"]), depth_max_m=0.05)
    a_crit_mm = 1e3 * lobe.a_crit_m
    assert 1.0 < a_crit_mm < 20.0  # a limit inside the reach of the test
    below = simulate_cut(cell, _cut(config, "s1_g1_px", feed_mm_s=5.0,
                                    depth_mm=0.6 * a_crit_mm), config)
    above = simulate_cut(cell, _cut(config, "s1_g1_px", feed_mm_s=5.0,
                                    depth_mm=1.6 * a_crit_mm), config)
    # below: every tooth stays in the cut, no line away from the spindle harmonics
    amp_below, _ = _spindle_non_harmonic_line(below)
    amp_above, f_above = _spindle_non_harmonic_line(above)
    mean_above = float(np.linalg.norm(above.force_N.mean(axis=0)))
    assert below.teeth_out < 0.005
    assert amp_below < 0.05 * float(np.linalg.norm(below.force_N.mean(axis=0)))
    # above: the vibration grew until teeth left the cut, a chatter line dominates
    assert above.teeth_out > 0.05
    assert amp_above > 0.2 * mean_above
    assert amp_above > 20 * amp_below
    rms = [float(np.std(s.deflection_m[s.t_s.size // 2:, :2])) for s in (below, above)]
    assert rms[1] > 1.6 / 0.6 * 3 * rms[0]  # far more than the depth ratio: not forced vibration
    # the line is the mode's vibration seen through the tooth-passing modulation
    tooth = above.tooth_hz
    offset = min(abs(f_above - 800.0 - n * tooth) for n in range(-3, 4))
    assert offset < 150.0, f_above


@pytest.fixture(scope="module")
def default_study(config):
    c = _study(config, cut_length_mm=10.0)
    return c, cell_from_config(c)


def test_a_deep_cut_of_the_default_design_chatters_at_the_thesis_speed(default_study):
    config, cell = default_study
    design = simulate_cut(cell, _cut(config, "s1_g3_px"), config)
    deep = simulate_cut(cell, _cut(config, "s1_g3_px", depth_mm=4.0), config)
    # at the design depth the arm's forced vibration lets a tooth leave now and then, but
    # no line grows: the largest one away from the spindle harmonics stays a few % of the force
    assert design.teeth_out < 0.05
    amp, _ = _spindle_non_harmonic_line(design)
    assert amp < 0.05 * float(np.linalg.norm(design.force_N.mean(axis=0)))
    assert deep.teeth_out > 0.3
    amp, f = _spindle_non_harmonic_line(deep)
    assert amp > 0.2 * float(np.linalg.norm(deep.force_N.mean(axis=0))), (amp, f)


def test_an_undisturbed_cut_has_the_closed_form_mean_force(config):
    from robomill.forces.model import CuttingCoefficients, mean_slot_forces

    c = _study(config, cut_length_mm=2.0)
    c["synth"]["modes"] = [{"f_hz": 50.0, "zeta": 0.05, "k_N_m": 1e13, "shape": [0, 1, 0]}]
    c["synth"]["process"].update(spindle_modes=[], runout_um=[0.0], coefficient_scatter=0.0)
    c["synth"]["gears"] = []
    c["synth"]["loadtests"]["robots"] = []
    cell = cell_from_config(c)
    cut = _cut(c, "s1_g1_py", feed_mm_s=4.0, depth_mm=0.5)
    sim = simulate_cut(cell, cut, c)
    c_mm = 4.0 / (2 * 28000 / 60)
    expected = mean_slot_forces(c_mm, 0.5, CuttingCoefficients.from_mapping(cell.cutting))
    # whole spindle revolutions only (the record's end is not one)
    n = int(np.floor(sim.t_s[-1] * 28000 / 60) * sim.fs_hz / (28000 / 60))
    np.testing.assert_allclose(sim.force_N[:n].mean(axis=0), expected, rtol=5e-3)


def test_a_prefix_of_a_cut_is_the_start_of_the_whole_cut(default_study):
    config, cell = default_study
    cut = _cut(config, "s1_g5_my")
    whole = simulate_cut(cell, cut, config)
    part = simulate_cut(cell, dataclasses.replace(cut, id="same_cut_again"), config,
                        length_mm=3.0)
    assert part.t_s.size < whole.t_s.size
    n = int(3.0 / cut.feed_mm_s * whole.fs_hz)
    assert part.t_s.size > n
    # a renamed cut draws its own noise: compare the same cut instead
    again = simulate_cut(cell, cut, config, length_mm=3.0)
    np.testing.assert_array_equal(again.force_N[:n], whole.force_N[:n])
    np.testing.assert_array_equal(again.deflection_m[:n], whole.deflection_m[:n])
    # the span of the whole cut is the prefix simulated alone, bit for bit (the force's
    # filter tail held as the prefix holds it): what every instrument samples
    spanned = whole.span(3.0)
    assert spanned.t_s.size == again.t_s.size
    for name in ("t_s", "force_N", "deflection_m", "path_error_m"):
        np.testing.assert_array_equal(getattr(spanned, name), getattr(again, name))
    assert whole.span(None) is whole
    with pytest.raises(ValueError, match="within the simulated one"):
        again.span(None)


def test_an_air_pass_has_no_force_and_the_tracker_sees_the_deflection(default_study):
    from robomill.synth.tracker import simulate_run

    config, cell = default_study
    cut = _cut(config, "s3_g5_px")
    air = simulate_cut(cell, cut, config, cutting=False)
    loaded = simulate_cut(cell, cut, config)
    assert not air.force_N.any()
    # in the air the arm only vibrates under its own servos: no static deflection
    assert np.all(np.abs(air.deflection_m.mean(axis=0)) < 0.05 * np.abs(
        loaded.deflection_m.mean(axis=0)).max())
    np.testing.assert_array_equal(air.path_error_m, loaded.path_error_m[:air.t_s.size])
    run_l = simulate_run(config, cell, cut.direction, cut.feed_mm_s, cut, sim=loaded)
    run_a = simulate_run(config, cell, cut.direction, cut.feed_mm_s, cut, "air")
    diff_um = 1e3 * (run_l[["x_mm", "y_mm", "z_mm"]] - run_a[["x_mm", "y_mm", "z_mm"]])
    static_um = 1e6 * (loaded.deflection_m @ loaded.frame.T).mean(axis=0)
    # loaded − air: the static deflection, within the two passes' tracker noise
    noise_um = float(config["synth"]["tracker"]["noise_std_um"])
    np.testing.assert_allclose(diff_um.mean().to_numpy(), static_um,
                               atol=4 * noise_um * np.sqrt(2 / len(diff_um)) + 0.5)
    assert np.linalg.norm(static_um) > 5.0  # the tool gives way by micrometres


def test_the_robot_modes_follow_the_joints_stiffness_and_masses_along_their_shapes(
        default_study):
    from robomill.calibration.gravity import mass_model_from_mapping
    from robomill.stiffness.model import jacobian_m, predict_deflection_m
    from robomill.synth.structure import modes_at, robot_modes_at

    config, cell = default_study
    assert robot_modes_at(cell, cell.q_reference_rad) == list(cell.modes)
    k_theta = np.asarray(config["synth"]["loadtests"]["robots"][1]["k_Nm_rad"], float)
    assert config["synth"]["loadtests"]["robots"][1]["name"] == "irb1600"
    masses = mass_model_from_mapping(config["cell"]["mass_model"], 6)
    q = cell.joint_path_rad(_cut(config, "s3_g5_py"), np.array([5.0]))[0]
    moved = robot_modes_at(cell, q)
    for planted, m in zip(cell.modes, moved, strict=True):
        phi = np.asarray(planted.shape)

        def along(qq, phi=phi):  # the joints' deflection along φ under a unit force along φ
            J = jacobian_m(cell.robot, qq[None])
            return float(predict_deflection_m(J, phi[None], 1.0 / k_theta)[0] @ phi)

        def mass(qq, phi=phi):  # 2 T of the joint deflection scaled to unit motion along φ
            J = jacobian_m(cell.robot, qq[None])[0, :3]
            psi = (J.T @ phi) / k_theta / along(qq)
            return 2.0 * kinetic_energy_J(cell.robot, masses.link, masses.mass_kg,
                                          masses.com_mm, qq, psi)

        assert m.m_kg == pytest.approx(planted.m_kg * mass(q) / mass(cell.q_reference_rad),
                                       rel=1e-6)
        assert m.shape == planted.shape and m.zeta == planted.zeta
        assert m.k_N_m == pytest.approx(planted.k_N_m * along(cell.q_reference_rad) / along(q),
                                        rel=1e-9)
    # the masses move the modes too: at this pose frequencies differ from a stiffness-only move
    assert any(abs(m.m_kg / p.m_kg - 1) > 0.05 for m, p in zip(moved, cell.modes, strict=True))
    assert any(abs(m.f_hz / p.f_hz - 1) > 0.03 for m, p in zip(moved, cell.modes, strict=True))
    spindle = modes_at(cell, q)[len(moved):]
    assert spindle == list(cell.spindle_modes) and min(m.f_hz for m in spindle) > 100.0


def test_without_masses_the_modes_keep_their_planted_masses(default_study):
    from robomill.synth.structure import robot_modes_at

    config, _ = default_study
    config = copy.deepcopy(config)
    config["cell"]["mass_model"] = None
    config["synth"]["ctrack"]["true_mass_model"] = None
    cell = cell_from_config(config)
    assert cell.rigid_body_model is None
    q = cell.joint_path_rad(_cut(config, "s3_g5_py"), np.array([5.0]))[0]
    for planted, m in zip(cell.modes, robot_modes_at(cell, q), strict=True):
        assert m.m_kg == pytest.approx(planted.m_kg, rel=1e-12)
        assert m.k_N_m != pytest.approx(planted.k_N_m, rel=1e-3)


def test_a_planted_mass_on_a_link_the_robot_lacks_is_one_clear_line(default_study):
    from robomill.errors import RawDataError

    config, _ = default_study
    config = copy.deepcopy(config)
    config["cell"]["mass_model"]["links"][2]["link"] = 9
    with pytest.raises(RawDataError) as err:
        cell_from_config(config)
    message = str(err.value)
    assert "\n" not in message
    assert "config.yaml (cell.mass_model)" in message and "links[2].link" in message
    assert "1..6" in message


def test_a_mode_that_moves_no_mass_keeps_its_planted_mass(default_study):
    # point masses on joint 1's own axis have no inertia about any joint's motion here: every
    # mode's Rayleigh mass is zero at every pose, and the modes keep their planted masses
    # (a ratio 0/0 would make their frequencies infinite)
    from robomill.synth.inertia import rigid_body_model
    from robomill.synth.structure import rayleigh_stiffness_mass, robot_modes_at

    config, _ = default_study
    cell = copy.copy(cell_from_config(config))
    base = np.asarray(cell.robot.base, float)
    on_axis_mm = base[:3, 3] + np.outer([100.0, 300.0], base[:3, 2])
    cell.rigid_body_model = rigid_body_model(cell.robot, np.array([1, 1]),
                                             np.array([20.0, 5.0]), on_axis_mm)
    q = cell.joint_path_rad(_cut(config, "s3_g5_py"), np.array([5.0]))[0]
    assert rayleigh_stiffness_mass(cell, q, cell.modes[0].shape)[1] == pytest.approx(0.0,
                                                                                     abs=1e-12)
    for planted, m in zip(cell.modes, robot_modes_at(cell, q), strict=True):
        assert np.isfinite(m.f_hz) and m.m_kg == pytest.approx(planted.m_kg, rel=1e-12)
