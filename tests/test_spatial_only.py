"""Spatial-only tracker streams (issue 32.6): a SpatialAnalyzer export whose stamps are whole
seconds holding uneven point counts (distance- or event-triggered) imports with
``--spatial-only``, is recorded as ``time_base: none``, read without a rate and analysed in
space (a planted line per mm is found); its peaks are not classified temporal/spatial. Without
the flag, one line suggests ``--spatial-only``."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from robomill.errors import RawDataError
from robomill.importers import spatialanalyzer
from robomill.io.manifest import parse_manifest
from robomill.io.tracker import read_tracker
from robomill.straightness.attribution import classify_peaks
from robomill.straightness.profile import profile_spectrum, spatial_profile, spectrum_peaks

COUNTS = [57, 98, 444, 159, 130, 310, 121, 212, 98, 377, 160, 250, 184, 140, 266, 188, 147,
          220, 109, 330, 155, 171, 40]  # points per whole-second stamp (inner: 98-444)
WAVELENGTH_MM = 2.5  # planted lateral line: 0.4 1/mm
AMPLITUDE_UM = 3.0


def _sa_stream(path: Path) -> Path:
    """SpatialAnalyzer's headerless ASCII layout (three ``//`` lines; Collection, Group,
    Target, X, Y, Z, MM/DD/YY HH:MM:SS): a 40 mm path along +X sampled every 0.0085 mm
    (distance-triggered), the stamps whole seconds with the point counts of ``COUNTS``."""
    n = sum(COUNTS)
    s = np.linspace(0.0, 40.0, n)
    rng = np.random.default_rng(7)
    y = -845.25 + 1e-3 * AMPLITUDE_UM * np.sin(2 * np.pi * s / WAVELENGTH_MM)
    y += rng.normal(0.0, 2e-4, n)
    z = 312.5 + rng.normal(0.0, 2e-4, n)
    sec = np.repeat(np.arange(len(COUNTS)), COUNTS)
    lines = ["// SpatialAnalyzer SA 2024.2.0923.4 ( x64 )",
             "// Points Relative to Coordinate Frame 'A::WORLD'",
             "// AXES = CARTESIAN: X,  Y,  Z (mm)"]
    lines += [f"stream_px_f2,  feed2,  {k},  {1520.0 + s[k]:.6f},  {y[k]:.6f},  {z[k]:.6f},  "
              f"02/12/26 10:{15 + (7 + sec[k]) // 60:02d}:{(7 + sec[k]) % 60:02d}"
              for k in range(n)]
    path.write_text("\n".join(lines) + "\n")
    return path


def _convert(src: Path, staging: Path, argv: list[str]) -> list[dict]:
    parser = argparse.ArgumentParser()
    spatialanalyzer.add_arguments(parser)
    return spatialanalyzer.convert([src], staging, parser.parse_args(argv))


ARGS = ["--direction", "px", "--feed-mm-s", "2"]
EXPERIMENT = {"spindle_rpm": 6000, "flutes": 2, "tool_diameter_mm": 10.0, "cut_length_mm": 40.0}


def test_spatial_only_stream_imports_and_its_spatial_line_is_found(tmp_path):
    src = _sa_stream(tmp_path / "stream.txt")
    entries = _convert(src, tmp_path / "raw", ARGS + ["--spatial-only"])
    assert entries == [{"path": "tracker/px_f2.csv", "kind": "tracker", "direction": "px",
                        "feed_mm_s": 2.0, "time_base": "none"}]
    # the manifest takes the entry without a rate
    plan = {"experiment": EXPERIMENT, "cuts": [], "files": [dict(entries[0], sha256="0" * 64)]}
    parse_manifest(plan, tmp_path / "manifest.yaml")
    t, p = read_tracker(tmp_path / "raw" / entries[0]["path"], spatial_only=True)
    assert t.size == sum(COUNTS)
    assert np.all(np.diff(t) >= 0) and t[-1] == len(COUNTS) - 1  # the export's stamps kept
    with pytest.raises(RawDataError, match="t_s"):  # not a uniform rate
        read_tracker(tmp_path / "raw" / entries[0]["path"], fs_hz=200.0)
    prof = spatial_profile(None, p, ds_mm=0.01, trim_mm=1.0, detrend_order=3)
    assert np.isnan(prof.speed_mm_s)
    spec = profile_spectrum(prof, nfft=32768)
    pk = spectrum_peaks(spec, fmin_per_mm=2.5 * spec.resolution_per_mm, fmax_per_mm=20.0,
                        threshold=25.0, n_peaks=20, local_ratio=1.5, floor_halfwidth_bins=25)
    assert len(pk) == 1
    assert pk["f_spatial_per_mm"].iloc[0] == pytest.approx(1 / WAVELENGTH_MM,
                                                           abs=0.1 * spec.resolution_per_mm)
    assert pk["amplitude_um"].iloc[0] == pytest.approx(AMPLITUDE_UM, rel=0.05)
    assert pk["component"].iloc[0] == "lateral"


def test_without_the_flag_one_line_suggests_spatial_only(tmp_path):
    src = _sa_stream(tmp_path / "stream.txt")
    for extra in ([], ["--fs-hz", "200"]):
        with pytest.raises(RawDataError) as info:
            _convert(src, tmp_path / "raw", ARGS + extra)
        msg = str(info.value)
        assert "\n" not in msg.strip()
        assert msg.startswith(str(src))
        assert f"{sum(COUNTS)} points on {len(COUNTS)} time stamps holding 98–444 points" in msg
        assert "(expected --spatial-only" in msg
        assert not (tmp_path / "raw" / "tracker" / "px_f2.csv").exists()


def test_a_time_triggered_stream_is_not_taken_for_an_event_triggered_one(tmp_path):
    """Whole-second stamps with even counts (200 Hz) keep the rate's message."""
    src = tmp_path / "even.txt"
    n = 640
    sec = np.repeat(np.arange(4), [40, 200, 200, 200])
    src.write_text("// AXES = CARTESIAN: X,  Y,  Z (mm)\n" + "".join(
        f"c,  g,  {k},  {1520 + 0.01 * k:.4f},  0,  0,  02/12/26 10:15:{7 + sec[k]:02d}\n"
        for k in range(n)))
    with pytest.raises(RawDataError, match="no rate was stated") as info:
        _convert(src, tmp_path / "raw", ARGS)
    assert "--spatial-only" not in str(info.value)


def test_manifest_refuses_another_time_base(tmp_path):
    entry = {"path": "tracker/px_f2.csv", "kind": "tracker", "direction": "px",
             "feed_mm_s": 2.0, "time_base": "seconds", "fs_hz": 10.0, "sha256": "0" * 64}
    with pytest.raises(RawDataError, match=r"time_base is 'seconds'.*expected none"):
        parse_manifest({"experiment": EXPERIMENT, "cuts": [], "files": [entry]},
                       tmp_path / "manifest.yaml")
    del entry["fs_hz"], entry["time_base"]  # a timed stream still needs its rate
    with pytest.raises(RawDataError, match="key 'fs_hz' is missing"):
        parse_manifest({"experiment": EXPERIMENT, "cuts": [], "files": [entry]},
                       tmp_path / "manifest.yaml")


def test_peaks_of_a_run_without_time_base_are_not_classified_temporal_or_spatial():
    # one temporal source (2 Hz) seen at three feeds; the 4 mm/s run has no time base
    peaks = pd.DataFrame({"direction": ["px"] * 4, "feed_mm_s": [1.0, 2.0, 4.0, 4.0],
                          "f_spatial_per_mm": [2.0, 1.0, 0.5, 0.4],
                          "joint": pd.array([pd.NA, pd.NA, pd.NA, 3], dtype="Int64"),
                          "run": ["px_f1", "px_f2", "px_f4", "px_f4"]})
    res = {"px_f1": 0.025, "px_f2": 0.025, "px_f4": 0.025}
    timed = classify_peaks(peaks, res)
    assert timed["mechanism"].tolist() == ["temporal", "temporal", "temporal", "gear"]
    out = classify_peaks(peaks, res, untimed=["px_f4"])
    # the untimed run: gear-matched stays gear, the rest unclassified; it witnesses for no
    # other run, so the 1 and 2 mm/s peaks still witness each other
    assert out["mechanism"].tolist() == ["temporal", "temporal", "unclassified", "gear"]


def test_robomill_import_says_the_stream_has_no_time_base(tmp_path, capsys):
    import yaml

    from robomill.cli import main
    from robomill.io.manifest import load_manifest

    src = _sa_stream(tmp_path / "stream.txt")
    raw = tmp_path / "raw"
    assert main(["init", str(raw)]) == 0
    capsys.readouterr()
    assert main(["import", "spatialanalyzer", str(src), "--to", str(raw), *ARGS]) == 1
    out = capsys.readouterr().out.splitlines()
    assert len(out) == 2 and "--spatial-only" in out[0] and out[1].endswith("nothing was written")
    assert main(["import", "spatialanalyzer", str(src), "--to", str(raw), *ARGS,
                 "--spatial-only"]) == 0
    out = capsys.readouterr().out
    assert "px_f2.csv: no time base (--spatial-only): analysed in space only" in out
    entry = yaml.safe_load((raw / "manifest.yaml").read_text())["files"][0]
    assert entry["time_base"] == "none" and "fs_hz" not in entry
    data = yaml.safe_load((raw / "manifest.yaml").read_text())
    data["experiment"] = EXPERIMENT
    (raw / "manifest.yaml").write_text(yaml.safe_dump(data))
    assert load_manifest(raw / "manifest.yaml").verify_file("tracker/px_f2.csv").is_file()


def test_a_tracker_run_id_is_its_own_key_or_direction_and_feed(tmp_path):
    """A tracker entry's ``run`` names it; without one it is ``<dir>_f<feed>``; a malformed or
    repeated id is refused in one line naming the entry (two runs of one direction and feed
    need their own ids)."""
    from robomill.experiment import tracker_run

    base = {"kind": "tracker", "direction": "px", "feed_mm_s": 2.0, "fs_hz": 10.0,
            "sha256": "0" * 64}
    assert tracker_run(base) == "px_f2"
    assert tracker_run({**base, "direction": None, "direction_deg": 45}) == "d45_f2"
    assert tracker_run({**base, "run": "px_f2_repeat"}) == "px_f2_repeat"
    one, two = {**base, "path": "tracker/a.csv"}, {**base, "path": "tracker/b.csv"}
    with pytest.raises(RawDataError, match=r"files\[1\] \(tracker/b\.csv\)\.run: tracker run "
                                           r"id 'px_f2' also names 'tracker/a\.csv'"):
        parse_manifest({"experiment": EXPERIMENT, "cuts": [], "files": [one, two]},
                       tmp_path / "manifest.yaml")
    m = parse_manifest({"experiment": EXPERIMENT, "cuts": [],
                        "files": [one, {**two, "run": "px_f2_b"}]}, tmp_path / "manifest.yaml")
    assert [tracker_run(f) for f in m.files] == ["px_f2", "px_f2_b"]
    with pytest.raises(RawDataError, match=r"run id 'a b' is malformed"):
        parse_manifest({"experiment": EXPERIMENT, "cuts": [], "files": [{**one, "run": "a b"}]},
                       tmp_path / "manifest.yaml")


def test_repeated_runs_at_one_feed_are_classified_each_by_its_id():
    """Two runs of +X at 2 mm/s (a repeat, ids a and b) and one at 4 mm/s: each peak's run is
    found by its id, not by (direction, feed) (which would merge a and b); the 13 Hz line is
    temporal in all three, the spatial 0.45 mm⁻¹ line with no gear is spatial."""
    peaks = pd.DataFrame({"run": ["a", "b", "c", "a", "b", "c"], "direction": ["px"] * 6,
                          "feed_mm_s": [2.0, 2.0, 4.0, 2.0, 2.0, 4.0],
                          "f_spatial_per_mm": [6.5, 6.5, 3.25, 0.45, 0.45, 0.45],
                          "joint": pd.array([pd.NA] * 6, dtype="Int64")})
    out = classify_peaks(peaks, {"a": 1 / 38.0, "b": 1 / 30.0, "c": 1 / 38.0},
                         untimed=["b"])
    assert out["mechanism"].tolist() == ["temporal", "unclassified", "temporal",
                                         "spatial", "unclassified", "spatial"]
