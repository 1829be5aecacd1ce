"""Pipeline checks of the modal stage on the tiny configuration (`all`, run once)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

pytestmark = pytest.mark.pipeline
REPO = Path(__file__).resolve().parents[1]


def test_modal_artefacts(tiny_run):
    import pyuff

    from robomill.config import load_config
    from robomill.io.impact import read_frf, read_frf_uff
    from robomill.synth.cell import cell_from_config

    res = tiny_run / "results" / "modal"
    ds = read_frf(res / "frf.nc")
    assert ds["H"].dims == ("output", "input", "frequency")
    assert np.iscomplexobj(ds["H"].values)
    assert ds["coherence"].attrs["units"] == "1"
    assert ds["output_node"].values.tolist() == [1, 1, 1]
    assert ds["input_dir"].values.tolist() == [1, 2, 3]
    assert "force_spectrum" in ds
    modes = pd.read_csv(res / "modes.csv")
    for col in ("mode", "f_n_hz", "zeta", "k_modal_N_m", "m_modal_kg", "shape_x", "shape_y",
                "shape_z", "driving_point", "coherence", "physical", "flags"):
        assert col in modes
    cell = cell_from_config(load_config(REPO / ".test" / "config.yaml"))
    f_true = np.array([m.f_hz for m in cell.modes])
    assert len(modes) == len(f_true)
    assert np.all(np.abs(modes["f_n_hz"].to_numpy() / f_true - 1) < 0.005)
    assert modes["physical"].all()
    peaks = pd.read_csv(res / "peak_picking.csv")
    assert peaks["natural_frequency"].any()
    hits = pd.read_csv(res / "hits.csv")
    assert (~hits["accepted"]).sum() >= 1  # the planted double hit (X3)
    # mode shapes, MAC, UFF 55 + 15 read back by pyuff, FRFs as UFF 58 with node numbers
    shapes = pd.read_csv(res / "mode_shapes.csv")
    assert set(shapes["point"]) == {"X", "Y", "Z"}
    mac = pd.read_csv(res / "mac.csv").set_index("mode").to_numpy()
    assert np.allclose(np.diag(mac), 1.0)
    uff = pyuff.UFF(str(res / "modes.uff"))
    assert list(uff.get_set_types()) == [15] + [55] * len(modes)
    back = read_frf_uff(res / "frf.uff")
    np.testing.assert_allclose(back["H"].values[..., 1:], ds["H"].values[..., 1:], rtol=1e-5)
    assert (tiny_run / "results" / "chapters" / "ch3_3_modal.html").exists()
