"""Pipeline checks of the stiffness stage on the tiny run (artefact names and contents)."""

import numpy as np
import pandas as pd
import pytest

from robomill.io import open_artefact

pytestmark = pytest.mark.pipeline


def test_joint_stiffness_contract_and_truth(tiny_run):
    truth = open_artefact(tiny_run / "results/synthetic/truth.nc")
    for robot in ("kr360", "irb1600"):
        js = pd.read_csv(tiny_run / f"results/stiffness/{robot}/joint_stiffness.csv")
        assert list(js.columns) == ["joint", "k_Nm_rad", "ci95_low_Nm_rad",
                                    "ci95_high_Nm_rad", "observable"]
        k = truth["stiffness_k_Nm_rad"].sel(stiffness_robot=robot).values
        obs = js["observable"].to_numpy(bool)
        rel = np.abs(js["k_Nm_rad"].to_numpy()[obs] / k[obs] - 1)
        assert rel.max() < 0.3
        val = pd.read_csv(tiny_run / f"results/stiffness/{robot}/validation.csv")
        assert len(val) and np.abs(val["error_pct"]).max() < 20
    irb = pd.read_csv(tiny_run / "results/stiffness/irb1600/joint_stiffness.csv")
    assert not irb["observable"].iloc[5]  # tool on the flange axis: joint 6 unobservable


def test_maps_optimal_beamframe(tiny_run):
    maps = open_artefact(tiny_run / "results/stiffness/maps.nc")
    assert {"k_N_m", "S_N_m", "q_deg", "reachable"} <= set(maps.data_vars)
    assert maps["reachable"].any()
    opt = pd.read_csv(tiny_run / "results/stiffness/optimal_poses.csv")
    for _, g in opt.groupby("height_mm"):
        best = g[g["pose"] == "optimal"].iloc[0]
        assert best["S_N_m"] >= g["S_N_m"].max() - 1e-6
    bf = open_artefact(tiny_run / "results/stiffness/beamframe.nc")
    assert bf["K0"].shape == (42, 42)
    assert float(bf["cantilever_tip_m"]) == pytest.approx(float(bf["cantilever_closed_form_m"]))
    slots = pd.read_csv(tiny_run / "results/stiffness/thesis_slots.csv")
    assert set(slots["model"]) == {"joint", "beam", "combined"}
    assert (slots[["k_feed_N_m", "k_normal_N_m", "k_axial_N_m"]] > 0).all().all()
