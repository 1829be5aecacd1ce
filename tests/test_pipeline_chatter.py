"""Chapter 4 artefacts of the tiny run."""

import numpy as np
import pandas as pd
import pytest

from robomill.io import open_artefact

pytestmark = pytest.mark.pipeline


def test_case_artefact(tiny_run):
    ds = open_artefact(tiny_run / "results/chatter/cases/insperger2004_down005.nc")
    assert ds["a_crit_mm"].dims == ("solver", "spindle_rpm")
    assert list(ds.solver.values) == ["zoa", "sem"]
    assert ds["a_crit_mm"].attrs["units"] == "mm"
    assert ds.attrs["case_teeth"] == 2 and ds.attrs["case_milling"] == "down"
    a = ds["a_crit_mm"].sel(solver="sem")
    assert np.isfinite(a).any()
    # every converged depth carries its error, within the configured accuracy
    err = ds["a_crit_error_mm"]
    assert err.dims == ("spindle_rpm",) and err.attrs["units"] == "mm"
    fin = np.isfinite(a.values)
    np.testing.assert_array_equal(np.isfinite(err.values), fin)
    assert (err.values[fin] <= ds.attrs["accuracy"] * a.values[fin]).all()
    assert set(ds["bifurcation"].values[fin]) <= {"hopf", "flip", "fold"}


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
    # the SDM diagram's discretization error, against the converged spectral element
    err = ds["seed_a_crit_error_mm"].values
    a_sdm = ds["seed_a_crit_mm"].sel(solver="sdm").values
    fin = np.isfinite(a_sdm) & np.isfinite(ds["seed_a_crit_sem_mm"].values)
    assert fin.any() and (err[fin] >= 0).all()
    np.testing.assert_allclose(np.abs(a_sdm - ds["seed_a_crit_sem_mm"].values)[fin],
                               err[fin], atol=ds.attrs["accuracy"] * a_sdm[fin].max())


def test_thesis_artefacts(tiny_run):
    lobes = open_artefact(tiny_run / "results/chatter/lobes.nc")
    assert list(lobes.direction.values) == ["px", "py", "my"]
    assert lobes["a_crit_error_mm"].dims == ("direction", "spindle_rpm")
    assert lobes.attrs["worst_relative_error"] <= lobes.attrs["accuracy"]
    rec = pd.read_csv(tiny_run / "results/chatter/recommendations.csv")
    assert {"direction", "spindle_rpm", "axial_depth_mm", "stability_margin", "a_crit_error_mm",
            "a_limit_error_mm", "stability_margin_min"} <= set(rec.columns)
    assert set(rec.direction) == {"px", "py", "my"}
    best = rec[rec.kind == "recommended"]
    assert (best["stability_margin_min"] > 0).all()
    # the safety fraction on top of the error (tiny config: the default 0.2; CSV: 6 digits)
    np.testing.assert_allclose(best["axial_depth_mm"],
                               0.8 * (best["a_limit_mm"] - best["a_limit_error_mm"]), rtol=1e-5)
    sem = rec[rec.solver == "sem"]
    assert (sem["a_crit_error_mm"] > 0).all()
    # the limit is the regenerative depth; the delay-free mode-coupling depth, far below it,
    # is reported beside it and limits nothing
    np.testing.assert_array_equal(rec["a_limit_mm"], rec["a_crit_mm"])
    assert (rec["limited_by"] == "regenerative").all()
    assert (rec["a_mode_coupling_mm"] < rec["a_crit_mm"]).all()
    assert (tiny_run / "results/chapters/ch4.html").exists()
