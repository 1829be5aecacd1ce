"""Chapter 4 artefacts of the tiny run."""

import numpy as np
import pandas as pd
import pytest

from robomill.io import open_artefact

pytestmark = pytest.mark.pipeline


def test_case_artefact(tiny_run):
    ds = open_artefact(tiny_run / "results/chatter/cases/insperger2004_down005.nc")
    assert ds["a_crit_mm"].dims == ("solver", "spindle_rpm")
    assert list(ds.solver.values) == ["zoa", "sdm"]
    assert ds["a_crit_mm"].attrs["units"] == "mm"
    assert ds.attrs["case_teeth"] == 2 and ds.attrs["case_milling"] == "down"
    assert np.isfinite(ds["a_crit_mm"].sel(solver="sdm")).any()


def test_simulation_artefact(tiny_run):
    ds = open_artefact(tiny_run / "results/chatter/simulation.nc")
    assert set(ds.run.values) == {"point1", "point2", "point2_adaptive"}
    assert ds.attrs["point1_depth_mm"] < ds.attrs["a_boundary_at_n_mm"] < \
        ds.attrs["point2_depth_mm"]
    assert ds.attrs["adaptation_lowered_fraction"] <= 0.02 + 1e-12
    assert ds["onset_unstable"].values.tolist() == (ds["onset_depth_fraction"] > 1).values.tolist()
    assert np.size(ds.attrs["detections_point1_s"]) == 0  # the stable point raises no alarm
    grows = ds["onset_depth_fraction"].values > 1
    assert (ds["onset_growth_rate_simulated_1_s"].values[grows] > 0).all()
    assert (ds["onset_growth_rate_sdm_1_s"].values[grows] > 0).all()
    assert (ds["onset_growth_rate_sdm_1_s"].values[~grows] < 0).all()
    assert ds.attrs["indicator_final_point1_N"] < ds.attrs["indicator_final_point2_N"]


def test_thesis_artefacts(tiny_run):
    lobes = open_artefact(tiny_run / "results/chatter/lobes.nc")
    assert list(lobes.direction.values) == ["px", "py", "my"]
    rec = pd.read_csv(tiny_run / "results/chatter/recommendations.csv")
    assert {"direction", "spindle_rpm", "axial_depth_mm", "stability_margin"} <= set(rec.columns)
    assert set(rec.direction) == {"px", "py", "my"}
    assert (rec.loc[rec.kind == "recommended", "stability_margin"] > 0).all()
    assert (tiny_run / "results/chapters/ch4_chatter.html").exists()
