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
    html = (tiny_run / "results/chapters/ch1_calibration.html").read_text()
    assert "Traceback" not in html and "improvement of" in html
    assert len(list((tiny_run / "results/figures/ch1").glob("*.png"))) >= 5
