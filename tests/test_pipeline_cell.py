"""The cell file in the pipeline: a raw folder without one (from before cell files) is
analysed with the configuration's cell; tracker points in the tracker's own frame stop with a
RawDataError naming the file and base_from_instrument, and registering the frame in
cell.yaml gives back the base-frame result."""

import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from conftest import REPO, run_snakemake

from robomill.io.manifest import build_manifest, load_manifest, write_manifest

pytestmark = pytest.mark.pipeline

ROT = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # tracker turned by 90°
SHIFT = np.array([2500.0, -800.0, 150.0])  # and 2.6 m away: p_base = ROT p + SHIFT


def tracker_folder(run_dir: Path, dst: Path, *, cell: str) -> Path:
    """Tracker runs of a finished run in a raw folder with the tiny config pointing at it:
    ``cell`` = ``none`` (no cell file), ``base`` (the run's cell file) or ``registered``
    (points in the tracker's frame, the cell file registering it)."""
    src = run_dir / "results/synthetic/raw"
    m = load_manifest(src / "manifest.yaml")
    raw = dst / "raw"
    files = [f for f in m.files if f["kind"] == "tracker"]
    for f in files:
        (raw / f["path"]).parent.mkdir(parents=True, exist_ok=True)
        if cell == "base" or cell == "none":
            shutil.copyfile(src / f["path"], raw / f["path"])
        else:  # the tracker's own frame: p = ROTᵀ (p_base − SHIFT)
            df = pd.read_csv(src / f["path"])
            xyz = ["x_mm", "y_mm", "z_mm"]
            df[xyz] = (df[xyz].to_numpy() - SHIFT) @ ROT
            df.to_csv(raw / f["path"], index=False, float_format="%.6f")
    meta = [{k: v for k, v in f.items() if k != "sha256"} for f in files]
    if cell != "none":
        data = yaml.safe_load((src / "cell.yaml").read_text())
        if cell == "registered":
            data["base_from_instrument"] = {"tracker": {"rotation": ROT.tolist(),
                                                        "translation_mm": SHIFT.tolist()}}
        (raw / "cell.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
        meta.append({"path": "cell.yaml", "kind": "cell"})
    write_manifest(build_manifest(m.experiment, m.cuts, meta, raw), raw / "manifest.yaml")
    cfg = yaml.safe_load((REPO / ".test" / "config.yaml").read_text())
    cfg["data"] = {"source": "raw", "raw_dir": str(raw)}
    (dst / "config.yaml").write_text(yaml.safe_dump(cfg, sort_keys=False))
    return dst


def _peaks(work: Path) -> pd.DataFrame:
    return pd.read_csv(work / "results/straightness/peaks.csv")


def test_a_raw_folder_without_a_cell_file_uses_the_configured_cell(tiny_run, tmp_path):
    work = tracker_folder(tiny_run, tmp_path / "none", cell="none")
    proc = run_snakemake(work, "-j2", "results/straightness/peaks.csv",
                         configfile=work / "config.yaml")
    assert proc.returncode == 0, proc.stderr[-4000:]
    assert (work / "results/ingest/cell.yaml").exists()
    mine, ref = _peaks(work), _peaks(tiny_run)
    pd.testing.assert_frame_equal(mine[ref.columns], ref)


def test_tracker_points_in_their_own_frame_need_base_from_instrument(tiny_run, tmp_path):
    work = tracker_folder(tiny_run, tmp_path / "registered", cell="registered")
    data = yaml.safe_load((work / "raw/cell.yaml").read_text())
    del data["base_from_instrument"]  # first without the registration
    (work / "raw/cell.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    m = load_manifest(work / "raw/manifest.yaml")
    write_manifest(build_manifest(m.experiment, m.cuts, [
        {k: v for k, v in f.items() if k != "sha256"} for f in m.files], work / "raw"),
        work / "raw/manifest.yaml")
    proc = run_snakemake(work, "-j1", "results/straightness/peaks.csv",
                         configfile=work / "config.yaml")
    assert proc.returncode != 0
    out = proc.stdout + proc.stderr
    assert "RawDataError" in out and "tracker/px_f2.csv" in out
    assert "base_from_instrument.tracker" in out and "did not converge" not in out
    # registered: the same peaks as in the robot's base frame
    work = tracker_folder(tiny_run, tmp_path / "ok", cell="registered")
    proc = run_snakemake(work, "-j2", "results/straightness/peaks.csv",
                         configfile=work / "config.yaml")
    assert proc.returncode == 0, proc.stderr[-4000:]
    mine, ref = _peaks(work), _peaks(tiny_run)
    assert list(mine["stage"].fillna("")) == list(ref["stage"].fillna(""))
    np.testing.assert_allclose(mine["f_spatial_per_mm"], ref["f_spatial_per_mm"], rtol=1e-4)
