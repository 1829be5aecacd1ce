"""The simulated state of a cut, integrated once and stored (robomill.synth.cutstate): what is
read back is what was simulated, bit for bit, over the span an instrument asks for; each cut
the plan's instruments sample is planned once, with its longest span and its air pass."""

from __future__ import annotations

import copy
import subprocess
from pathlib import Path

import numpy as np
import pytest

from robomill.io.synthetic_layout import synthetic_cuts
from robomill.synth.cell import cell_from_config
from robomill.synth.cutstate import planned_cut_states, read_cut_state, write_cut_state
from robomill.synth.process import simulate_cut

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def short_study(config):
    c = copy.deepcopy(config)
    c["experiment"]["cut_length_mm"] = 3.0
    return c, cell_from_config(c)


def _same(a, b, teeth_out=True):
    for name in ("t_s", "force_N", "deflection_m", "path_error_m", "frame"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert (a.cut_id, a.fs_hz, a.feed_mm_s, a.tooth_hz, a.n_full) == (
        b.cut_id, b.fs_hz, b.feed_mm_s, b.tooth_hz, b.n_full)
    assert a.modes == b.modes
    if teeth_out:  # a span keeps the count of the whole simulated span
        assert a.teeth_out == b.teeth_out


def test_a_stored_cut_reads_back_as_simulated_with_its_air_pass_and_spans(short_study,
                                                                          tmp_path):
    config, cell = short_study
    cut = synthetic_cuts(config)[4]
    path = write_cut_state(cell, cut, config, tmp_path / "c.nc", air=True)
    _same(read_cut_state(path), simulate_cut(cell, cut, config))
    air = read_cut_state(path, "air")
    _same(air, simulate_cut(cell, cut, config, cutting=False))
    assert not air.force_N.any() and air.deflection_m.any()
    # a span of the stored whole cut is that span simulated alone
    prefix = simulate_cut(cell, cut, config, length_mm=1.0)
    _same(read_cut_state(path, length_mm=1.0), prefix, teeth_out=False)
    # an instrument reading one array gets it, and NaN (read-only) for the others
    only = read_cut_state(path, length_mm=1.0, variables=["deflection_m"])
    np.testing.assert_array_equal(only.deflection_m, prefix.deflection_m)
    assert np.isnan(only.force_N).all() and np.isnan(only.path_error_m).all()
    assert only.force_N.shape == prefix.force_N.shape and not only.force_N.flags.writeable
    np.testing.assert_array_equal(
        read_cut_state(path, length_mm=1.0, variables=["force_N"]).force_N, prefix.force_N)


def test_a_stored_prefix_refuses_a_longer_span_and_a_missing_pass_in_one_line(short_study,
                                                                              tmp_path):
    config, cell = short_study
    cut = synthetic_cuts(config)[0]
    path = write_cut_state(cell, cut, config, tmp_path / "p.nc", length_mm=1.0)
    with pytest.raises(ValueError, match=r"p\.nc: .*within the simulated one"):
        read_cut_state(path, length_mm=2.0)
    with pytest.raises(ValueError, match=r"p\.nc: no 'air' pass"):
        read_cut_state(path, "air")
    with pytest.raises(ValueError, match=r"unknown cut state variable\(s\) \['t_s'\]"):
        read_cut_state(path, variables=["t_s"])


def test_each_sampled_cut_is_planned_once_with_its_longest_span(config):
    c = copy.deepcopy(config)
    c["synth"]["dynamometer"]["record_length_mm"] = 10.0
    trace_end = float(c["synth"]["profilometer"]["start_mm"]) + (
        int(c["synth"]["profilometer"]["n_samples"]) - 1) / float(
        c["synth"]["profilometer"]["fs_per_mm"])
    files = [
        {"kind": "force", "cut": "a"},
        {"kind": "profile", "cut": "a"},
        {"kind": "force", "cut": "b"},
        {"kind": "sound", "cut": "b", "pass": "air"},
        {"kind": "tracker", "cut": "c"},
        {"kind": "tracker", "cut": "d", "pass": "air"},
        {"kind": "impact", "hit": 1},
    ]
    plan = planned_cut_states(c, files)
    assert list(plan) == ["a", "b", "c"]  # the tracker's air run samples no cut state
    assert plan["a"] == {"length_mm": max(10.0, trace_end), "air": False}
    assert plan["b"] == {"length_mm": 10.0, "air": True}
    assert plan["c"] == {"length_mm": None, "air": False}  # a tracker run: the whole cut


def test_the_virtual_cell_integrates_a_cut_in_one_place():
    """Every instrument samples the stored cut: one call of simulate_cut in the simulators,
    the one that writes the shared state."""
    out = subprocess.run(["git", "grep", "-n", "simulate_cut(", "--", "src/robomill/synth"],
                         cwd=REPO, capture_output=True, text=True, check=True).stdout
    callers = [line for line in out.splitlines() if "def simulate_cut(" not in line]
    assert len(callers) == 1 and callers[0].startswith("src/robomill/synth/cutstate.py"), out
