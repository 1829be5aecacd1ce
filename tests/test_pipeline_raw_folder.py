"""A raw folder made with the `robomill` command runs through Snakemake with the default
config: `--config data=FOLDER`, a 10 kHz force record (decimation from its rate), numbers
given on the command line."""

from __future__ import annotations

import numpy as np
import pytest
import yaml
from conftest import REPO, run_snakemake, tree_digest

pytestmark = pytest.mark.pipeline

FS_HZ, SPINDLE_RPM, FEED_MM_S, LENGTH_MM = 10_000.0, 6000, 8.0, 40.0


@pytest.fixture(scope="module")
def raw_folder(tmp_path_factory):
    """One cut of a 10 kHz record (6000 rpm, 2 teeth, like a Kistler DynoWare export) with a
    planted 85 Hz depth modulation, time stamps printed with 7 significant digits; manifest
    by `robomill manifest`, completed as a user would, passing `robomill check`."""
    from test_cli import write_csv

    from robomill.cli import main
    from robomill.forces import (
        CuttingCoefficients,
        slot_force_tables,
        slot_forces_band_limited,
    )

    raw = tmp_path_factory.mktemp("raw10k") / "raw"
    spindle_hz = SPINDLE_RPM / 60
    t = np.arange(int(LENGTH_MM / FEED_MM_S * FS_HZ)) / FS_HZ
    K = CuttingCoefficients(796.0, 168.0, 222.0, 27.7, 30.8, 6.7)
    a = 0.25 * (1 + 0.05 * np.sin(2 * np.pi * 85.0 * t))
    F = slot_forces_band_limited(2 * np.pi * spindle_hz * t, FEED_MM_S / (2 * spindle_hz), a,
                                 K, slot_force_tables(2, int(0.45 * FS_HZ / spindle_hz)))
    F = F + np.random.default_rng(0).normal(0, 0.2, F.shape)
    write_csv(raw / "forces/s1_g1_px.csv", {"t_s": t, "Fx_N": F[:, 0], "Fy_N": F[:, 1],
                                           "Fz_N": F[:, 2]}, fmt="%.7g")
    assert main(["manifest", str(raw)]) == 0
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    assert m["files"][0]["fs_hz"] == FS_HZ
    m["experiment"] = {"spindle_rpm": SPINDLE_RPM, "flutes": 2, "tool_diameter_mm": 6.0,
                       "cut_length_mm": LENGTH_MM}
    m["cuts"][0].update(feed_mm_s=FEED_MM_S, depth_mm=0.25)
    (raw / "manifest.yaml").write_text(yaml.safe_dump(m, sort_keys=False))
    assert main(["check", str(raw)]) == 0
    return raw


def test_ten_khz_record_runs_with_the_default_config_and_data_folder(tmp_path, raw_folder):
    from robomill.io import open_artefact

    before = tree_digest(raw_folder)
    proc = run_snakemake(tmp_path, "-j1", "results/forces/cuts/s1_g1_px.nc", "--config",
                         f"data={raw_folder}", configfile=REPO / "config.yaml", timeout=300)
    assert proc.returncode == 0, proc.stderr[-4000:]
    ds = open_artefact(tmp_path / "results/forces/cuts/s1_g1_px.nc")
    assert ds.attrs["decimation"] == 10 and ds.attrs["fs_hz"] == FS_HZ
    assert abs(float(ds["dominant_hz"]) - 85.0) <= FS_HZ / ds.attrs["n_samples"]
    # no line was planted at a spatial frequency: the kinematic band has no peak, which the
    # flag says (the 40 mm record itself resolves 1/L = 0.025 1/mm)
    assert np.isnan(float(ds["kinematic_per_mm"])) and bool(ds["kinematic_below_resolution"])
    assert "decimation 10 (from the rate)" in (
        tmp_path / "results/logs/forces/cut_s1_g1_px.log").read_text()
    assert tree_digest(raw_folder) == before  # the raw folder is only read


def test_numbers_on_the_command_line_reach_the_analysis(tmp_path, raw_folder):
    """`--config forces='{decimation: 10}'` used to fail `'10' is not of type 'integer'`; a
    decimation too high for the record is refused with the fix."""
    from robomill.io import open_artefact

    proc = run_snakemake(tmp_path, "-j1", "results/forces/cuts/s1_g1_px.nc", "--config",
                         f"data={raw_folder}", "forces={decimation: 8, lowband_hz: 2.0e+2}",
                         timeout=300)
    assert proc.returncode == 0, proc.stderr[-4000:]
    ds = open_artefact(tmp_path / "results/forces/cuts/s1_g1_px.nc")
    assert ds.attrs["decimation"] == 8
    assert float(ds["f_low"].max()) <= 200.0
    (tmp_path / "bad").mkdir()
    bad = run_snakemake(tmp_path / "bad", "-j1", "results/forces/cuts/s1_g1_px.nc",
                        "--config", f"data={raw_folder}", "forces={decimation: 25}",
                        timeout=300)
    assert bad.returncode != 0
    log = (tmp_path / "bad/results/logs/forces/cut_s1_g1_px.log").read_text()
    assert "forces.decimation 25 leaves fs 400 Hz of the 10000 Hz record" in log
    assert "decimation <= 19" in log


def test_check_and_manifest_on_the_tiny_runs_raw_folder(tiny_run, tmp_path, capsys):
    """The synthetic raw folder of the tiny run (every kind) passes `robomill check`, and
    `robomill manifest` on a copy without its manifest finds every file again with the same
    kind, metadata and sha256 (aside: the tracker's optional `cut`, absent from its name, and
    the sensors' ranges `range_N`/`range_ms2` of the impact hits, which are the instruments'
    specifications a lab states, and the impact test's TCP point `tcp_mm`, where the lab made
    the test: stated, not something a file holds)."""
    import shutil

    from robomill.cli import main

    raw = tiny_run / "results/synthetic/raw"
    assert main(["check", str(raw)]) == 0
    copy = tmp_path / "raw"
    shutil.copytree(raw, copy)
    (copy / "manifest.yaml").unlink()
    assert main(["manifest", str(copy)]) == 0
    ours = {f["path"]: f for f in yaml.safe_load((copy / "manifest.yaml").read_text())["files"]}
    theirs = {f["path"]: f for f in yaml.safe_load((raw / "manifest.yaml").read_text())["files"]}
    assert set(ours) == set(theirs)
    for path, f in theirs.items():
        stated = {"tracker": {"cut"},
                  "impact": {"range_N", "range_ms2", "tcp_mm"}}.get(f["kind"], set())
        expected = {k: v for k, v in f.items() if k not in stated}
        assert ours[path] == expected, path


def test_another_design_in_the_manifest_reaches_chapters_4_and_5(tiny_run, tmp_path):
    """A raw folder whose manifest states another spindle speed, tool and depth than the
    configuration (the tiny config: 28 000 rpm, 2 flutes, 0.25 mm) gets chapter 4's
    recommendations at its own speed and depth and chapter 5's per-cut stiffness on its own
    slots (the slot floor at its depth): the design comes from the study, not config.yaml."""
    import pandas as pd
    from conftest import raw_copy_of_run

    from robomill.cli import main

    raw = raw_copy_of_run(tiny_run, tmp_path / "raw", config_path=tmp_path / "config.yaml")
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    m["experiment"].update(spindle_rpm=24000, flutes=3)
    for c in m["cuts"]:
        c["depth_mm"] = 1.5
    (raw / "manifest.yaml").write_text(yaml.safe_dump(m, sort_keys=False))
    assert main(["check", str(raw)]) == 0
    targets = ["results/chatter/recommendations.csv", "results/stiffness/thesis_slots.csv"]
    proc = run_snakemake(tmp_path, "-j2", *targets, configfile=tmp_path / "config.yaml")
    assert proc.returncode == 0, proc.stderr[-4000:]
    rec = pd.read_csv(tmp_path / targets[0])
    thesis = rec[rec["kind"] == "thesis"]
    assert set(thesis["spindle_rpm"]) == {24000} and set(thesis["axial_depth_mm"]) == {1.5}
    ours = pd.read_csv(tmp_path / targets[1])
    theirs = pd.read_csv(tiny_run / targets[1])
    assert set(ours["cut"]) == {c["id"] for c in m["cuts"]}
    key = ["cut", "model"]
    both = ours.merge(theirs, on=key, suffixes=("", "_config"))
    assert len(both) == len(ours)
    # a slot floor 1.25 mm lower: another pose, another stiffness (same cuts otherwise)
    assert not np.allclose(both["k_normal_N_m"], both["k_normal_N_m_config"], rtol=1e-6)
