"""Manifest validation and sha256 checks; the raw folder is never modified."""

from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import run_snakemake, tree_digest

from robomill.experiment import Cut
from robomill.io import RawDataError
from robomill.io.manifest import build_manifest, load_manifest, write_manifest


def _raw_dir(tmp_path: Path) -> Path:
    raw = tmp_path / "raw"
    (raw / "profiles").mkdir(parents=True)
    (raw / "profiles" / "s1_g1_px.csv").write_text("x_mm,z_um\n0,0.1\n0.00125,0.2\n")
    cut = Cut("s1_g1_px", 1, 1, "px", 1.0, 0.25)
    m = build_manifest({"spindle_rpm": 28000, "flutes": 2, "tool_diameter_mm": 6.0,
                        "cut_length_mm": 40.0}, [cut],
                       [{"path": "profiles/s1_g1_px.csv", "kind": "profile", "cut": cut.id}], raw)
    write_manifest(m, raw / "manifest.yaml")
    return raw



def test_good_manifest_verifies(tmp_path):
    m = load_manifest(_raw_dir(tmp_path) / "manifest.yaml")
    m.verify_all()
    assert m.cut("s1_g1_px").feed_mm_s == 1.0


def test_experiment_modal_band_is_optional_and_kept(tmp_path):
    raw = _raw_dir(tmp_path)
    data = yaml.safe_load((raw / "manifest.yaml").read_text())
    assert load_manifest(raw / "manifest.yaml").experiment.get("modal_band_hz") is None
    data["experiment"]["modal_band_hz"] = [10, 100.0]
    (raw / "manifest.yaml").write_text(yaml.safe_dump(data))
    assert load_manifest(raw / "manifest.yaml").experiment["modal_band_hz"] == [10, 100.0]


def test_changed_file_is_named(tmp_path):
    raw = _raw_dir(tmp_path)
    (raw / "profiles" / "s1_g1_px.csv").write_text("x_mm,z_um\n0,0.1\n0.00125,0.3\n")
    with pytest.raises(RawDataError, match=r"s1_g1_px\.csv.*sha256"):
        load_manifest(raw / "manifest.yaml").verify_all()


def test_unlisted_and_missing_files_are_named(tmp_path):
    raw = _raw_dir(tmp_path)
    (raw / "profiles" / "extra.csv").write_text("x_mm,z_um\n")
    with pytest.raises(RawDataError, match="extra.csv.*not listed"):
        load_manifest(raw / "manifest.yaml").verify_all()
    (raw / "profiles" / "extra.csv").unlink()
    (raw / "profiles" / "s1_g1_px.csv").unlink()
    with pytest.raises(RawDataError, match="s1_g1_px.csv.*does not exist"):
        load_manifest(raw / "manifest.yaml").verify_all()


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d["files"][0].update(kind="spectrum"), "unknown kind 'spectrum'"),
        (lambda d: d["files"][0].pop("cut"), "key 'cut' is missing"),
        (lambda d: d["cuts"].append(dict(d["cuts"][0])), "duplicate cut id"),
        (lambda d: d["cuts"][0].update(id="s1_g2_px"), "disagrees"),
        (lambda d: d.pop("experiment"), "'experiment' is missing"),
        (lambda d: d["experiment"].update(modal_band_hz=[100, 10]), "modal_band_hz is"),
        (lambda d: d["experiment"].update(modal_band_hz="10-100"), "modal_band_hz is"),
    ],
)
def test_bad_manifest_is_explained(tmp_path, edit, message):
    raw = _raw_dir(tmp_path)
    data = yaml.safe_load((raw / "manifest.yaml").read_text())
    edit(data)
    (raw / "manifest.yaml").write_text(yaml.safe_dump(data))
    with pytest.raises(RawDataError, match=message) as info:
        load_manifest(raw / "manifest.yaml")
    assert "manifest.yaml" in str(info.value)


@pytest.mark.pipeline
def test_pipeline_stops_on_sha_mismatch_and_leaves_raw_untouched(tmp_path, repo):
    raw = _raw_dir(tmp_path)
    (raw / "profiles" / "s1_g1_px.csv").write_text("x_mm,z_um\n0,0.1\n0.00125,0.9\n")
    before = tree_digest(raw)
    cfg = yaml.safe_load((repo / ".test/config.yaml").read_text())
    cfg["data"] = {"source": "raw", "raw_dir": str(raw)}
    cfgfile = tmp_path / "config.yaml"
    cfgfile.write_text(yaml.safe_dump(cfg))
    work = tmp_path / "work"
    work.mkdir()
    proc = run_snakemake(work, "-j1", "results/ingest/cuts.csv", configfile=cfgfile, timeout=300)
    assert proc.returncode != 0
    log = (work / "results/logs/ingest/manifest.log").read_text()
    assert "s1_g1_px.csv" in log and "sha256" in log
    assert not (work / "results/ingest/cuts.csv").exists()
    assert tree_digest(raw) == before
    # the last thing printed is the one-screen failure summary naming job, error and log
    tail = proc.stderr.strip().splitlines()[-4:]
    summary = "\n".join(tail)
    assert "1 failed job(s)" in summary
    assert "- ingest_manifest: RawDataError:" in summary and "sha256" in summary
    assert "log: results/logs/ingest/manifest.log" in summary


# --- cuts of any design: per-cut keys overriding the experiment ----------------------------
EXP = {"spindle_rpm": 28000, "flutes": 2, "tool_diameter_mm": 6.0, "cut_length_mm": 40.0}
FREE_CUTS = [
    {"id": "n12k_mx", "feed_mm_s": 2.0, "depth_mm": 0.5, "direction": "mx",
     "spindle_rpm": 12000, "flutes": 3, "radial_immersion": 0.5, "milling": "down"},
    {"id": "n18k.d45", "feed_mm_s": 3.0, "depth_mm": 0.5, "direction_deg": 45.0,
     "spindle_rpm": 18000, "flutes": 3, "tool_diameter_mm": 8.0,
     "start_mm": [650.0, -50.0, 180.0]},
    {"id": "thesis-like", "set": 2, "feed_mm_s": 1.0, "depth_mm": 0.25, "direction": "px"},
]


def _parse(cuts):
    from robomill.io.manifest import parse_manifest

    return parse_manifest({"experiment": EXP, "cuts": cuts, "files": []}, "manifest.yaml")


def test_cuts_of_any_design_take_their_own_process_values():
    from robomill.experiment import cut_process, cuts_table, feed_direction, is_thesis_design

    m = _parse(FREE_CUTS)
    a, b, c = m.cuts
    pa, pb, pc = (cut_process(x, EXP) for x in m.cuts)
    assert pa["tooth_passing_hz"] == pytest.approx(3 * 12000 / 60)  # 600 Hz at its own speed
    assert pb["tooth_passing_hz"] == pytest.approx(3 * 18000 / 60)
    assert pc["tooth_passing_hz"] == pytest.approx(2 * 28000 / 60)  # the experiment's
    assert pa["feed_per_tooth_mm"] == pytest.approx(2.0 / 600.0)
    assert (pa["milling"], pa["radial_immersion"], pc["milling"], pc["radial_immersion"]) == \
        ("down", 0.5, "slot", 1.0)
    assert (pb["tool_diameter_mm"], pc["tool_diameter_mm"]) == (8.0, 6.0)
    np.testing.assert_allclose(feed_direction(a), [-1, 0, 0])
    np.testing.assert_allclose(feed_direction(b), [np.sqrt(0.5), np.sqrt(0.5), 0], atol=1e-12)
    assert c.segment is None and a.set is None
    assert not is_thesis_design(m.cuts)
    table = cuts_table(m.cuts, EXP["spindle_rpm"], EXP["flutes"])
    np.testing.assert_allclose(table["tooth_passing_hz"], [600.0, 900.0, 2800 / 3])
    assert list(table["milling"]) == ["down", "slot", "slot"]
    assert list(table["spindle_rpm"]) == [12000.0, 18000.0, 28000.0]
    # the manifest mapping round-trips, keys left at the experiment's value omitted
    assert _parse([x.as_dict() for x in m.cuts]).cuts == m.cuts
    assert "spindle_rpm" not in c.as_dict() and "start_mm" in b.as_dict()


def test_the_thesis_design_keeps_its_manifest_and_tables():
    from robomill.experiment import cuts_table, is_thesis_design, plan_cuts

    cuts = plan_cuts([{"set": 1, "depth_mm": 0.25, "feeds_mm_s": [1, 2]}])
    assert is_thesis_design(cuts)
    assert list(cuts[0].as_dict()) == ["id", "set", "segment", "direction", "feed_mm_s",
                                       "depth_mm"]
    assert list(cuts_table(cuts, 28000, 2).columns) == [
        "cut", "set", "segment", "direction", "feed_mm_s", "depth_mm", "feed_per_tooth_um",
        "spindle_hz", "tooth_passing_hz"]


BAD_CUTS = [
    ({"colour": "red"}, r"cuts\[0\]: unknown key\(s\) colour"),
    ({"spindle_rpm": "fast"}, r"cuts\[0\]\.spindle_rpm: key 'spindle_rpm' is 'fast'"),
    ({"flutes": 2.5}, r"cuts\[0\]\.flutes: key 'flutes' is 2\.5 \(expected int\)"),
    ({"set": "one"}, r"cuts\[0\]\.set: key 'set' is 'one'"),
    ({"direction": None}, r"cuts\[0\]: neither direction nor direction_deg"),
    ({"direction_deg": 45.0}, r"cuts\[0\]: both direction and direction_deg are given"),
    ({"direction": "pz"}, r"cuts\[0\]\.direction: direction 'pz' is unknown \(expected one "
                          r"of px, py, my, mx"),
    ({"direction_deg": "north", "direction": None},
     r"cuts\[0\]\.direction_deg: key 'direction_deg' is 'north'"),
    ({"spindle_rpm": -100}, r"cuts\[0\]\.spindle_rpm: spindle_rpm is -100"),
    ({"tool_diameter_mm": 0}, r"cuts\[0\]\.tool_diameter_mm: tool_diameter_mm is 0"),
    ({"flutes": 0}, r"cuts\[0\]\.flutes: flutes is 0"),
    ({"radial_immersion": 1.5}, r"cuts\[0\]\.radial_immersion: radial_immersion is 1\.5 "
                                r"\(expected a_e / D in \(0, 1\]"),
    ({"milling": "climb"}, r"cuts\[0\]\.milling: milling 'climb' is unknown"),
    ({"milling": "slot", "radial_immersion": 0.5}, r"cuts\[0\]: milling slot with "
                                                   r"radial_immersion 0\.5"),
    ({"start_mm": [1.0, 2.0]}, r"cuts\[0\]\.start_mm: start_mm is \[1\.0, 2\.0\]"),
    ({"start_mm": "origin"}, r"cuts\[0\]\.start_mm: key 'start_mm' is 'origin'"),
    ({"id": "s1 g1"}, r"cuts\[0\]\.id: cut id 's1 g1' is malformed"),
]


@pytest.mark.parametrize(("edit", "message"), BAD_CUTS)
def test_bad_cut_keys_are_named(edit, message):
    cut = {"id": "c1", "feed_mm_s": 1.0, "depth_mm": 0.25, "direction": "px", **edit}
    cut = {k: v for k, v in cut.items() if v is not None}
    with pytest.raises(RawDataError, match=r"^manifest\.yaml: " + message):
        _parse([cut])


@pytest.mark.parametrize(("entry", "message"), [
    ({"direction": "mx"}, None),
    ({"direction_deg": 45.0}, None),
    ({}, r"files\[0\] \(tracker/r\.csv\): give one of direction, direction_deg"),
    ({"direction": "px", "direction_deg": 0.0}, r"direction_deg \(both are given\)"),
    ({"direction": "east"}, r"files\[0\] \(tracker/r\.csv\)\.direction: direction 'east' is "
                            r"unknown"),
    ({"direction_deg": "ne"}, r"\.direction_deg: key 'direction_deg' is 'ne'"),
])
def test_tracker_runs_take_the_direction_forms_of_cuts(entry, message):
    from robomill.experiment import tracker_direction, tracker_run_id
    from robomill.io.manifest import parse_manifest

    f = {"path": "tracker/r.csv", "kind": "tracker", "feed_mm_s": 2.0, "fs_hz": 815.0,
         "sha256": "0", **entry}
    data = {"experiment": EXP, "cuts": [], "files": [f]}
    if message is None:
        m = parse_manifest(data, "manifest.yaml")
        run = tracker_run_id(tracker_direction(m.files[0]), 2.0)
        assert run == {"direction": "mx_f2", "direction_deg": "d45_f2"}[next(iter(entry))]
    else:
        with pytest.raises(RawDataError, match=message):
            parse_manifest(data, "manifest.yaml")


def test_unlisted_files_in_a_data_folder_stop_ingestion_naming_all(tmp_path):
    raw = _raw_dir(tmp_path)
    for name in ("extra.csv", "more.csv"):
        (raw / "profiles" / name).write_text("x_mm,z_um\n")
    with pytest.raises(RawDataError, match=r"2 file\(s\) in a data folder.*"
                       r"profiles/extra\.csv, profiles/more\.csv"):
        load_manifest(raw / "manifest.yaml").verify_all()


def test_unlisted_files_elsewhere_give_one_warning_line(tmp_path):
    raw = _raw_dir(tmp_path)
    (raw / "notes").mkdir()
    (raw / "notes" / "lab book.txt").write_text("cut 1 went fine\n")
    (raw / "photo.jpg").write_bytes(b"\xff\xd8")
    warnings = load_manifest(raw / "manifest.yaml").verify_all()
    assert len(warnings) == 1
    assert "2 file(s) not listed" in warnings[0]
    assert "notes/lab book.txt" in warnings[0] and "photo.jpg" in warnings[0]


def test_ignore_patterns_are_gitignore_style_and_kept_by_robomill_manifest(tmp_path):
    from robomill.cli.manifest import update_manifest

    raw = _raw_dir(tmp_path)
    (raw / "notes").mkdir()
    (raw / "notes" / "a.txt").write_text("a\n")
    (raw / "profiles" / "photo.jpg").write_bytes(b"\xff\xd8")
    (raw / "profiles" / "project.mnt").write_bytes(b"\x00")
    (raw / "keep.jpg").write_bytes(b"\xff\xd8")
    data = yaml.safe_load((raw / "manifest.yaml").read_text())
    data["ignore"] = ["notes/", "*.jpg", "/profiles/*.mnt", "!keep.jpg"]
    (raw / "manifest.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    # inside profiles/ both files are ignored (a pattern without a slash matches at any
    # depth, an anchored one from the raw folder); keep.jpg is re-included by '!'
    warnings = load_manifest(raw / "manifest.yaml").verify_all()
    assert warnings == [w for w in warnings if "keep.jpg" in w] and len(warnings) == 1
    assert "a.txt" not in warnings[0] and "photo.jpg" not in warnings[0]
    out, _, todo = update_manifest(raw)
    assert out["ignore"] == data["ignore"]
    assert [f["path"] for f in out["files"]] == ["profiles/s1_g1_px.csv"]
    assert not any("a.txt" in t or "photo" in t or "mnt" in t for t in todo)
    assert any("keep.jpg" in t for t in todo)
    data["ignore"] = "*.jpg"
    (raw / "manifest.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    with pytest.raises(RawDataError, match=r"ignore: ignore is '\*\.jpg' \(expected a list"):
        load_manifest(raw / "manifest.yaml")


def test_robomill_manifest_names_the_import_of_an_areal_export(tmp_path):
    from robomill.cli.manifest import update_manifest

    raw = _raw_dir(tmp_path)
    (raw / "areal").mkdir()
    (raw / "areal" / "scan.x3p").write_bytes(b"PK")
    _, _, todo = update_manifest(raw)
    assert any("areal/scan.x3p: native areal scan export: convert it with robomill import "
               "x3p areal/scan.x3p --areal" in t for t in todo), todo
