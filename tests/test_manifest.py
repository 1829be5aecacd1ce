"""Manifest validation and sha256 checks; the raw folder is never modified."""

from pathlib import Path

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
