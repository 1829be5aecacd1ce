"""A deep cut of the default study's design chatters on the virtual cell and chapter 4 calls it
chatter from the files alone: the virtual cell writes the dynamometer records of a cut at the
thesis speed and design depth and of the same cut 16 times deeper, and the microphone's and
the spindle accelerometer's recordings of both (synth.recordings), snakemake judges them
(results/chatter/verdicts.csv) and renders chapter 4; the test reads only those files.

The structure is the default study's: the planted robot modes hold at the impact test's pose,
by default the centre of the study's cuts, so the test states the default study's centre
(``synth.process.reference_point_mm``) instead of the centre of its own three cuts (the
depth at which a cut chatters, and at which frequency, depends on the structure at its pose).
The truth is the one of tests/test_synth_process.py: at 4 mm the cut is far above any limit
of the planted structure (teeth leave the cut in a third of the deep passages), at 0.25 mm
the thesis cut is stable; a chatter line lies off the tooth-passing comb by construction of
the regenerative process, and the test asks that of the file, not the simulator's line.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import yaml
from conftest import REPO, chapter_outputs, run_snakemake

pytestmark = [pytest.mark.pipeline]

RPM, FLUTES = 28000.0, 2  # the thesis' speed and tool (config.yaml experiment)
TOOTH_HZ = RPM / 60.0 * FLUTES
DESIGN = {"set": 1, "segment": 3, "direction": "px", "feed_mm_s": 3.0}  # s1_g3_px of the thesis


def _default_centre_mm() -> list[float]:
    """The centre of the default study's cuts (the default impact-test point)."""
    from robomill.io.synthetic_layout import synthetic_cuts
    from robomill.pipeline.config import load_config
    from robomill.synth.cell import cell_from_config

    cfg = load_config(REPO / "config.yaml")
    cell = cell_from_config(cfg)
    mids = [np.mean(cell.cut_endpoints_mm(c), axis=0) for c in synthetic_cuts(cfg)]
    return [float(v) for v in np.mean(mids, axis=0)]


def test_a_deep_cut_is_called_chatter_by_chapter_4_and_the_design_cut_is_not(tmp_path):
    cfg = yaml.safe_load((REPO / ".test" / "config.yaml").read_text())
    assert cfg["experiment"]["spindle_rpm"] == RPM and cfg["experiment"]["flutes"] == FLUTES
    cfg["experiment"]["cut_length_mm"] = 8.0  # the dynamometer records the first 4 mm
    cfg["experiment"]["cuts"] = [
        # a second feed at the design depth: the lobes of chapter 4 need the coefficients
        {"id": "s1_g1_px", **DESIGN, "segment": 1, "feed_mm_s": 1.0, "depth_mm": 0.25},
        {"id": "s1_g3_px", **DESIGN, "depth_mm": 0.25},
        {"id": "s1_g3_px_deep", **DESIGN, "depth_mm": 4.0}]
    cfg["synth"].setdefault("process", {})["reference_point_mm"] = _default_centre_mm()
    cfg["synth"]["recordings"] = {"sound": True, "vibration": True}
    # chapter 4 also shows the reference studies: the smallest seed simulation will do
    cfg["chatter"]["seed"].update(spindle_rpm={"start": 1000, "stop": 2000, "num": 3},
                                  duration_s=1.0)
    config = tmp_path / "config.yaml"
    config.write_text(yaml.safe_dump(cfg, sort_keys=False))
    work = tmp_path / "work"
    work.mkdir()
    done = run_snakemake(work, "-j2", "ch4", configfile=config)
    assert done.returncode == 0, done.stderr[-3000:]

    table = pd.read_csv(work / "results/chatter/verdicts.csv").set_index("source")
    deep = table.loc["forces/s1_g3_px_deep.h5"]
    assert deep["cut"] == "s1_g3_px_deep" and deep["verdict"] == "chatter", deep["evidence"]
    f_c = float(deep["chatter_hz"])
    assert 10.0 < f_c < 10_000.0
    # off the tooth-passing comb (and the run-out's lines between its teeth) by more than a
    # line's width: not forced vibration
    spindle_hz = TOOTH_HZ / FLUTES
    assert abs(f_c / spindle_hz - round(f_c / spindle_hz)) * spindle_hz > 20.0, f_c
    # the speeds to try put a tooth-passing harmonic on it: n = 60 f_c / (Z k)
    speeds = [float(s) for s in str(deep["speeds_rpm"]).split()]
    assert speeds and all(min(abs(60.0 * f_c / (FLUTES * n) - k) for k in range(1, 40))
                          < 0.01 for n in speeds)
    for cut in ("s1_g3_px", "s1_g1_px"):
        row = table.loc[f"forces/{cut}.h5"]
        assert row["cut"] == cut and row["verdict"] == "stable", row["evidence"]
    # the microphone and the accelerometer: the design cut stable, the deep one chatters on a
    # line off the comb. (s1_g1_px's recordings are left out: at 1 mm/s the run-out's fifth
    # spindle harmonic, 2333 Hz beside the spindle modes, passes the threshold in both; the
    # verdict names run-out lines as candidates and its growth does not decide.)
    for source in ("sound/s1_g3_px.wav", "vibration/s1_g3_px.csv"):
        row = table.loc[source]
        assert row["cut"] == "s1_g3_px" and row["verdict"] == "stable", row["evidence"]
    for source in ("sound/s1_g3_px_deep.wav", "vibration/s1_g3_px_deep.csv"):
        row = table.loc[source]
        assert row["cut"] == "s1_g3_px_deep" and row["verdict"] == "chatter", row["evidence"]
        f_r = float(row["chatter_hz"])
        assert abs(f_r / spindle_hz - round(f_r / spindle_hz)) * spindle_hz > 20.0, f_r

    text = " ".join(chapter_outputs(work, "ch4").split())
    assert "(3 force records, 6 recordings)" in text
    assert (f"`forces/s1_g3_px_deep.h5` (cut s1_g3_px_deep, force): **chatter** at "
            f"{f_c:.1f} Hz") in text
    not_stable = text.split("Force records not judged stable")[-1].split("recordings agree")[0]
    assert "`forces/s1_g3_px.h5`" not in not_stable
    for source, kind in (("sound/s1_g3_px_deep.wav", "sound"),
                         ("vibration/s1_g3_px_deep.csv", "vibration")):
        assert f"`{source}` (cut s1_g3_px_deep, {kind}): **chatter** at" in text
    assert (work / "results/chapters/ch4.html").stat().st_size > 0
