"""Forces stage on the tiny run: artefacts, peaks at the cell's modes, coefficients."""

import numpy as np
import pandas as pd
import pytest

pytestmark = pytest.mark.pipeline


def test_force_artefacts(tiny_run):
    from robomill.io import open_artefact

    peaks = pd.read_csv(tiny_run / "results/forces/peaks.csv")
    assert list(peaks.columns) == ["cut", "dominant_hz", "dominant_power", "kinematic_per_mm",
                                   "kinematic_resolution_per_mm", "kinematic_below_resolution",
                                   "dominant_below_resolution"]
    assert len(peaks) == 6
    # the tiny study's 4 mm records (synth.dynamometer.record_length_mm): 1/L = 0.25 1/mm, a
    # kinematic peak near 0.5 1/mm has 2 periods in the record: every cut is flagged; the
    # dominant peak (~70 Hz over 0.5-2 s: 35-140 periods) is resolved
    np.testing.assert_allclose(peaks["kinematic_resolution_per_mm"], 1 / 4.0, rtol=1e-3)
    assert peaks["kinematic_below_resolution"].all()
    assert not peaks["dominant_below_resolution"].any()
    assert peaks["dominant_hz"].between(60, 120).all()
    sp = open_artefact(tiny_run / "results/forces/spectra.nc")
    for v in list(sp.data_vars) + list(sp.coords):
        assert "units" in sp[v].attrs and "long_name" in sp[v].attrs, v
    assert set(sp["cut"].values) == set(peaks["cut"])
    assert (tiny_run / "results/chapters/ch3_forces.html").exists()


def test_identified_coefficients_near_planted(tiny_run):
    from robomill.io import open_artefact

    coef = pd.read_csv(tiny_run / "results/forces/cutting_coefficients.csv")
    assert list(coef.columns) == ["name", "value", "ci_low", "ci_high", "unit", "negative",
                                  "fit_residual_rms_N", "fit_signal_rms_N",
                                  "residual_exceeds_signal", "physical"]
    # planted positive coefficients, recovered within 5 %: every row physical
    assert coef["physical"].all() and not coef["negative"].any()
    truth = open_artefact(tiny_run / "results/synthetic/truth.nc")
    for row in coef.itertuples():
        unit = "N_mm2" if row.unit == "N/mm^2" else "N_mm"
        planted = float(truth[f"cutting_{row.name}_{unit}"])
        assert row.ci_low <= row.value <= row.ci_high
        assert abs(row.value / planted - 1) < 0.05, (row.name, row.value, planted)
    assert np.isfinite(coef["value"]).all()
