"""Calibration artefacts of the tiny run: the contract columns, and calibration helps."""

import pandas as pd
import pytest

pytestmark = pytest.mark.pipeline


def test_accuracy_table_contract(tiny_run):
    acc = pd.read_csv(tiny_run / "results/calibration/accuracy.csv")
    assert list(acc.columns) == ["model", "mean_mm", "rms_mm", "p95_mm", "max_mm", "n_points"]
    assert list(acc["model"]) == ["nominal", "geometric", "full"]
    a = acc.set_index("model")
    assert a.loc["full", "rms_mm"] < a.loc["geometric", "rms_mm"] < a.loc["nominal", "rms_mm"]
    assert (a["mean_mm"] <= a["rms_mm"]).all() and (a["p95_mm"] <= a["max_mm"]).all()


def test_model_artefact_has_every_part(tiny_run):
    from robomill.io import open_artefact

    ds = open_artefact(tiny_run / "results/calibration/model.nc")
    for name in ("axis", "centre_mm", "a0_mm", "a_prime_mm", "compliance_rad_per_Nm",
                 "error_sin_rad", "error_cos_rad", "error_poly_rad", "base_compliance_rad_per_Nm"):
        assert name in ds and "units" in ds[name].attrs
    assert ds.sizes["joint"] == 6


def test_chapter_1_rendered(tiny_run):
    html = (tiny_run / "results/chapters/ch1.html").read_text()
    assert "Traceback" not in html and "improvement of" in html
    assert len(list((tiny_run / "results/figures/ch1").glob("*.png"))) >= 5


def test_a_cell_file_without_mass_model_is_calibrated_without_gravity(tiny_config, tmp_path):
    """A raw folder with the C-Track tables and a cell.yaml that states no mass_model (the
    virtual robot does have masses: planted as synth truth the analysis is not told): the
    calibration runs, leaves the gravity term out and says so in model.nc, its log and
    chapter 1."""
    import copy

    import numpy as np
    import yaml
    from conftest import REPO, run_snakemake

    from robomill.io import open_artefact
    from robomill.io.cell import write_cell
    from robomill.io.manifest import build_manifest, write_manifest
    from robomill.synth import ctrack as sc
    from robomill.synth.cell import cell_from_config

    raw = tmp_path / "raw"
    (raw / "ctrack").mkdir(parents=True)
    for table in sc.TABLES:
        sc.write_table(tiny_config, cell_from_config(tiny_config), table,
                       raw / "ctrack" / f"{table}.csv")
    cell = copy.deepcopy(tiny_config["cell"])
    cell["mass_model"] = None
    write_cell(cell, raw / "cell.yaml")
    files = [{"path": f"ctrack/{t}.csv", "kind": "ctrack", "table": t} for t in sc.TABLES]
    files.append({"path": "cell.yaml", "kind": "cell"})
    experiment = {k: tiny_config["experiment"][k]
                  for k in ("spindle_rpm", "flutes", "tool_diameter_mm", "cut_length_mm")}
    write_manifest(build_manifest(experiment, [], files, raw), raw / "manifest.yaml")
    cfg = yaml.safe_load((REPO / ".test" / "config.yaml").read_text())
    cfg["data"] = {"source": "raw", "raw_dir": str(raw)}
    (tmp_path / "config.yaml").write_text(yaml.safe_dump(cfg, sort_keys=False))
    proc = run_snakemake(tmp_path, "-j1", "results/chapters/ch1.html",
                         configfile=tmp_path / "config.yaml")
    assert proc.returncode == 0, proc.stderr[-6000:]
    ds = open_artefact(tmp_path / "results/calibration/model.nc")
    assert ds.attrs["gravity_model"].startswith("none: the cell file states no mass_model")
    assert ds.sizes["mass"] == 0 and np.isnan(float(ds["base_compliance_rad_per_Nm"]))
    assert (ds["tau_home_Nm"].values == 0).all()
    log = (tmp_path / "results/logs/calibration/identify.log").read_text()
    assert "states no mass_model: gravity model none" in log
    acc = pd.read_csv(tmp_path / "results/calibration/accuracy.csv").set_index("model")
    assert acc.loc["full", "rms_mm"] < acc.loc["geometric", "rms_mm"] < acc.loc["nominal",
                                                                                "rms_mm"]
    html = (tmp_path / "results/chapters/ch1.html").read_text()
    assert "Traceback" not in html and "No gravity model." in html
    assert "nan nrad" not in html and "<strong>No gravity model.</strong> none:" in html
