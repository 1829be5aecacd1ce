"""The whole workflow on the tiny config: it runs, and a second run does nothing."""

import json
import time

import pytest
from conftest import chapter_outputs, run_snakemake

from robomill.findings import read_findings

pytestmark = pytest.mark.pipeline


def test_all_builds_every_chapter(tiny_run):
    html = tiny_run / "results/chapters/ch0.html"
    assert html.exists() and html.stat().st_size > 10_000
    assert any((tiny_run / "results/figures/ch0").glob("*.png"))
    text = html.read_text()
    assert "Traceback" not in text and "6 cuts" in text


def test_the_thesis_design_keeps_its_tables_and_thesis_remarks(tiny_run):
    """The tiny config is the thesis' study: chapter 0's U-segment plan, Tables 2.1/2.2 in the
    thesis' layout (issue 20: per-cut tables only for other designs), and each chapter's one
    closing comparison with its source, from the comparison rows of its findings.
    Chapters 1-5 are checked on their findings and their structure, not on their sentences."""
    ch0 = chapter_outputs(tiny_run, "ch0")
    plan = read_findings(tiny_run / "results/ingest/findings.yaml").values()
    assert plan["thesis_layout"] and plan["thesis_study"] and plan["single_speed"]
    assert plan["directions"] == ["+Y", "+X", "−Y"] and plan["spindle_rpm"] == 28000.0
    assert plan["ref_robot"] in ch0  # the thesis' cell, in its closing section
    assert "The cut plan: the cuts of every segment" in ch0 and "grouped by what" not in ch0
    nb0 = json.loads((tiny_run / "results/chapters/ch0.ipynb").read_text())
    assert sum(ln.startswith("## Against") for c in nb0["cells"] if c["cell_type"] == "markdown"
               for ln in "".join(c["source"]).splitlines()) == 1
    assert read_findings(tiny_run / "results/surface/findings.yaml").values()["thesis_layout"]
    ch2 = chapter_outputs(tiny_run, "ch2")
    assert "Table 2.1" in ch2 and "Table 2.2" in ch2 and "grouped by what varies" not in ch2
    stages = {"ch1": "calibration", "ch2": "surface",
              "ch3_forces": "forces", "ch3_straightness": "straightness",
              "ch3_modal": "modal", "ch4": "chatter", "ch5": "stiffness",
              "ch6_chatter": "chatter", "ch6_stiffness": "stiffness",
              "ch6_hexapod": "hexapod"}
    # chapters 4 and 5 say what the thesis claims; the rows of the sources they rest on
    # (seeds 001, 002, the lobe benchmark) are in the reference studies 6.1 and 6.2
    rows_elsewhere = {"ch4": "chapter 6.1", "ch5": "chapter 6.2"}
    for name, stage in stages.items():
        found = read_findings(tiny_run / "results" / stage / "findings.yaml")
        assert found.comparisons, name
        nb = json.loads((tiny_run / "results/chapters" / f"{name}.ipynb").read_text())
        headings = [ln for c in nb["cells"] if c["cell_type"] == "markdown"
                    for ln in "".join(c["source"]).splitlines() if ln.startswith("## Against")]
        assert len(headings) == 1, (name, headings)
        text = chapter_outputs(tiny_run, name)
        if name in rows_elsewhere:
            assert "source_value" not in text and rows_elsewhere[name] in text, name
        else:
            assert "source_value" in text, name


def test_no_chapter_prints_a_stray_label(tiny_run):
    """A chapter's cells show figures, tables and prose, never the return value of a
    declaration (``num.table(...)`` gives ``'Table 4.2'``) left as a cell's last line."""
    for path in sorted((tiny_run / "results/chapters").glob("*.ipynb")):
        nb = json.loads(path.read_text())
        stray = ["".join(o["data"].get("text/plain", "")) for c in nb["cells"]
                 for o in c.get("outputs", []) if o.get("output_type") == "execute_result"
                 and "".join(o["data"].get("text/plain", "")).startswith(("'Figure",
                                                                          "'Table"))]
        assert not stray, (path.name, stray)


def test_second_run_is_a_fast_noop(tiny_run):
    t0 = time.monotonic()
    proc = run_snakemake(tiny_run, "-j2", "all", timeout=120)
    elapsed = time.monotonic() - t0
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "Nothing to be done" in proc.stdout + proc.stderr
    assert elapsed < 30, f"no-op run took {elapsed:.1f} s"


def test_raw_folder_of_synthetic_run_matches_manifest(tiny_run):
    from robomill.io.manifest import load_manifest

    load_manifest(tiny_run / "results/synthetic/raw/manifest.yaml").verify_all()


def test_long_jobs_end_their_log_with_what_they_did_and_how_long(tiny_run):
    """Force simulations, lobe maps and sensitivity shards log progress and a final summary."""
    import re

    logs = tiny_run / "results/logs"
    files = (sorted((logs / "forces").glob("synth_*.log"))
             + sorted((logs / "chatter/cases").glob("*.log"))
             + sorted((logs / "hexapod").glob("sensitivity_*.log")))
    assert len(files) >= 3
    for f in files:
        last = f.read_text().strip().splitlines()[-1]
        assert re.search(r" in \d+\.\d s$", last), (f.name, last)


def test_provenance_report(tiny_run):
    """`make report`: Snakemake's report with the chapters' figures and tables by chapter."""
    proc = run_snakemake(tiny_run, "--report", "results/report.html", timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    html = (tiny_run / "results/report.html").read_text(errors="replace")
    for category in ("Chapter 0", "Chapter 2", "Chapter 4", "Book"):
        assert category in html
    assert "table_2_1_waviness_rms.csv" in html and "fig2_" in html
