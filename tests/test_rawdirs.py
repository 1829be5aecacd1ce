"""One study from several raw folders (robomill.io.rawdirs, config data.raw_dirs): the cuts of
all, per-cut files from their folder, instrument files that are not per cut from the first
folder that has them, one cell, and a cut id that names two different cuts refused in one
line."""

import pytest

from robomill.errors import RawDataError
from robomill.experiment import Cut
from robomill.io.manifest import build_manifest, write_manifest
from robomill.io.rawdirs import load_study_manifest, raw_folders
from robomill.study import load_study, write_study

EXP = {"spindle_rpm": 6000, "flutes": 2, "tool_diameter_mm": 10.0, "cut_length_mm": 40.0}


def _folder(root, name, cut_ids, *, exp=EXP, impact="hit 1\n", cell="robot: {name: kr}\n",
            force_text=None):
    """A raw folder with one force file per cut, one impact hit and a cell file."""
    raw = root / name
    (raw / "force").mkdir(parents=True)
    (raw / "impact").mkdir()
    cuts, files = [], []
    for cid in cut_ids:
        (raw / "force" / f"{cid}.csv").write_text(force_text or f"t_s,Fx_N\n0,{len(cid)}\n{cid}\n")
        cuts.append(Cut(id=cid, set=None, segment=None, direction="mx", feed_mm_s=5.0,
                        depth_mm=1.0))
        files.append({"path": f"force/{cid}.csv", "kind": "force", "cut": cid,
                      "fs_hz": 10000.0})
    (raw / "impact" / "h1.csv").write_text(impact)
    files.append({"path": "impact/h1.csv", "kind": "impact", "point": "tcp",
                  "direction": "x"})
    (raw / "cell.yaml").write_text(cell)
    files.append({"path": "cell.yaml", "kind": "cell"})
    write_manifest(build_manifest(exp, cuts, files, raw), raw / "manifest.yaml")
    return raw


def test_two_folders_make_one_study_with_the_cuts_of_both(tmp_path):
    a = _folder(tmp_path, "study", ["c1", "c2"])
    b = _folder(tmp_path / "plan" / "next", "raw", ["p1"], impact="hit 2\n",
                exp={**EXP, "spindle_rpm": 30000})
    m = load_study_manifest([a / "manifest.yaml", b / "manifest.yaml"])
    assert [c.id for c in m.cuts] == ["c1", "c2", "p1"]
    # the later folder's cut keeps its own folder's speed; the first folder's take the study's
    assert m.cut("p1").spindle_rpm == 30000 and m.cut("c1").spindle_rpm is None
    force = {f["cut"]: f for f in m.files_of("force")}
    assert force["p1"]["path"] == "../plan/next/raw/force/p1.csv"
    # every rule reads <first folder>/<path>: that is the later folder's file, verified
    assert m.verify_file(force["p1"]["path"]).resolve() == (b / "force" / "p1.csv").resolve()
    # not per cut: the first folder's impact hit only; one cell file
    assert [f["path"] for f in m.files_of("impact")] == ["impact/h1.csv"]
    assert [f["path"] for f in m.files_of("cell")] == ["cell.yaml"]
    m.verify_all()
    # the study artefact reads back the merged study
    back = load_study(write_study(m, tmp_path / "study.yaml"))
    assert [c.id for c in back.cuts] == ["c1", "c2", "p1"]
    assert back.files == m.files


def test_a_cut_id_with_other_files_in_a_later_folder_is_one_line(tmp_path):
    a = _folder(tmp_path, "study", ["c1", "c2"])
    b = _folder(tmp_path, "run", ["c2"], force_text="t_s,Fx_N\n0,99\n")
    with pytest.raises(RawDataError) as err:
        load_study_manifest([a / "manifest.yaml", b / "manifest.yaml"])
    line = str(err.value)
    assert "\n" not in line
    assert "'c2'" in line and str(b / "manifest.yaml") in line and str(a) in line


def test_the_same_cut_with_the_same_files_is_taken_once(tmp_path):
    a = _folder(tmp_path, "study", ["c1"])
    b = _folder(tmp_path, "copy", ["c1", "p1"])
    m = load_study_manifest([a / "manifest.yaml", b / "manifest.yaml"])
    assert [c.id for c in m.cuts] == ["c1", "p1"]
    assert sorted(f["cut"] for f in m.files_of("force")) == ["c1", "p1"]


def test_a_cell_file_that_disagrees_is_one_line(tmp_path):
    a = _folder(tmp_path, "study", ["c1"])
    b = _folder(tmp_path, "run", ["p1"], cell="robot: {name: other}\n")
    with pytest.raises(RawDataError, match="cell file differs") as err:
        load_study_manifest([a / "manifest.yaml", b / "manifest.yaml"])
    assert "\n" not in str(err.value)
    # the same cell written otherwise (key order, spacing) agrees
    c = _folder(tmp_path, "run2", ["p2"], cell="robot:\n  name: kr\n")
    assert len(load_study_manifest([a / "manifest.yaml", c / "manifest.yaml"]).cuts) == 2


def test_a_hand_written_path_leaving_its_folder_is_still_refused(tmp_path):
    from robomill.io.manifest import parse_manifest

    data = {"experiment": EXP, "cuts": [], "files": [
        {"path": "../elsewhere/x.csv", "kind": "impact", "point": "tcp", "direction": "x",
         "sha256": "0" * 64}]}
    with pytest.raises(RawDataError, match="leaves the raw folder"):
        parse_manifest(data, tmp_path / "raw" / "manifest.yaml")


def test_raw_folders_default_and_synthetic():
    assert raw_folders({"source": "raw", "raw_dir": "data/raw", "raw_dirs": []}) == ["data/raw"]
    assert raw_folders({"source": "raw", "raw_dir": "data/raw",
                        "raw_dirs": ["a", "b"]}) == ["a", "b"]
    assert raw_folders({"source": "synthetic", "raw_dir": "data/raw",
                        "raw_dirs": ["results/synthetic/raw/", "r/run"]}) == [
        "results/synthetic/raw", "r/run"]


def test_a_first_folder_reached_through_a_link_still_finds_the_later_files(tmp_path):
    a = _folder(tmp_path / "disk" / "deep", "study", ["c1"])  # one level deeper than the link
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "raw").symlink_to(a, target_is_directory=True)
    b = _folder(tmp_path, "run", ["p1"])
    m = load_study_manifest([tmp_path / "data" / "raw" / "manifest.yaml", b / "manifest.yaml"])
    p1 = m.files_of("force", cut="p1")[0]["path"]
    assert m.verify_file(p1).read_text() == (b / "force" / "p1.csv").read_text()
    back = load_study(write_study(m, tmp_path / "study.yaml"))
    assert [c.id for c in back.cuts] == ["c1", "p1"]
