"""A lab's own surface files through the documented commands (``robomill init``, ``robomill
import``, ``robomill manifest``, ``robomill check``, ``snakemake ch2``) with the default
``config.yaml``: a SMATS XML profile that states its own parameters (chapter 2 shows ours
beside them), and the raw folder as a lab keeps it (notes and photos beside the data)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
import yaml
from conftest import REPO, run_snakemake

pytestmark = [pytest.mark.pipeline]

DATA = REPO / "tests" / "data"
ROBOMILL = Path(sys.executable).parent / "robomill"


def robomill(*args) -> subprocess.CompletedProcess:
    return subprocess.run([str(ROBOMILL), *map(str, args)], capture_output=True, text=True,
                          timeout=300)


def _fill_design(raw: Path) -> None:
    """What ``robomill manifest`` cannot infer, written as a user would."""
    text = (raw / "manifest.yaml").read_text()
    m = yaml.safe_load(text)
    m["experiment"].update(spindle_rpm=6000, flutes=2)
    for c in m["cuts"]:
        c.update(feed_mm_s=1.0, depth_mm=0.25)
    m["ignore"] = ["notes/"]
    (raw / "manifest.yaml").write_text(yaml.safe_dump(m, sort_keys=False))


def test_smats_xml_reference_parameters_in_chapter_2(tmp_path):
    raw = tmp_path / "raw"
    xml = DATA / "constructed" / "smats" / "nist_layout_reference.xml"
    for args in (("init", raw), ("import", "smats", xml, "--to", raw, "--cut", "s1_g1_px"),
                 ("manifest", raw)):
        proc = robomill(*args)
        assert proc.returncode == 0, (args, proc.stdout, proc.stderr)
    _fill_design(raw)
    (raw / "notes").mkdir()
    (raw / "notes" / "lab book.txt").write_text("s1_g1_px: coolant off\n")  # ignored
    (raw / "photo.jpg").write_bytes(b"\xff\xd8\xff")                       # warned about
    assert robomill("manifest", raw).returncode == 0  # sha256 of the edits; keeps ignore:
    assert yaml.safe_load((raw / "manifest.yaml").read_text())["ignore"] == ["notes/"]
    check = robomill("check", raw)
    assert check.returncode == 0, check.stdout + check.stderr
    work = tmp_path / "work"
    work.mkdir()
    proc = run_snakemake(work, "-j2", "ch2", "--config", f"data={raw}",
                         configfile=REPO / "config.yaml")
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-6000:]
    warnings = [line for line in proc.stderr.splitlines() if "not listed in" in line]
    assert len(warnings) == 1 and "photo.jpg" in warnings[0], warnings
    table = pd.read_csv(work / "results/surface/reference_comparison.csv")
    pq = table[table["parameter"] == "Pq"].set_index("profile")
    assert ((pq["ours"] / pq["file_value"] - 1).abs() < 0.01).all(), pq
    assert table["within_tolerance"].all()
    html = (work / "results/chapters/ch2_surface.html").read_text()
    assert "Against the files&#39; own parameters" in html or \
        "Against the files' own parameters" in html
    assert "CUTOFF 0.25 mm" in html
