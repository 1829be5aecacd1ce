"""Straightness stage on the tiny run: contract columns, attribution vs planted truth."""

import numpy as np
import pandas as pd
import pytest

pytestmark = pytest.mark.pipeline

CONTRACT = ["direction", "feed_mm_s", "f_spatial_per_mm", "amplitude_um", "mechanism", "joint",
            "stage"]


def test_peaks_follow_the_contract(tiny_run):
    peaks = pd.read_csv(tiny_run / "results/straightness/peaks.csv")
    assert list(peaks.columns[:7]) == CONTRACT
    assert set(peaks["mechanism"]) <= {"gear", "temporal", "spatial", "unclassified"}
    gear = peaks[peaks["mechanism"] == "gear"]
    assert len(gear) > 0 and gear["joint"].between(1, 6).all()
    # the 13 Hz servo ripple is found at every run, as temporal
    temporal = peaks[peaks["mechanism"] == "temporal"]
    runs = peaks[["direction", "feed_mm_s"]].drop_duplicates()
    assert len(temporal) == len(runs)
    np.testing.assert_allclose(temporal["f_temporal_hz"], 13.0, atol=0.1)


def test_every_planted_gear_above_noise_is_found_and_nothing_else(tiny_run):
    check = pd.read_csv(tiny_run / "results/straightness/truth_check.csv")
    above = check[check["class"] == "above_noise"]
    assert len(above) > 0
    assert (above["found"] | above["merged"]).all(), above
    assert not check["false_attribution"].any()


def test_gear_frequencies_and_profiles(tiny_run):
    from robomill.io import open_artefact

    gears = pd.read_csv(tiny_run / "results/straightness/gears.csv")
    assert {"direction", "feed_mm_s", "joint", "stage", "order", "f_spatial_per_mm"} <= set(
        gears.columns)
    prof = open_artefact(tiny_run / "results/straightness/profiles.nc")
    assert prof["deviation_um"].attrs["units"] == "um"
    assert prof.sizes["run"] == len(gears[["direction", "feed_mm_s"]].drop_duplicates())
    np.testing.assert_allclose(prof["speed_mm_s"], prof["feed_mm_s"], rtol=0.01)
