"""Pipeline checks of the modal stage on the tiny configuration (`all`, run once)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

pytestmark = pytest.mark.pipeline


def test_modal_artefacts(tiny_run):
    from robomill.config import load_config
    from robomill.io.impact import read_frf
    from robomill.synth.cell import cell_from_config
    from tests.conftest import REPO

    res = tiny_run / "results" / "modal"
    ds = read_frf(res / "frf.nc")
    assert ds["H"].dims == ("output", "input", "frequency")
    assert np.iscomplexobj(ds["H"].values)
    assert ds["coherence"].attrs["units"] == "1"
    modes = pd.read_csv(res / "modes.csv")
    for col in ("mode", "f_n_hz", "zeta", "k_modal_N_m", "m_modal_kg", "shape_x", "shape_y",
                "shape_z"):
        assert col in modes
    cell = cell_from_config(load_config(REPO / ".test" / "config.yaml"))
    f_true = np.array([m.f_hz for m in cell.modes])
    assert len(modes) == len(f_true)
    assert np.all(np.abs(modes["f_n_hz"].to_numpy() / f_true - 1) < 0.005)
    peaks = pd.read_csv(res / "peak_picking.csv")
    assert peaks["natural_frequency"].any()
    hits = pd.read_csv(res / "hits.csv")
    assert (~hits["accepted"]).sum() >= 1  # the planted double hit (X3)
    assert (tiny_run / "results" / "chapters" / "ch3_3_modal.html").exists()
