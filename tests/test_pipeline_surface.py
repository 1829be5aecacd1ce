"""Chapter 2 on the tiny run: artefacts exist with the contract's columns, the planted RMS is
recovered, the chapter renders."""

import numpy as np
import pandas as pd
import pytest

pytestmark = pytest.mark.pipeline


def test_surface_tables_and_contract_columns(tiny_run):
    res = tiny_run / "results/surface"
    t21 = pd.read_csv(res / "table_2_1_waviness_rms.csv", index_col="segment")
    t22 = pd.read_csv(res / "table_2_2_roughness_rms.csv", index_col="segment")
    assert list(t21.columns) == ["s1_px", "s1_py", "s1_my"] == list(t22.columns)
    assert list(t21.index) == [1, 2]
    assert (t21.values > 0).all() and (t22.values > 0).all()
    met = pd.read_csv(res / "metrics.csv")
    assert list(met.columns[:6]) == ["cut", "Wt_um", "Wq_um", "Rq_um", "Ra_um", "Rz_um"]
    assert len(met) == 6
    pk = pd.read_csv(res / "peaks.csv")
    assert list(pk.columns[:5]) == ["cut", "f_spatial_per_mm", "f_temporal_hz",
                                    "amplitude_um", "mechanism"]
    assert set(pk.mechanism) <= {"kinematic", "dynamic", "unclassified"}
    assert np.allclose(pk.f_temporal_hz, pk.f_spatial_per_mm * pk.feed_mm_s)


def test_surface_recovers_planted_rms(tiny_run):
    rec = pd.read_csv(tiny_run / "results/surface/recovery.csv")
    assert len(rec) == 6
    assert ((rec.waviness_ratio - 1).abs() < 0.10).all(), rec
    assert ((rec.roughness_ratio - 1).abs() < 0.10).all(), rec


def test_surface_spectra_parseval(tiny_run):
    from robomill.io import open_artefact

    spec = open_artefact(tiny_run / "results/surface/spectra.nc")
    prof = open_artefact(tiny_run / "results/surface/profiles.nc")
    for cut in spec.cut.values:
        z = prof.z.sel(cut=cut).values.astype(float)
        assert np.sqrt(float(spec.power.sel(cut=cut).sum())) == pytest.approx(
            np.sqrt(np.mean(z**2)), rel=1e-4)  # profiles stored as float32


def test_chapter_2_renders(tiny_run):
    html = tiny_run / "results/chapters/ch2.html"
    assert html.exists()
    text = html.read_text()
    assert "Traceback" not in text and "Table 2.1" in text
    assert any((tiny_run / "results/figures/ch2").glob("fig2_17_*.png"))
