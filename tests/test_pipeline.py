"""The whole workflow on the tiny config: it runs, and a second run does nothing."""

import time

import pytest
from conftest import run_snakemake

pytestmark = pytest.mark.pipeline


def test_all_builds_every_chapter(tiny_run):
    html = tiny_run / "results/chapters/ch0_experiment.html"
    assert html.exists() and html.stat().st_size > 10_000
    assert any((tiny_run / "results/figures/ch0").glob("*.png"))
    text = html.read_text()
    assert "Traceback" not in text and "6 cuts" in text


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
