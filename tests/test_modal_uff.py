"""UFF in and out: real exports (tests/data/real/uff), UFF 58 time histories through the hit
chain, FRF forms by unit code, modes.uff (UFF 15 + 55) through pyuff, the uff importer."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from test_modal_layouts import (  # the planted 4-node structure (tests/ is on sys.path)
    BAND,
    DOFS,
    F_HZ,
    FS,
    NODES,
    ZETA,
    _analytic,
    _hits,
    _truth_at,
)

from robomill import modal
from robomill.io import RawDataError
from robomill.io.impact import (
    G_MS2,
    HitRecord,
    load_impact_test,
    read_frf_uff,
    read_hits_uff,
)
from robomill.modal.uff import write_frf_uff, write_modes_uff

REAL = Path(__file__).parent / "data" / "real" / "uff"
MEASUREMENT = REAL / "pyuff_measurement_roving_hammer.uff"


# ---- real files -------------------------------------------------------------------------------
def test_real_roving_hammer_frfs_accelerance_to_receptance():
    import pyuff

    ds = read_frf_uff(MEASUREMENT)
    assert ds["H"].dims == ("output", "input", "frequency")
    assert list(ds["output"].values) == ["X"]
    assert list(ds["input"].values) == ["X", "2X", "3X"]
    assert ds["input_node"].values.tolist() == [1, 2, 3]
    assert "coherence" not in ds  # the export has no type-6 sets
    raw = pyuff.UFF(str(MEASUREMENT)).read_sets(1)  # H(1X, 2X), accelerance (12/13)
    assert (raw["ordinate_spec_data_type"], raw["orddenom_spec_data_type"]) == (12, 13)
    w = 2 * np.pi * raw["x"][100]
    assert ds["H"].values[0, 1, 100] == pytest.approx(-raw["data"][100] / w**2, rel=1e-12)
    assert np.isnan(ds["H"].values[..., 0]).all()  # DC: no receptance from an accelerance


def test_real_roving_hammer_identification_and_its_flags():
    ds = read_frf_uff(MEASUREMENT)
    # no coherence in the export: the band starts at 2 % of its top (modal.band_from_data)
    band = modal.band_from_data(ds)
    assert band == (20.0, 1000.0)
    idn = modal.identify(ds, band_hz=band, max_order=30)
    t = idn.modes
    # the free-free beam of this export: six modes in 0-1000 Hz
    np.testing.assert_allclose(t["f_n_hz"], [51.5, 142.2, 278.7, 460.4, 687.2, 958.5],
                               rtol=0.005)
    assert (t["zeta"] < 0.01).all()
    assert [tuple(p) for p in idn.shapes.points] == [(1, 1), (2, 1), (3, 1)]
    assert (t["driving_point"] == "X").all()
    # every other mode has a negative residue at the "driving point" 1X/1X: the real part of
    # the accelerance does not pass through an antiresonance between modes 1 and 2, so node 1
    # of the hammer and of the accelerometer are not the same point in this export. Reported
    # as non-physical, never as a plain negative stiffness.
    neg = t["m_modal_kg"] < 0
    assert neg.tolist() == [False, True, False, True, False, True]
    assert (~t.loc[neg, "physical"]).all() and t.loc[~neg, "physical"].all()
    assert t.loc[neg, "flags"].str.contains("negative modal mass").all()
    assert idn.mac.shape == (6, 6) and np.allclose(np.diag(idn.mac), 1.0)
    # the synthesized FRFs follow the measured ones (relative misfit per FRF, in the band)
    f = ds["frequency"].values
    inb = (f >= band[0]) & (f <= band[1])
    h, hs = ds["H"].values[..., inb], idn.H_synth[..., inb]
    assert np.all(np.linalg.norm(hs - h, axis=-1) / np.linalg.norm(h, axis=-1) < 0.05)


@pytest.mark.parametrize("name, message", [
    ("pyuff_binary8byte_time.uff", r"data set 1 \(NONE\): direction code 0 in rsp_dir"),
    ("pyuff_catman_time_history.uff", r"data set 1 \(1x : m/s²\): direction code 0 in rsp_dir"),
])
def test_real_time_histories_that_are_not_hits_are_refused(name, message):
    with pytest.raises(RawDataError, match=message) as err:
        read_hits_uff(REAL / name)
    assert name in str(err.value)


# ---- UFF 58 time histories (function type 1) ---------------------------------------------------
def _write_hits_uff(path, hit_list, *, accel_in_g=False):
    import pyuff

    sets = []
    for rec, _ in hit_list:
        t = np.arange(rec.force_N.size) / rec.fs_hz
        common = dict(func_type=1, abscissa_spacing=1, abscissa_min=0.0,
                      abscissa_inc=1.0 / rec.fs_hz, abscissa_spec_data_type=17, x=t, id2="",
                      id3="", id4="", id5="", ref_node=0, ref_dir=0,
                      orddenom_spec_data_type=0)
        sets.append(pyuff.prepare_58(id1="hammer", rsp_node=rec.reference[0],
                                     rsp_dir=rec.reference[1], ordinate_spec_data_type=13,
                                     ordinate_axis_units_lab="N", data=rec.force_N, **common))
        for k, (node, d) in enumerate(rec.responses):
            scale = G_MS2 if accel_in_g else 1.0
            sets.append(pyuff.prepare_58(id1=f"acc {node}{d}", rsp_node=node, rsp_dir=d,
                                         ordinate_spec_data_type=12,
                                         ordinate_axis_units_lab="g" if accel_in_g else "m/s^2",
                                         data=rec.accel_ms2[:, k] / scale, **common))
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    return path


def test_uff_time_histories_give_the_same_frfs_as_the_records(tmp_path):
    refs = [(n, 1) for n in NODES]
    hit_list = [h for ref in refs for h in _hits(ref, [(1, 1), (1, 2)])]
    path = _write_hits_uff(tmp_path / "hits.uff", hit_list, accel_in_g=True)
    back = read_hits_uff(path)
    assert len(back) == len(hit_list)
    assert back[5].reference == (2, 1) and back[5].responses == ((1, 1), (1, 2))
    np.testing.assert_allclose(back[5].accel_ms2, hit_list[5][0].accel_ms2, rtol=1e-10)
    assert back[5].fs_hz == pytest.approx(FS)

    def frf(hits):
        _, groups = modal.check_and_group(hits)
        return modal.frf_from_groups(groups, FS, force_window_s=0.01, exponential_end=0.05)

    a = frf(hit_list)
    b = frf([(r, {"path": r.source, "hit": k}) for k, r in enumerate(back)])
    np.testing.assert_allclose(b["H"].values[..., 1:], a["H"].values[..., 1:], rtol=1e-8)
    idn = modal.identify(b, band_hz=BAND, max_order=20)
    assert np.all(np.abs(idn.modes["f_n_hz"].to_numpy() / F_HZ - 1) < 0.005)
    assert np.all(np.abs(idn.modes["zeta"].to_numpy() / ZETA - 1) < 0.10)


def test_load_impact_test_from_a_manifest_mixes_csv_and_uff_hits(tmp_path):
    from robomill.io.manifest import build_manifest, load_manifest, write_manifest

    raw = tmp_path / "raw"
    (raw / "impact").mkdir(parents=True)
    uff_hits = _hits((2, 1), [(1, 1)])
    _write_hits_uff(raw / "impact" / "node2.uff", uff_hits)
    (rec, _), = _hits((1, 1), [(1, 1)], n_hits=1)
    t = np.arange(rec.force_N.size) / FS
    np.savetxt(raw / "impact" / "n1.csv", np.column_stack([t, rec.force_N, rec.accel_ms2]),
               delimiter=",", header="t_s,force_N,ax_ms2", comments="", fmt="%.12g")
    files = [{"path": "impact/n1.csv", "kind": "impact", "direction": "X", "hit": 1,
              "range_N": 5000.0},
             {"path": "impact/node2.uff", "kind": "impact"}]
    write_manifest(build_manifest({"spindle_rpm": 1, "flutes": 1, "tool_diameter_mm": 1,
                                   "cut_length_mm": 1}, [], files, raw), raw / "manifest.yaml")
    man = load_manifest(raw / "manifest.yaml")
    test = load_impact_test(man, man.files)
    assert len(test.hits) == 4 and not test.frfs
    assert test.hits[0][1]["range_N"] == 5000.0 and test.hits[0][0].responses == ((1, 1),)
    assert [m["path"] for _, m in test.hits[1:]] == [f"impact/node2.uff#{k}" for k in (1, 2, 3)]
    table, groups = modal.check_and_group(test.hits)
    ds = modal.frf_from_groups(groups, FS, force_window_s=0.01, exponential_end=0.05)
    assert list(ds["input"].values) == ["X", "2X"]
    # a CSV entry without its direction is refused naming the manifest key
    bad = [dict(files[0], direction="W")]
    with pytest.raises(RawDataError, match=r"files\[0\]\.direction"):
        load_impact_test(man, bad)
    with pytest.raises(RawDataError, match=r"files\[0\]\.node: node 0 is not a node number"):
        load_impact_test(man, [dict(files[0], node=0)])
    with pytest.raises(RawDataError, match=r"files\[0\]\.hit: hit 'one' is not a hit number"):
        load_impact_test(man, [dict(files[0], hit="one")])
    with pytest.raises(RawDataError, match=r"files\[0\]\.range_ms2: range_ms2 -1"):
        load_impact_test(man, [dict(files[0], range_ms2=-1)])


# ---- FRF forms, FRFs out with nodes, modes out ------------------------------------------------
def test_mobility_and_unknown_unit_codes(tmp_path):
    import pyuff

    ds = _analytic([(1, 1)], [(1, 1)], df=0.5, fmax=120.0)
    f = ds["frequency"].values
    mob = np.nan_to_num(ds["H"].values[0, 0] * 2j * np.pi * f)

    def write(code):
        s = pyuff.prepare_58(func_type=4, id1="H", rsp_node=1, rsp_dir=1, ref_node=1, ref_dir=1,
                             abscissa_spacing=1, abscissa_min=0.0, abscissa_inc=0.5,
                             abscissa_spec_data_type=18, x=f, ordinate_spec_data_type=code,
                             orddenom_spec_data_type=13, data=mob.astype(complex), id2="",
                             id3="", id4="", id5="")
        p = tmp_path / f"h{code}.uff"
        pyuff.UFF(str(p)).write_sets([s], mode="overwrite")
        return p

    back = read_frf_uff(write(11))
    np.testing.assert_allclose(back["H"].values[..., 1:], ds["H"].values[..., 1:], rtol=1e-4)
    with pytest.raises(RawDataError, match=r"h9.uff: data set 1 \(H\): FRF unit codes 9/13"):
        read_frf_uff(write(9))


def test_frf_uff_keeps_nodes_and_signed_directions(tmp_path):
    outputs = [(1, 1), (3, -2), (4, 3)]
    ds = _analytic(outputs, [(2, 1)], df=0.5, fmax=120.0)
    back = read_frf_uff(write_frf_uff(ds, tmp_path / "frf.uff"))
    assert list(back["output"].values) == ["X", "3-Y", "4Z"]
    assert back["output_dir"].values.tolist() == [1, -2, 3]
    assert list(back["input"].values) == ["2X"]
    np.testing.assert_allclose(back["H"].values[..., 1:], ds["H"].values[..., 1:], rtol=1e-5)


def test_modes_uff_round_trip_through_pyuff(tmp_path):
    import pyuff

    outputs = [(n, 2) for n in NODES] + [(3, -1)]
    ds = _analytic(outputs, [(1, 2)])
    idn = modal.identify(ds, band_hz=BAND, max_order=20)
    path = write_modes_uff(idn.modes, idn.shapes, tmp_path / "modes.uff")
    uff = pyuff.UFF(str(path))
    assert list(uff.get_set_types()) == [15, 55, 55, 55]
    sets = uff.read_sets()
    assert np.asarray(sets[0]["node_nums"]).tolist() == [1, 2, 3, 4]
    for r, s in enumerate(sets[1:]):
        # complex modes (analysis type 3) carry the pole: |p| = ω_n, -Re p/|p| = ζ
        assert abs(s["eig"]) / (2 * np.pi) == pytest.approx(idn.modes["f_n_hz"][r], rel=1e-5)
        assert -s["eig"].real / abs(s["eig"]) == pytest.approx(idn.modes["zeta"][r], rel=1e-4)
        assert s["mode_n"] == r + 1
        assert np.asarray(s["node_nums"]).tolist() == [1, 2, 3, 4]
        shape = idn.shapes.shapes[r]
        np.testing.assert_allclose(s["r2"], shape[:4], atol=1e-5)  # +Y at nodes 1-4
        assert s["r1"][2] == pytest.approx(-shape[4], abs=1e-5)  # -X at node 3 -> +X
        assert np.asarray(s["r3"]).tolist() == [0, 0, 0, 0]
        # and the shape matches the planted one
        truth = _truth_at(outputs)[r]
        assert modal.mac_matrix(np.vstack([shape, truth]))[0, 1] > 0.999
    assert DOFS  # the structure of tests.test_modal_layouts


# ---- the importer --------------------------------------------------------------------------------
def test_uff_importer_converts_real_and_hit_files(tmp_path):
    from robomill.importers import uff as importer

    parser = argparse.ArgumentParser()
    importer.add_arguments(parser)
    args = parser.parse_args(["--range-ms2", "500"])
    args.cut = None
    hits = _write_hits_uff(tmp_path / "my hits.uff", _hits((1, 1), [(1, 1)]))
    staging = tmp_path / "staging"
    entries = importer.convert([MEASUREMENT, hits], staging, args)
    assert entries == [
        {"path": "impact/pyuff_measurement_roving_hammer.uff", "kind": "impact",
         "uff_content": "frf", "range_ms2": 500.0},
        {"path": "impact/my_hits.uff", "kind": "impact", "uff_content": "hits",
         "range_ms2": 500.0}]
    assert (staging / "impact" / "my_hits.uff").read_bytes() == hits.read_bytes()
    assert importer.FORMAT == "uff" and importer.KIND == "impact"


@pytest.mark.parametrize("name, message", [
    ("pyuff_binary8byte_time.uff", r"direction code 0 in rsp_dir"),
    ("../../bad/impact/uff_truncated.uff", r"truncated file"),
    ("../../bad/impact/uff_empty.uff", r"no UFF 58 data set"),
    ("../../bad/impact/uff_hits_no_force.uff", r"acceleration before any hammer force set"),
])
def test_uff_importer_refuses_bad_files_naming_them(tmp_path, name, message):
    from robomill.importers import uff as importer

    src = (REAL / name).resolve()
    args = argparse.Namespace(cut=None, range_N=None, range_ms2=None)
    with pytest.raises(RawDataError, match=message) as err:
        importer.convert([src], tmp_path / "staging", args)
    assert src.name in str(err.value)
    assert not (tmp_path / "staging" / "impact" / src.name).exists()


def test_frf_dataset_combination_and_hit_traces():
    a = _analytic([(1, 1)], [(1, 1)])
    b = _analytic([(2, 1)], [(1, 1)])
    ds = modal.combine_frfs([a, b])
    assert list(ds["output"].values) == ["X", "2X"]
    with pytest.raises(ValueError, match="in two files"):
        modal.combine_frfs([a, a])
    hit_list = _hits((1, 1), [(1, -2)], n_hits=2)
    table, _ = modal.check_and_group(hit_list)
    tr = modal.hit_traces(hit_list, table, FS)
    assert np.isnan(tr["ax_ms2"].values).all()
    np.testing.assert_allclose(tr["ay_ms2"].values[0], -hit_list[0][0].accel_ms2[:FS, 0])
    assert isinstance(tr, xr.Dataset) and isinstance(hit_list[0][0], HitRecord)
