"""The whole workflow on the tiny config: it runs, and a second run does nothing."""

import time

import pytest
from conftest import chapter_outputs, run_snakemake

from robomill.findings import read_findings

pytestmark = pytest.mark.pipeline


def test_all_builds_every_chapter(tiny_run):
    html = tiny_run / "results/chapters/ch0_experiment.html"
    assert html.exists() and html.stat().st_size > 10_000
    assert any((tiny_run / "results/figures/ch0").glob("*.png"))
    text = html.read_text()
    assert "Traceback" not in text and "6 cuts" in text


def test_the_thesis_design_keeps_its_tables_and_thesis_remarks(tiny_run):
    """The tiny config is the thesis' study: Tables 2.1/2.2 beside the thesis', the U-segment
    plan and the "thesis: ..." remarks stay (issue 20: per-cut tables only for other designs)."""
    ch0 = chapter_outputs(tiny_run, "ch0_experiment")
    assert "Three sets of five U-shaped segments" in ch0 and "+Y, +X, −Y" in ch0
    assert "(thesis: 1.07 µm at 1 mm/s, 10.7 µm at 10 mm/s)" in ch0
    assert "The cut plan: the cuts of every segment" in ch0 and "grouped by what" not in ch0
    ch2 = chapter_outputs(tiny_run, "ch2_surface")
    assert "beside the thesis' Table 2.1" in ch2 and "beside the thesis' Table 2.2" in ch2
    assert "thesis: X smallest, +Y largest" in ch2 and "within a factor 1.5" in ch2
    assert "grouped by what varies" not in ch2
    ch5 = chapter_outputs(tiny_run, "ch5_stiffness")
    assert "stiffness along the slot directions beside the mean waviness of Table 2.1" in ch5
    ch1 = chapter_outputs(tiny_run, "ch1_calibration")
    assert "the thesis says it 'can be a few millimetres'" in ch1
    assert "The thesis prints no accuracy figure" in ch1
    # chapters 3.1, 3.2, 3.3 and 4 tell the thesis comparison in one closing section, from
    # the comparison rows of their findings (issue 30): the section and its rows are there
    stages = {"ch3_1_forces": "forces", "ch3_2_straightness": "straightness",
              "ch3_3_modal": "modal", "ch4_chatter": "chatter"}
    for name, stage in stages.items():
        found = read_findings(tiny_run / "results" / stage / "findings.yaml")
        assert found.comparisons, name
        text = chapter_outputs(tiny_run, name)
        assert "The thesis" in text and "source_value" in text, name


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
