"""The study artefact (robomill.study): written once from the manifest, read by every
analysis rule; the same cuts, files and experiment, each cut's design resolved."""

import pytest
import yaml

from robomill.errors import RawDataError
from robomill.experiment import Cut
from robomill.io.manifest import build_manifest, parse_manifest, write_manifest
from robomill.study import load_study, study_dict, write_study


def _manifest(tmp_path):
    raw = tmp_path / "raw"
    (raw / "forces").mkdir(parents=True)
    (raw / "forces" / "a.csv").write_text("t_s,Fx_N\n0,1\n")
    (raw / "forces" / "b.csv").write_text("t_s,Fx_N\n0,2\n")
    cuts = [Cut(id="a", set=None, segment=None, direction="mx", feed_mm_s=5.0, depth_mm=3.0),
            Cut(id="b", set=None, segment=None, direction=None, direction_deg=30.0,
                feed_mm_s=2.5, depth_mm=1.0, spindle_rpm=9000.0, flutes=3,
                radial_immersion=0.25, milling="down")]
    files = [{"path": "forces/a.csv", "kind": "force", "cut": "a", "fs_hz": 10000.0},
             {"path": "forces/b.csv", "kind": "force", "cut": "b", "fs_hz": 10000.0}]
    exp = {"spindle_rpm": 6000, "flutes": 2, "tool_diameter_mm": 10.0, "cut_length_mm": 40.0}
    path = write_manifest(build_manifest(exp, cuts, files, raw), raw / "manifest.yaml")
    return parse_manifest(yaml.safe_load(path.read_text()), path)


def test_the_study_reads_back_as_the_manifest_it_was_written_from(tmp_path):
    m = _manifest(tmp_path)
    path = write_study(m, tmp_path / "study.yaml")
    s = load_study(path)
    assert s.cuts == m.cuts and s.files == m.files and s.experiment == m.experiment
    assert s.path == m.path and s.raw_dir == m.raw_dir
    assert s.verify_file("forces/b.csv") == m.raw_dir / "forces" / "b.csv"


def test_each_cut_carries_its_resolved_design(tmp_path):
    """Written by hand from the manifest above: cut a takes the experiment's speed and flutes
    (6000 rpm, 2 flutes: 5 mm/s / (2 × 100 rev/s) = 0.025 mm, 200 Hz tooth passing), a slot
    along −X (180°); cut b its own (9000 rpm, 3 flutes: 2.5 / (3 × 150) mm, 450 Hz), down
    milling at a_e/D 0.25 along 30°."""
    d = study_dict(_manifest(tmp_path))
    proc = {c["id"]: c["process"] for c in d["cuts"]}
    assert proc["a"] == pytest.approx({
        "spindle_rpm": 6000.0, "flutes": 2, "tool_diameter_mm": 10.0, "radial_immersion": 1.0,
        "milling": "slot", "direction_deg": 180.0, "feed_per_tooth_mm": 0.025,
        "tooth_passing_hz": 200.0})
    assert proc["b"]["feed_per_tooth_mm"] == pytest.approx(2.5 / 450.0)
    assert proc["b"]["tooth_passing_hz"] == pytest.approx(450.0)
    assert (proc["b"]["milling"], proc["b"]["direction_deg"]) == ("down", 30.0)
    assert d["manifest"].endswith("raw/manifest.yaml") and d["cell"] is None


def test_a_cut_without_speed_has_no_process_and_the_study_still_loads(tmp_path):
    m = _manifest(tmp_path)
    m.experiment.pop("spindle_rpm")
    d = study_dict(m)
    assert [c["process"] is None for c in d["cuts"]] == [True, False]


def test_a_changed_raw_file_stops_the_job_that_reads_it(tmp_path):
    m = _manifest(tmp_path)
    s = load_study(write_study(m, tmp_path / "study.yaml"))
    (m.raw_dir / "forces" / "a.csv").write_text("t_s,Fx_N\n0,9\n")
    with pytest.raises(RawDataError, match="sha256 is"):
        s.verify_file("forces/a.csv")


@pytest.mark.parametrize("text, match", [
    (None, "cannot read the study"),
    ("[1, 2]", "not a study file"),
    ("cuts: []\n", "not a study file"),
    ("a: [\n", "cannot read the study"),
])
def test_a_missing_or_foreign_study_is_one_clear_error(tmp_path, text, match):
    path = tmp_path / "study.yaml"
    if text is not None:
        path.write_text(text)
    with pytest.raises(RawDataError, match=match) as exc:
        load_study(path)
    assert str(path) in str(exc.value) and "\n" not in str(exc.value)
