"""Forced vibration is not chatter, on the virtual cell and through its files: a learn cut at
10 000 rpm, 0.1 mm, 1 mm/s whose force record holds a steady line of the arm's own servo
excitation (``synth.process.servo_force_N`` of the default cell, on), and a deep regenerative cut
at the same speed whose chatter line lies near the same robot modes. The virtual cell records
each cut with the dynamometer and the spindle accelerometer (``synth.recordings.vibration``)
and, with the accelerometer, the air pass of each (``synth.recordings.air_pass``: the same path
without material, manifest ``pass: air``); snakemake judges the records
(``results/chatter/verdicts.csv``); the test reads only that file.

The truth is the cell's, not the verdict's: with the servo excitation set to zero the learn cut's
force record has no such line (stable), so its line is forced vibration; the deep cut is 40 times
deeper, and its line is the cut's own (it is there with the servo excitation off as well).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import yaml
from conftest import REPO
from test_pipeline_deep_cut import _default_centre_mm, _study

pytestmark = [pytest.mark.pipeline]

RPM = 10000.0
CUTS = [{"id": "learn_px", "set": 1, "segment": 3, "direction": "px", "feed_mm_s": 1.0,
         "depth_mm": 0.1, "spindle_rpm": RPM},
        {"id": "learn_py", "set": 1, "segment": 1, "direction": "py", "feed_mm_s": 1.0,
         "depth_mm": 0.1, "spindle_rpm": RPM},
        {"id": "deep_py", "set": 1, "segment": 2, "direction": "py", "feed_mm_s": 1.0,
         "depth_mm": 4.0, "spindle_rpm": RPM}]


def _force_verdict_without_servo(cut: dict) -> str:
    """The verdict of the cut's force record on the study's cell (as :func:`_study` sets it)
    with ``servo_force_N`` 0 (the counterfactual that says which line the servo excitation
    makes)."""
    from robomill.chatter.verdicts import default_settings, judge
    from robomill.experiment import Cut
    from robomill.pipeline.config import load_config
    from robomill.synth.cell import cell_from_config
    from robomill.synth.dynamometer import simulate_blocks
    from robomill.synth.process import simulate_cut

    cfg = load_config(REPO / ".test" / "config.yaml",
                      REPO / "src/robomill/data/schemas/config.schema.yaml")
    cfg["synth"]["process"]["reference_point_mm"] = _default_centre_mm()
    cfg["experiment"]["cut_length_mm"] = 8.0
    cfg["synth"]["dynamometer"]["record_length_mm"] = 8.0
    cfg["synth"]["process"]["servo_force_N"] = 0.0
    cell, the_cut = cell_from_config(cfg), Cut(**cut)
    _, fs, blocks = simulate_blocks(cell, the_cut, cfg, simulate_cut(cell, the_cut, cfg))
    force = np.concatenate([b for _, b in blocks])
    return judge(force, fs, default_settings(), spindle_rpm=RPM, flutes=2).verdict


def test_the_servo_excited_learn_cut_is_forced_and_the_deep_cut_still_chatters(tmp_path):
    default = yaml.safe_load((REPO / "config.yaml").read_text())
    servo = default["synth"]["process"]["servo_force_N"]
    assert servo > 0  # the default cell's servo excitation is on
    work = _study(tmp_path, CUTS, "results/chatter/verdicts.csv",
                  recordings={"vibration": True}, dynamometer={"record_length_mm": 8.0})
    manifest = yaml.safe_load((work / "results/synthetic/raw/manifest.yaml").read_text())
    air = {f["path"] for f in manifest["files"] if f.get("pass") == "air"}
    assert air == {f"vibration/{c['id']}_air.csv" for c in CUTS}
    table = pd.read_csv(work / "results/chatter/verdicts.csv").set_index("source")
    assert len(table) == 6  # air passes are evidence, not records of a cut
    assert not (set(table.index) & air)

    for cut in ("learn_px", "learn_py"):
        learn = table.loc[f"forces/{cut}.h5"]
        # the spectral test alone calls the line chatter (energy ratio over the threshold) ...
        assert learn["energy_ratio"] >= learn["energy_ratio_threshold"], learn["evidence"]
        # ... the air pass of the accelerometer calls it forced
        assert learn["verdict"] == "forced", learn["evidence"]
        assert str(learn["evidence"]).startswith("air test: forced")
        assert f"vibration/{cut}_air.csv" in learn["evidence"]
        assert np.isnan(learn["chatter_hz"]) and 10.0 < float(learn["line_hz"]) < 200.0
        assert table.loc[f"vibration/{cut}.csv", "verdict"] != "chatter"

    for source in ("forces/deep_py.h5", "vibration/deep_py.csv"):
        row = table.loc[source]
        assert row["verdict"] == "chatter", (source, row["evidence"])
        assert "grows with depth" in row["evidence"] or "no line" in row["evidence"]

    # the cell's truth: without the servo excitation the learn cut is stable, the deep cut
    # chatters all the same
    assert _force_verdict_without_servo(CUTS[0]) == "stable"
    assert _force_verdict_without_servo(CUTS[1]) == "stable"
    assert _force_verdict_without_servo(CUTS[2]) == "chatter"
