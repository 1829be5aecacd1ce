"""Issue 21, "Done means": a folder of instrument exports becomes chapters with the four
commands a user types, and the default ``config.yaml`` unedited.

The files: the real UFF 58 FRFs of a roving-hammer test (``tests/data/real/uff``, pyuff), the
real confocal X3P scan (``tests/data/real/x3p``, x3ptools, one row as the cut's profile) and,
for formats with no public export (``tests/data/real/*/SOURCE.md``), the constructed FARO
tracker export (``tests/data/constructed/faro``) and DynoWare force exports: the constructed
``tests/data/constructed/dynoware/slot_s1_g1_px.txt`` and two copies of it with the forces
scaled (1.5x, 2x) written here for the cuts at the higher feeds (the mechanistic calibration
of chapter 3.1 needs three cuts at two or more feeds).

Steps, as in docs/own-data.md "The four commands": ``robomill init``; ``robomill import`` for each
export (the console script, in a subprocess); ``robomill manifest``; the keys it lists as not
inferred written as a user would (spindle speed, flutes, feed and depth of each cut) and the
tracker frame registered in ``cell.yaml``; ``robomill check`` exits 0; then
``snakemake -j2 all --config data=<folder>`` with the repository's ``config.yaml``: planned
(``-n``) in full, and run for the study's chapters it plans (the reference studies' chapters
read no raw file; the tiny run and ``make all`` build them).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from conftest import NO_BOOK_PDF, REPO, run_snakemake

from robomill.registry import chapters

pytestmark = [pytest.mark.pipeline, pytest.mark.whole_study]

DATA = REPO / "tests" / "data"
ROBOMILL = Path(sys.executable).parent / "robomill"
FEEDS = {"s1_g1_px": 1.0, "s1_g2_px": 2.0, "s1_g3_px": 3.0}  # mm/s at 6000 rpm, 2 teeth


def robomill(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([str(ROBOMILL), *map(str, args)], capture_output=True, text=True,
                          timeout=300)


def _scaled_dynoware(src: Path, dst: Path, factor: float) -> Path:
    """A copy of a DynoWare ASCII export with every force sample times ``factor``."""
    lines = src.read_bytes().decode().split("\r\n")
    start = lines.index("s\tN\tN\tN") + 1
    out = lines[:start]
    for line in lines[start:]:
        if not line.strip():
            out.append(line)
            continue
        t, *f = line.split("\t")
        out.append("\t".join([t, *(f"{float(v) * factor:.3f}" for v in f)]))
    dst.write_bytes("\r\n".join(out).encode())
    return dst


@pytest.fixture(scope="module")
def real_study(tmp_path_factory):
    base = tmp_path_factory.mktemp("real_study")
    raw, exports = base / "raw", base / "exports"
    exports.mkdir()
    steps = [("init", raw)]
    dyno = DATA / "constructed/dynoware/slot_s1_g1_px.txt"
    for cut, factor in zip(FEEDS, (1.0, 1.5, 2.0), strict=True):
        src = dyno if factor == 1.0 else _scaled_dynoware(dyno, exports / f"{cut}.txt", factor)
        steps.append(("import", "dynoware", src, "--to", raw, "--cut", cut))
    steps += [
        ("import", "uff", DATA / "real/uff/pyuff_measurement_roving_hammer.uff", "--to", raw),
        ("import", "x3p", DATA / "real/x3p/sample-land_rows4-7.x3p", "--to", raw,
         "--cut", "s1_g1_px", "--row", "2", "--dropouts", "longest"),
        ("import", "faro", DATA / "constructed/faro/px_f1.csv", "--to", raw, "--fs-hz", "815",
         "--direction", "px", "--feed-mm-s", "1"),
        ("manifest", raw),
    ]
    out = {}
    for step in steps:
        proc = robomill(*step)
        assert proc.returncode == 0, (step, proc.stdout, proc.stderr)
        out[step[0] if step[0] != "import" else f"import {step[1]}"] = proc.stdout
    # what `robomill manifest` could not infer, written as a user would
    todo = out["manifest"]
    for key in ("spindle_rpm", "flutes", "tool_diameter_mm"):
        assert f"experiment.{key} not inferred" in todo
    # asked only for the chapters this folder feeds: no robot or stiffness files, so no
    # chapter reads the cut length (issue 32.3)
    assert "cut_length_mm" not in todo
    assert "native" not in todo  # the imported UFF is a contract file, listed as impact
    text = (raw / "manifest.yaml").read_text()
    comments = "".join(line for line in text.splitlines(True) if line.startswith("#"))
    m = yaml.safe_load(text)
    m["experiment"].update(spindle_rpm=6000, flutes=2, tool_diameter_mm=6.0,
                           cut_length_mm=40.0)
    assert sorted(c["id"] for c in m["cuts"]) == sorted(FEEDS)
    for c in m["cuts"]:
        c.update(feed_mm_s=FEEDS[c["id"]], depth_mm=0.25)
    (raw / "manifest.yaml").write_text(comments + yaml.safe_dump(m, sort_keys=False))
    # the tracker's frame: the export's points sit 1.5 m from the robot base
    cell = (raw / "cell.yaml").read_text()
    (raw / "cell.yaml").write_text(cell + "base_from_instrument:\n  tracker: {rotation: "
                                   "[[1, 0, 0], [0, 1, 0], [0, 0, 1]], translation_mm: "
                                   "[-250.0, -1200.0, 0.0]}\n")
    assert "could not infer" not in robomill("manifest", raw).stdout  # sha256 of the edits
    check = robomill("check", raw)
    assert check.returncode == 0, check.stdout + check.stderr
    work = base / "work"
    work.mkdir()
    # what `all` builds from this folder (a dry run), then those of its chapters that read
    # the folder: the reference studies' chapters (part "reference" of the registry) read no
    # raw file and, at the default config's resolution, would be half of the run's work
    # (the tiny run and `make all` build them)
    dry = run_snakemake(work, "-n", "all", "--config", f"data={raw}", NO_BOOK_PDF,
                        configfile=REPO / "config.yaml")
    assert dry.returncode == 0, dry.stdout[-3000:] + dry.stderr[-8000:]
    in_all = [c for c in chapters() if c.in_all and c.page in dry.stdout]
    assert {c.part for c in in_all} == {"study", "reference"}, [c.id for c in in_all]
    study = [c.id for c in in_all if c.part == "study"]
    proc = run_snakemake(work, "-j2", *study, "--config", f"data={raw}",
                         configfile=REPO / "config.yaml")
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-8000:]
    return work, dry, proc


def test_real_exports_become_chapters_with_the_default_config(real_study):
    work, dry, _ = real_study
    built = sorted(p.stem for p in (work / "results/chapters").glob("*.html"))
    for ch in ("ch0", "ch2", "ch3_forces", "ch3_straightness",
               "ch3_modal"):
        assert ch in built
    for ch, line in (("ch1", "chapter 1: no ctrack files in manifest.yaml"),
                     ("ch5", "chapter 5: no robot files and no stiffness files in "
                      "manifest.yaml")):
        assert dry.stderr.count(line) == 1, line  # partial study: one line each
        assert f"results/chapters/{ch}.html" not in dry.stdout  # and `all` leaves it out
    assert "ch1" not in built and "ch5" not in built


def test_real_uff_modes_and_band_from_the_data(real_study):
    """The free-free beam of the pyuff export: modes near 51 and 142 Hz (SOURCE.md), band
    from the data (no band set in config.yaml or in the manifest)."""
    import xarray as xr

    work, *_ = real_study
    modes = pd.read_csv(work / "results/modal/modes.csv")
    f = modes["f_n_hz"].to_numpy()
    for f_beam in (142.0, 279.0):
        assert np.min(np.abs(f - f_beam)) < 0.03 * f_beam, (f_beam, f)
    with xr.open_dataset(work / "results/modal/frf_synth.nc", engine="h5netcdf") as s:
        assert s.attrs["band_source"] == "data" and s.attrs["band_flag"] == ""


def test_forces_rate_and_decimation_from_the_record(real_study):
    work, *_ = real_study
    log = (work / "results/logs/forces/cut_s1_g1_px.log").read_text()
    assert "2000 samples at 10000 Hz, decimation 10 (from the rate)" in log
    coef = pd.read_csv(work / "results/forces/cutting_coefficients.csv")
    assert np.isfinite(coef["value"]).all()


def test_x3p_profile_keeps_its_sampling(real_study):
    """The Sensofar scan's 2.58 µm spacing survives import and the surface chapter's input."""
    work, *_ = real_study
    raw_profile = pd.read_csv(work.parent / "raw/profiles/s1_g1_px.csv")
    dx_um = np.diff(raw_profile["x_mm"].to_numpy()) * 1e3
    assert np.allclose(dx_um, 2.58, atol=0.01)


def test_an_impact_test_alone_gives_the_six_beam_modes(tmp_path):
    """Issue 32, "Done means": the real roving-hammer UFF alone (no cuts, no spindle speed,
    flutes, tool or cut length written anywhere) through init, import, manifest, check and
    ``snakemake ch3_modal`` with the default config: the six bending modes of the free-free
    beam listed in tests/data/real/uff/SOURCE.md (51, 142, 279, 460, 687, 959 Hz)."""
    raw = tmp_path / "raw"
    uff = DATA / "real" / "uff" / "pyuff_measurement_roving_hammer.uff"
    for args in (("init", raw), ("import", "uff", uff, "--to", raw), ("manifest", raw),
                 ("check", raw)):
        proc = robomill(*args)
        assert proc.returncode == 0, (args, proc.stdout, proc.stderr)
    manifest = yaml.safe_load((raw / "manifest.yaml").read_text())
    assert manifest["cuts"] == [] and not any(manifest["experiment"].values())
    work = tmp_path / "work"
    work.mkdir()
    proc = run_snakemake(work, "-j2", "ch3_modal", "--config", f"data={raw}",
                         configfile=REPO / "config.yaml")
    assert proc.returncode == 0, proc.stderr[-3000:]
    f = np.sort(pd.read_csv(work / "results/modal/modes.csv")["f_n_hz"].to_numpy())
    beam = np.array([51.0, 142.0, 279.0, 460.0, 687.0, 959.0])
    assert f.size == beam.size, f
    assert np.all(np.abs(f / beam - 1.0) < 0.02), f
