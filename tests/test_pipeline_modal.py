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

    from robomill.io.impact import read_frf, read_frf_uff
    from robomill.pipeline.config import load_config
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
    assert (tiny_run / "results" / "chapters" / "ch3_modal.html").exists()


def _raw_with_impact(tiny_run, tmp_path, files, entries, *, band_hz=None):
    """The tiny run's raw folder with its impact hits replaced by ``files`` (name -> bytes)
    listed as ``entries``; config with ``modal.band_hz`` set to ``band_hz``."""
    import yaml
    from conftest import raw_copy_of_run

    from robomill.io.hashing import sha256_file

    cfgfile = tmp_path / "config.yaml"
    raw = raw_copy_of_run(tiny_run, tmp_path / "raw", config_path=cfgfile)
    for p in (raw / "impact").glob("*.csv"):
        p.unlink()
    for name, data in files.items():
        (raw / "impact" / name).write_bytes(data)
    man = yaml.safe_load((raw / "manifest.yaml").read_text())
    man["files"] = [f for f in man["files"] if f["kind"] != "impact"] + [
        {**e, "sha256": sha256_file(raw / e["path"])} for e in entries]
    (raw / "manifest.yaml").write_text(yaml.safe_dump(man, sort_keys=False))
    cfg = yaml.safe_load(cfgfile.read_text())
    cfg["modal"]["band_hz"] = band_hz
    cfgfile.write_text(yaml.safe_dump(cfg, sort_keys=False))
    return cfgfile


def test_modal_stage_on_a_real_uff_frf_export_with_the_band_from_the_data(tiny_run, tmp_path):
    """A raw folder whose impact data is pyuff's real roving-hammer FRF export (accelerance,
    nodes 1-3, no coherence) runs the modal stage with modal.band_hz: null."""
    import pyuff
    from conftest import run_snakemake

    from robomill.io.impact import read_frf

    src = REPO / "tests/data/real/uff/pyuff_measurement_roving_hammer.uff"
    cfg = _raw_with_impact(tiny_run, tmp_path, {src.name: src.read_bytes()},
                           [{"path": f"impact/{src.name}", "kind": "impact"}])
    work = tmp_path / "work"
    work.mkdir()
    proc = run_snakemake(work, "-j2", "results/modal/modes.uff", "results/modal/frf.uff",
                         configfile=cfg)
    assert proc.returncode == 0, proc.stderr[-4000:]
    res = work / "results" / "modal"
    ds = read_frf(res / "frf.nc")
    assert ds["input_node"].values.tolist() == [1, 2, 3]
    modes = pd.read_csv(res / "modes.csv")
    np.testing.assert_allclose(modes["f_n_hz"], [51.5, 142.2, 278.7, 460.4, 687.2, 958.5],
                               rtol=0.005)
    assert modes["physical"].tolist() == [True, False, True, False, True, False]
    assert len(pd.read_csv(res / "hits.csv")) == 0
    assert list(pyuff.UFF(str(res / "modes.uff")).get_set_types()) == [15] + [55] * 6
    assert "band 20-1000 Hz" in (work / "results/logs/modal/identify.log").read_text()


def test_modal_stage_on_uff_time_histories_matches_the_csv_hits(tiny_run, tmp_path):
    """The tiny run's hits exported as one UFF 58 file of time histories (as a modal test
    system would) give the same FRFs and modes as the CSV hits."""
    import pyuff
    from conftest import run_snakemake

    from robomill.io.impact import read_frf

    raw_hits = sorted((tiny_run / "results/synthetic/raw/impact").glob("hit*.csv"))
    sets = []
    for p in raw_hits:
        df = pd.read_csv(p)
        ref = "XYZ".index(p.stem[3]) + 1
        common = dict(func_type=1, abscissa_spacing=1, abscissa_min=0.0,
                      abscissa_inc=float(df["t_s"][1] - df["t_s"][0]),
                      abscissa_spec_data_type=17, x=df["t_s"].to_numpy(), id2="", id3="",
                      id4="", id5="", ref_node=0, ref_dir=0, orddenom_spec_data_type=0)
        sets.append(pyuff.prepare_58(id1=f"{p.stem} force", rsp_node=1, rsp_dir=ref,
                                     ordinate_spec_data_type=13,
                                     data=df["force_N"].to_numpy(), **common))
        for d, col in enumerate(("ax_ms2", "ay_ms2", "az_ms2"), start=1):
            sets.append(pyuff.prepare_58(id1=f"{p.stem} {col}", rsp_node=1, rsp_dir=d,
                                         ordinate_spec_data_type=12,
                                         data=df[col].to_numpy(), **common))
    uff = tmp_path / "hits.uff"
    pyuff.UFF(str(uff)).write_sets(sets, mode="overwrite")
    cfg = _raw_with_impact(tiny_run, tmp_path, {"hits.uff": uff.read_bytes()},
                           [{"path": "impact/hits.uff", "kind": "impact", "range_N": 2000.0,
                             "range_ms2": 50.0}], band_hz=[10.0, 100.0])
    work = tmp_path / "work"
    work.mkdir()
    proc = run_snakemake(work, "-j2", "results/modal/modes.uff", configfile=cfg)
    assert proc.returncode == 0, proc.stderr[-4000:]
    a = read_frf(tiny_run / "results/modal/frf.nc")
    b = read_frf(work / "results/modal/frf.nc")
    np.testing.assert_allclose(b["H"].values[..., 1:], a["H"].values[..., 1:], rtol=1e-6)
    hits_a = pd.read_csv(tiny_run / "results/modal/hits.csv")
    hits_b = pd.read_csv(work / "results/modal/hits.csv")
    assert hits_b["accepted"].tolist() == hits_a["accepted"].tolist()
    assert hits_b["path"].str.startswith("impact/hits.uff#").all()
    ma = pd.read_csv(tiny_run / "results/modal/modes.csv")
    mb = pd.read_csv(work / "results/modal/modes.csv")
    np.testing.assert_allclose(mb["f_n_hz"], ma["f_n_hz"], rtol=1e-5)
