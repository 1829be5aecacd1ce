"""Cuts of any design in the synthetic study (config ``experiment.cuts``): planning, the
simulators' per-cut values, and what the simulators refuse."""

import copy

import numpy as np
import pytest

from robomill.errors import ConfigError
from robomill.io.synthetic_layout import synthetic_cuts, synthetic_manifest

SERIES = [  # a spindle-speed series with a 3-flute tool, -X and 45 deg slots
    {"id": "n12k_mx", "feed_mm_s": 2.0, "depth_mm": 0.25, "direction": "mx",
     "spindle_rpm": 12000, "flutes": 3, "start_mm": [690.0, -60.0, 199.75]},
    {"id": "n18k_mx", "feed_mm_s": 2.0, "depth_mm": 0.25, "direction": "mx",
     "spindle_rpm": 18000, "flutes": 3, "start_mm": [690.0, -30.0, 199.75]},
    {"id": "n24k_d45", "feed_mm_s": 2.0, "depth_mm": 0.25, "direction_deg": 45.0,
     "spindle_rpm": 24000, "flutes": 3, "start_mm": [620.0, -100.0, 199.75]},
]


def _design(tiny_config, cuts):
    cfg = copy.deepcopy(tiny_config)
    cfg["experiment"]["cuts"] = copy.deepcopy(cuts)
    return cfg


def test_an_explicit_design_is_planned_as_given(tiny_config):
    cfg = _design(tiny_config, SERIES)
    cuts = synthetic_cuts(cfg)
    assert [c.id for c in cuts] == ["n12k_mx", "n18k_mx", "n24k_d45"]
    files = synthetic_manifest(cfg)["files"]
    assert {f["cut"] for f in files if f["kind"] == "force"} == {c.id for c in cuts}
    # tracker runs follow the cuts with a named direction (tiny config: px only -> none)
    assert not [f for f in files if f["kind"] == "tracker"]


@pytest.mark.parametrize(("edit", "message"), [
    ({"start_mm": None}, r"cut 'n12k_mx' needs start_mm"),
    ({"spindle_rpm": -1}, r"experiment\.cuts': cuts\[0\]\.spindle_rpm: spindle_rpm is -1"),
])
def test_cuts_the_simulators_cannot_make_are_refused(tiny_config, edit, message):
    cuts = copy.deepcopy(SERIES)
    cuts[0].update(edit)
    cuts[0] = {k: v for k, v in cuts[0].items() if v is not None}
    with pytest.raises(ConfigError, match=message):
        synthetic_cuts(_design(tiny_config, cuts))


def test_each_simulated_record_carries_its_own_tooth_passing_line(tiny_config, tmp_path):
    """Known truth: the dynamometer's force is periodic at each cut's own N·n (600, 900 and
    1200 Hz), not at the experiment's 933 Hz."""
    from robomill.io.forces import open_force_record
    from robomill.synth.cell import cell_from_config
    from robomill.synth.dynamometer import simulate_file
    from robomill.synth.process import simulate_cut

    cfg = _design(tiny_config, SERIES)
    cfg["synth"]["dynamometer"] = {**cfg["synth"]["dynamometer"], "record_length_mm": 1.0,
                                   "format": "csv"}
    for cut, f_tp in zip(synthetic_cuts(cfg), (600.0, 900.0, 1200.0), strict=True):
        cell = cell_from_config(cfg)
        path = simulate_file(cfg, cut, tmp_path / f"{cut.id}.csv",
                             simulate_cut(cell, cut, cfg, length_mm=1.0), cell=cell)
        rec = open_force_record(path, 25000.0)
        force = np.concatenate([f for _, f in rec.chunks(1 << 20)])
        w = np.hanning(len(force))[:, None]
        F = np.abs(np.fft.rfft((force - force.mean(axis=0)) * w, axis=0)).sum(axis=1)
        f = np.fft.rfftfreq(len(force), 1 / 25000.0)
        floor = np.median(F[(f > 300) & (f < 3000)])

        def line(hz, F=F, f=f):
            return F[np.abs(f - hz) <= 2.5].max()

        # its own N n (20 x the floor: the closed-loop cut's process noise and the arm's
        # vibration raise the broadband floor a dynamometer alone would have)
        assert line(f_tp) > 20 * floor and line(2 * f_tp) > 10 * floor
        assert line(f_tp) > 10 * line(2800 / 3)  # not at the experiment's 933 Hz


@pytest.mark.parametrize(("ae", "mode"), [(0.5, "down"), (0.5, "up"), (1.0, "slot")])
def test_a_partial_immersion_cut_is_simulated_with_its_own_chip_model(tiny_config, tmp_path,
                                                                        ae, mode):
    """Known truth: the dynamometer's mean force of a half-immersion down (or up) milling cut
    is Altintas' eq. 2.25 for its entry/exit angles (and not the slot's), in the cut frame."""
    from robomill.experiment import cut_process, feed_direction
    from robomill.forces import (
        CuttingCoefficients,
        cut_frame,
        engagement_angles_rad,
        mean_milling_forces,
    )
    from robomill.io.forces import open_force_record
    from robomill.synth.cell import cell_from_config
    from robomill.synth.dynamometer import simulate_file
    from robomill.synth.process import simulate_cut

    cuts = copy.deepcopy(SERIES[:1])
    cuts[0].update({"radial_immersion": ae, "milling": mode})
    cfg = _design(tiny_config, cuts)
    cfg["synth"]["dynamometer"] = {**cfg["synth"]["dynamometer"], "record_length_mm": 2.0,
                                   "format": "csv"}
    # the chip model alone: a rigid, quiet cell (the closed loop's static retreat along the
    # tool axis and its vibration would move the mean, as in a real cell)
    cfg["synth"]["modes"] = [{"f_hz": 50.0, "zeta": 0.05, "k_N_m": 1e13, "shape": [0, 1, 0]}]
    cfg["synth"]["process"] = {**cfg["synth"]["process"], "spindle_modes": [],
                               "runout_um": [0.0], "coefficient_scatter": 0.0,
                               "servo_force_N": 0.0}
    cut = synthetic_cuts(cfg)[0]
    cell = cell_from_config(cfg)
    rec = open_force_record(simulate_file(cfg, cut, tmp_path / "f.csv",
                                          simulate_cut(cell, cut, cfg, length_mm=2.0),
                                          cell=cell), 25000.0)
    force = np.concatenate([f for _, f in rec.chunks(1 << 20)])
    mean_cut = cut_frame(feed_direction(cut)).T @ force.mean(axis=0)
    proc = cut_process(cut, cell.experiment)
    st, ex = engagement_angles_rad(ae, mode)
    k = CuttingCoefficients.from_mapping(cell.cutting)
    expected = mean_milling_forces(proc["feed_per_tooth_mm"], cut.depth_mm, k, flutes=3,
                                   entry_rad=st, exit_rad=ex)
    slot = mean_milling_forces(proc["feed_per_tooth_mm"], cut.depth_mm, k, flutes=3)
    scale = np.linalg.norm(expected)
    assert np.abs(mean_cut - expected).max() < 0.02 * scale
    if mode != "slot":
        assert np.abs(mean_cut - slot).max() > 0.2 * scale
