"""Tracker reader and simulator plan: the data contract of tracker/<dir>_f<feed>.csv."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from robomill.io import RawDataError
from robomill.io.synthetic_layout import instrument_files
from robomill.io.tracker import read_tracker
from robomill.synth import tracker
from robomill.synth.process import simulate_cut


def _write(tmp_path, df, name="py_f2.csv"):
    path = tmp_path / name
    df.to_csv(path, index=False)
    return path


def _good(n=500, fs=815.0, v=2.0):
    t = np.arange(n) / fs
    return pd.DataFrame({"t_s": t, "x_mm": 600.0 + 0 * t, "y_mm": v * t, "z_mm": 200.0 + 0 * t})


def test_reads_a_good_file(tmp_path):
    t, p = read_tracker(_write(tmp_path, _good()), fs_hz=815.0)
    assert t.shape == (500,) and p.shape == (500, 3)


@pytest.mark.parametrize("change, match", [
    (lambda d: d.rename(columns={"z_mm": "z_m"}), "column 'z_mm' is missing"),
    (lambda d: d.assign(t_s=d["t_s"] * 2), "spacing"),
    (lambda d: d.assign(y_mm=0.0), "moves only"),
    (lambda d: d.assign(y_mm=np.where(d.index > 300, d["y_mm"] + 5, d["y_mm"])), "jumps"),
    (lambda d: d.iloc[:10], "data rows"),
])
def test_bad_files_are_refused_with_a_clear_error(tmp_path, change, match):
    path = _write(tmp_path, change(_good()))
    with pytest.raises(RawDataError, match=match) as err:
        read_tracker(path, fs_hz=815.0)
    assert str(path) in str(err.value)


def test_plan_lists_every_direction_and_feed(config, tiny_config):
    files = instrument_files(config, "tracker")
    feeds = sorted({f for s in config["experiment"]["sets"] for f in s["feeds_mm_s"]})
    assert len(files) == 3 * len(feeds)
    for f in files:
        assert f["kind"] == "tracker" and f["fs_hz"] == 815.0
        assert f["path"] == f"tracker/{f['direction']}_f{f['feed_mm_s']:g}.csv"
    # feeds 2..10 follow set 3 (thesis Figs 3.12-3.15)
    assert {f["cut"][:2] for f in files if f["feed_mm_s"] in (6.0, 8.0, 10.0, 2.0)} == {"s3"}
    assert len(instrument_files(tiny_config, "tracker")) == 2


def test_simulated_run_follows_the_contract(tmp_path, tiny_config):
    from robomill.synth.cell import cell_from_config

    cell = cell_from_config(tiny_config)
    run = tracker.tracker_runs(tiny_config)[-1]
    sim = simulate_cut(cell, run["cut"], tiny_config)
    df = tracker.simulate_run(tiny_config, cell, run["direction"], run["feed_mm_s"], run["cut"],
                              sim=sim)
    path = tracker.write_run(df, tmp_path / "run.csv")
    t, p = read_tracker(path, fs_hz=815.0)
    a, b = cell.cut_endpoints_mm(run["cut"])
    assert np.linalg.norm(p[0] - a) < 0.1 and np.linalg.norm(p[-1] - b) < 0.1
    again = tracker.simulate_run(tiny_config, cell, run["direction"], run["feed_mm_s"],
                                 run["cut"], sim=simulate_cut(cell, run["cut"], tiny_config))
    pd.testing.assert_frame_equal(df, again)  # deterministic
