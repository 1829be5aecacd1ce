"""Static deflection from a tracker's loaded pass minus its air pass along the same path: a
planted offset normal to the wall and along the tool axis is read back, whatever the gear
errors both passes share; the manifest key ``pass`` is checked."""

import numpy as np
import pytest

from robomill.errors import RawDataError
from robomill.experiment import tracker_pass, tracker_pass_pairs
from robomill.io.manifest import parse_manifest
from robomill.straightness.deflection import pass_deflection_um

U = np.array([np.cos(np.deg2rad(30.0)), np.sin(np.deg2rad(30.0)), 0.0])   # feed direction
N = np.array([-U[1], U[0], 0.0])                                           # z x u


def tracked_pass(offset_um, seed, t0_s=0.0, fs_hz=815.0, feed_mm_s=10.0, length_mm=40.0):
    """A pass along U at ``feed_mm_s`` (ramps of 100 mm/s²), with the gear errors both passes
    share (sinusoids in the wall normal and in z), its own 5 µm noise and ripple, shifted
    by ``offset_um`` (3,)."""
    rng = np.random.default_rng(seed)
    t = np.arange(t0_s, length_mm / feed_mm_s + 0.2, 1.0 / fs_hz)
    s = np.clip(feed_mm_s * (t - 0.1), 0.0, length_mm)
    start = np.array([600.0, -20.0, 200.0])
    gear_um = 4.0 * np.sin(2 * np.pi * 0.37 * s)[:, None] * N + \
        2.0 * np.cos(2 * np.pi * 0.9 * s)[:, None] * np.array([0.0, 0.0, 1.0])
    ripple_um = 2.0 * np.sin(2 * np.pi * 13.0 * t + rng.uniform(0, 2 * np.pi))[:, None] * \
        np.array([0.5, 0.5, 0.7])
    noise_um = 5.0 * rng.standard_normal((t.size, 3))
    p = start + s[:, None] * U + 1e-3 * (gear_um + ripple_um + noise_um +
                                           np.asarray(offset_um, float))
    return t, p


def test_a_planted_offset_is_read_back_along_the_normal_and_the_tool_axis():
    planted = 3.0 * N + np.array([0.0, 0.0, -1.5])       # 3 µm along n, -1.5 µm along z
    _, loaded = tracked_pass(planted, seed=1, t0_s=0.5 / 815)
    t_air, air = tracked_pass(np.zeros(3), seed=2)
    d = pass_deflection_um(loaded, air, ds_mm=0.05, trim_mm=2.0, t_air_s=t_air)
    assert d["deflection_normal_um"] == pytest.approx(3.0, abs=0.3)
    assert d["deflection_axial_um"] == pytest.approx(-1.5, abs=0.3)
    assert 0 < d["stderr_normal_um"] < 0.3
    assert d["length_mm"] == pytest.approx(36.0, abs=0.5)
    # no load, no deflection: two air passes agree within their noise
    _, again = tracked_pass(np.zeros(3), seed=3)
    d0 = pass_deflection_um(again, air, ds_mm=0.05, trim_mm=2.0, t_air_s=t_air)
    assert abs(d0["deflection_normal_um"]) < 0.3 and abs(d0["deflection_axial_um"]) < 0.3


def test_passes_that_do_not_overlap_are_refused():
    _, a = tracked_pass(np.zeros(3), seed=1)
    with pytest.raises(ValueError, match="share"):
        pass_deflection_um(a + 100.0 * U, a, ds_mm=0.05, trim_mm=2.0)


MANIFEST = {"experiment": {"spindle_rpm": 30000.0, "flutes": 2, "tool_diameter_mm": 6.0,
                           "cut_length_mm": 40.0},
            "cuts": [{"id": "c1", "feed_mm_s": 10.0, "depth_mm": 0.2, "direction": "px",
                      "start_mm": [600.0, 0.0, 200.0]}]}


def tracker_entry(**extra):
    return {"path": f"tracker/{extra.get('run', 'x')}.csv", "kind": "tracker",
            "direction": "px", "feed_mm_s": 10.0, "fs_hz": 815.0, **extra}


def test_the_manifest_reads_loaded_and_air_passes():
    files = [tracker_entry(run="c1", cut="c1"),
             tracker_entry(run="c1_air", cut="c1", **{"pass": "air"})]
    m = parse_manifest({**MANIFEST, "files": files}, "m.yaml", require_sha256=False)
    assert [tracker_pass(f) for f in m.files] == ["loaded", "air"]    # default loaded
    runs = {f["run"]: f for f in m.files}
    assert tracker_pass_pairs(runs) == [{"cut": "c1", "loaded_run": "c1",
                                         "air_run": "c1_air"}]
    lone = {"c1_air": runs["c1_air"]}
    assert tracker_pass_pairs(lone)[0]["loaded_run"] == ""


@pytest.mark.parametrize("entry, message", [
    (tracker_entry(run="a", cut="c1", **{"pass": "idle"}),
     r"m.yaml: files\[0\] \(tracker/a.csv\).pass: pass is 'idle' \(expected one of loaded, "
     r"air\)"),
    (tracker_entry(run="a", **{"pass": "air"}),
     r"m.yaml: files\[0\] \(tracker/a.csv\).cut: an air pass names no cut"),
])
def test_a_bad_pass_is_one_line(entry, message):
    with pytest.raises(RawDataError, match=message):
        parse_manifest({**MANIFEST, "files": [entry]}, "m.yaml", require_sha256=False)


def test_the_virtual_cells_loaded_pass_minus_its_air_pass_is_the_planted_deflection(config):
    """On the virtual cell, a planned cut tracked while cutting and in the air: the estimate
    from the two files' positions is the tool's deflection in the closed-loop cut (the
    structure's displacement the simulator integrated) averaged along the path, within the
    tracker's noise."""
    from robomill.experiment import Cut
    from robomill.synth.cell import cell_from_config
    from robomill.synth.process import simulate_cut
    from robomill.synth.tracker import deflection_along_path_mm, simulate_run

    cfg = config
    cell = cell_from_config(cfg)
    cut = Cut("plan_01", None, None, "px", 10.0, 0.5, spindle_rpm=30000.0, flutes=2,
              tool_diameter_mm=6.0, radial_immersion=1.0, milling="slot",
              start_mm=(580.0, -50.0, 200.0))
    sim = simulate_cut(cell, cut, cfg)
    loaded = simulate_run(cfg, cell, "px", 10.0, cut, "loaded", "plan_01", sim=sim)
    air = simulate_run(cfg, cell, "px", 10.0, cut, "air", "plan_01_air")
    xyz = ["x_mm", "y_mm", "z_mm"]
    d = pass_deflection_um(loaded[xyz].to_numpy(), air[xyz].to_numpy(), ds_mm=0.05,
                           trim_mm=2.0, t_air_s=air["t_s"].to_numpy())
    s = np.linspace(2.0, 38.0, 37)
    truth_um = 1e3 * deflection_along_path_mm(sim, s, 815.0).mean(0)
    assert np.linalg.norm(truth_um) > 2.0                       # a deflection worth measuring
    # px: wall normal z x x = +y, tool axis z
    assert d["deflection_normal_um"] == pytest.approx(truth_um[1], abs=0.5)
    assert d["deflection_axial_um"] == pytest.approx(truth_um[2], abs=0.5)
    same = simulate_run({**config}, cell, "px", 10.0, cut, sim=sim)  # default pass, run id
    assert same.equals(simulate_run(config, cell, "px", 10.0, cut, "loaded", "px_f10",
                                    sim=sim))
