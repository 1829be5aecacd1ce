"""A deep cut of the default study's design chatters on the virtual cell and chapter 4 calls it
chatter from the files alone: the virtual cell writes the dynamometer records of a cut at the
thesis speed and design depth and of the same cut 16 times deeper, snakemake judges them
(results/chatter/verdicts.csv) and renders chapter 4; the test reads only those files. The
same study records its cuts with the virtual cell's microphone and spindle accelerometer too
(synth.recordings), and the second test asks the same of their verdicts.

The structure is the default study's: the planted robot modes hold at the impact test's pose,
by default the centre of the study's cuts, so the test states the default study's centre
(``synth.process.reference_point_mm``) instead of the centre of its own few cuts (the depth
at which a cut chatters, and at which frequency, depends on the structure at its pose).
The truth is the one of tests/test_synth_process.py: at 4 mm the cut is far above any limit
of the planted structure (teeth leave the cut in a third of the deep passages), at 0.25 mm
the thesis cut is stable; a chatter line lies off the tooth-passing comb by construction of
the regenerative process, and the test asks that of the file, not the simulator's line.
"""

from __future__ import annotations

import re

import numpy as np
import pandas as pd
import pytest
import yaml
from conftest import REPO, chapter_outputs, run_snakemake

pytestmark = [pytest.mark.pipeline]

RPM, FLUTES = 28000.0, 2  # the thesis' speed and tool (config.yaml experiment)
SPINDLE_HZ = RPM / 60.0
DESIGN = {"set": 1, "segment": 3, "direction": "px", "feed_mm_s": 3.0}  # s1_g3_px of the thesis
PAIR = [{"id": "s1_g3_px", **DESIGN, "depth_mm": 0.25},
        {"id": "s1_g3_px_deep", **DESIGN, "depth_mm": 4.0}]


def _default_centre_mm() -> list[float]:
    """The centre of the default study's cuts (the default impact-test point)."""
    from robomill.io.synthetic_layout import synthetic_cuts
    from robomill.pipeline.config import load_config
    from robomill.synth.cell import cell_from_config

    cfg = load_config(REPO / "config.yaml")
    cell = cell_from_config(cfg)
    mids = [np.mean(cell.cut_endpoints_mm(c), axis=0) for c in synthetic_cuts(cfg)]
    return [float(v) for v in np.mean(mids, axis=0)]


def _study(tmp_path, cuts, target, **synth):
    """Run ``target`` on the tiny study with these cuts at the default study's structure;
    the finished work folder."""
    cfg = yaml.safe_load((REPO / ".test" / "config.yaml").read_text())
    assert cfg["experiment"]["spindle_rpm"] == RPM and cfg["experiment"]["flutes"] == FLUTES
    cfg["experiment"]["cut_length_mm"] = 8.0  # the dynamometer records the first 4 mm
    cfg["experiment"]["cuts"] = cuts
    cfg["synth"].setdefault("process", {})["reference_point_mm"] = _default_centre_mm()
    cfg["synth"].update(synth)
    # chapter 4 also shows the reference studies: the smallest seed simulation will do
    cfg["chatter"]["seed"].update(spindle_rpm={"start": 1000, "stop": 2000, "num": 3},
                                  duration_s=1.0)
    config = tmp_path / "config.yaml"
    config.write_text(yaml.safe_dump(cfg, sort_keys=False))
    work = tmp_path / "work"
    work.mkdir()
    done = run_snakemake(work, "-j2", target, configfile=config)
    assert done.returncode == 0, done.stderr[-3000:]
    return work


def _off_comb_hz(f_hz: float) -> float:
    """Distance of ``f_hz`` from the nearest spindle harmonic (the tooth-passing comb and the
    run-out's lines between its teeth) [Hz]."""
    return abs(f_hz / SPINDLE_HZ - round(f_hz / SPINDLE_HZ)) * SPINDLE_HZ


@pytest.fixture(scope="module")
def deep_study(tmp_path_factory):
    """One study for both tests: the pair and two more feeds at the design depth (the lobes of
    chapter 4 need the coefficients, fitted from three cuts at least once the chattering one
    is left out), each recorded by the dynamometer, the microphone and the spindle
    accelerometer (with their air passes), through chapter 4."""
    return _study(tmp_path_factory.mktemp("deep"), [
        {"id": "s1_g1_px", **DESIGN, "segment": 1, "feed_mm_s": 1.0, "depth_mm": 0.25},
        {"id": "s1_g5_px", **DESIGN, "segment": 5, "feed_mm_s": 5.0, "depth_mm": 0.25},
        *PAIR], "ch4", recordings={"sound": True, "vibration": True})


def test_a_deep_cut_is_called_chatter_by_chapter_4_and_the_design_cut_is_not(deep_study):
    work = deep_study
    table = pd.read_csv(work / "results/chatter/verdicts.csv").set_index("source")
    deep = table.loc["forces/s1_g3_px_deep.h5"]
    assert deep["cut"] == "s1_g3_px_deep" and deep["verdict"] == "chatter", deep["evidence"]
    f_c = float(deep["chatter_hz"])
    assert 10.0 < f_c < 10_000.0
    # off the tooth-passing comb (and the run-out's lines between its teeth) by more than a
    # line's width: not forced vibration
    assert _off_comb_hz(f_c) > 20.0, f_c
    # the speeds to try put a tooth-passing harmonic on it: n = 60 f_c / (Z k)
    speeds = [float(s) for s in str(deep["speeds_rpm"]).split()]
    assert speeds and all(min(abs(60.0 * f_c / (FLUTES * n) - k) for k in range(1, 40))
                          < 0.01 for n in speeds)
    for cut in ("s1_g3_px", "s1_g1_px", "s1_g5_px"):
        row = table.loc[f"forces/{cut}.h5"]
        assert row["cut"] == cut and row["verdict"] == "stable", row["evidence"]

    text = " ".join(chapter_outputs(work, "ch4").split())
    # the chapter counts what the verdict table and the manifest hold (counted here)
    n = table["verdict"].value_counts()
    kinds = table.index.str.split("/").str[0]
    manifest = yaml.safe_load((work / "results/synthetic/raw/manifest.yaml").read_text())
    air = [f for f in manifest["files"] if f.get("pass") == "air"]
    assert len(air) == 8 and (kinds == "forces").sum() == 4 and len(table) == 12
    assert (f"12 records: {n.get('stable', 0)} stable, {n.get('chatter', 0)} chatter, "
            f"{n.get('forced', 0)} forced, {n.get('undetermined', 0)} undetermined "
            f"(4 force records, 8 recordings, 8 air passes)") in text
    assert (f"`forces/s1_g3_px_deep.h5` (cut s1_g3_px_deep, force): **chatter** at "
            f"{f_c:.1f} Hz") in text
    # the list of force records not judged stable names the deep cut's, not the design cut's
    listed = re.findall(r"- `(forces/[^`]+)` \(cut",
                        chapter_outputs(work, "ch4").split("Force records not judged stable:")[1]
                        .split("\n\n")[1])
    assert listed == ["forces/s1_g3_px_deep.h5"], listed
    assert (work / "results/chapters/ch4.html").stat().st_size > 0


def test_the_microphone_and_the_accelerometer_hear_the_deep_cut_chatter(deep_study):
    """The same pair recorded by the virtual cell's microphone and spindle accelerometer:
    the design cut's recordings stable, the deep cut's chatter on a line off the comb, as its
    force record. (Their chatter frequency need not be the force record's: the sensors
    weight the vibration by ω², and the spindle modes near 2.1 kHz make the second harmonic
    of the force's line, or another member of its family, the strongest line they hear.)"""
    table = pd.read_csv(deep_study / "results/chatter/verdicts.csv").set_index("source")
    assert len(table) == 12  # four cuts, three records each: the air passes are no rows
    for source in ("forces/s1_g3_px.h5", "sound/s1_g3_px.wav", "vibration/s1_g3_px.csv"):
        row = table.loc[source]
        assert row["cut"] == "s1_g3_px" and row["verdict"] == "stable", (source,
                                                                         row["evidence"])
    for source in ("forces/s1_g3_px_deep.h5", "sound/s1_g3_px_deep.wav",
                   "vibration/s1_g3_px_deep.csv"):
        row = table.loc[source]
        assert row["cut"] == "s1_g3_px_deep" and row["verdict"] == "chatter", (
            source, row["evidence"])
        assert _off_comb_hz(float(row["chatter_hz"])) > 20.0, (source, row["chatter_hz"])
    # the recordings' chatter lines were tested on their air passes and grow with depth (or
    # the air pass lacks them); the force record's on the recordings' pairs
    for source in ("sound/s1_g3_px_deep.wav", "vibration/s1_g3_px_deep.csv",
                   "forces/s1_g3_px_deep.h5"):
        assert "air test: " in table.loc[source, "evidence"], source
