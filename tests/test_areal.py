"""Areal scans: the contract file, the X3P and instrument-format importers on real exports,
the ISO 25178-2 height parameters after form removal, the areal PSD and the profiles along
the feed (robomill.io.areal, robomill.importers.x3p --areal, robomill.importers.topography,
robomill.surface.areal)."""

from __future__ import annotations

import argparse
import hashlib
import zipfile
from pathlib import Path

import numpy as np
import pytest

from robomill.errors import RawDataError
from robomill.importers.topography import read_topography_file
from robomill.importers.x3p import read_x3p_grid
from robomill.io.areal import read_areal, scan_problem, write_areal
from robomill.surface.areal import (
    analyse_scan,
    extract_lines,
    height_parameters,
    line_psd,
    psd_2d,
    radial_psd,
    remove_form,
)

REAL = Path(__file__).parent / "data" / "real"
LAND = REAL / "x3p" / "sample-land.x3p"
MM11 = REAL / "smats" / "mm11_iso1_ascii_binary64.sdf"
# Sq of the real Sensofar scan computed by SurfaceTopography 1.27.1 (an independent reader
# and implementation; tests/data/real/x3p/SOURCE.md has the command): the mean plane
# (detrend_mode="height") and the quadric (detrend_mode="curvature") removed, in µm
SQ_PLANE_UM = 33.64027570219823
SQ_QUADRIC_UM = 16.398857366647832


def _import(module: str, sources, staging: Path, argv=()):
    import importlib

    mod = importlib.import_module(f"robomill.importers.{module}")
    parser = argparse.ArgumentParser()
    parser.add_argument("--cut", default=None)
    mod.add_arguments(parser)
    return mod.convert([Path(s) for s in sources], staging, parser.parse_args(list(argv)))


def test_real_x3p_scan_sq_matches_surfacetopography_within_1_percent():
    """The real confocal scan (nested archive layout, empty CZ Offset, 25 292 dropouts):
    Sq after form removal within 1 % of SurfaceTopography's value for the same operator."""
    z, dx, dy, meta = read_x3p_grid(LAND)
    assert z.shape == (256, 918) and dx == pytest.approx(2.58e-3) and dy == pytest.approx(2.58e-3)
    assert int(np.isnan(z).sum()) == 25292
    assert meta["manufacturer"] == "Sensofar" and meta["model"] == "Sneox1"
    assert meta["probe"] == "Nikon - EPI 20X"
    for degree, ref in ((1, SQ_PLANE_UM), (2, SQ_QUADRIC_UM)):
        resid, _ = remove_form(z, dx, dy, degree)
        assert height_parameters(resid)["Sq_um"] == pytest.approx(ref, rel=0.01)


def test_surfacetopography_agrees_on_a_flat_copy_of_the_real_scan(tmp_path):
    """The reference recomputed: SurfaceTopography reads the same bytes once the archive is
    flattened and the empty Offset written as 0 (it refuses the export as it is)."""
    st = pytest.importorskip("SurfaceTopography")
    with zipfile.ZipFile(LAND) as zf:
        main = zf.read("sample-land/main.xml").replace(b"<Offset/>", b"<Offset>0</Offset>")
        data = zf.read("sample-land/bindata/data.bin")
    flat = tmp_path / "flat.x3p"
    with zipfile.ZipFile(flat, "w") as zf:
        zf.writestr("main.xml", main)
        zf.writestr("bindata/data.bin", data)
    with pytest.raises(Exception):  # noqa: B017 - the export as it is: refused
        st.read_topography(str(LAND))
    t = st.read_topography(str(flat))
    ours = remove_form(read_x3p_grid(LAND)[0], 2.58e-3, 2.58e-3, 1)[0]
    sq_st = t.detrend(detrend_mode="height").rms_height_from_area() * 1e6
    assert height_parameters(ours)["Sq_um"] == pytest.approx(sq_st, rel=1e-6)


def test_x3p_areal_import_carries_the_instrument_into_entry_and_file(tmp_path):
    e = _import("x3p", [LAND], tmp_path, ["--cut", "c1", "--areal", "--feed-angle-deg", "90"])
    assert e == [{"path": "areal/c1.nc", "kind": "areal", "cut": "c1", "feed_angle_deg": 90.0,
                  "instrument": "Sensofar Sneox1", "probe": "Nikon - EPI 20X",
                  "lateral_spacing_um": [2.58, 2.58], "source_file": "sample-land.x3p",
                  "source_format": "x3p"}]
    z, dx, dy, attrs = read_areal(tmp_path / "areal/c1.nc")
    z0 = read_x3p_grid(LAND)[0]
    np.testing.assert_allclose(z, z0, rtol=1e-6)  # float32 in the file
    assert attrs["model"] == "Sneox1" and attrs["serial"] == "350262016"
    assert dx == pytest.approx(2.58e-3)


def test_real_sdf_surface_through_surfacetopography(tmp_path):
    """The MountainsMap SDF re-export (real output of a commercial program): height
    (30 p + i) nm at point i of profile p, 1 µm spacing, the BAD point not measured."""
    pytest.importorskip("SurfaceTopography")
    e = _import("topography", [MM11], tmp_path, ["--cut", "c2"])
    assert e[0]["kind"] == "areal" and e[0]["source_format"] == "sdf"
    assert e[0]["lateral_spacing_um"] == [pytest.approx(1.0), pytest.approx(1.0)]
    z, dx, dy, _ = read_areal(tmp_path / "areal/c2.nc")
    assert z.shape == (20, 30)
    p, i = np.mgrid[0:20, 0:30]
    truth = (30 * p + i) * 1e-3
    ok = np.isfinite(z)
    assert int((~ok).sum()) == 1 and not ok[0, 29]
    np.testing.assert_allclose(z[ok], truth[ok], atol=1e-5)


def test_only_invalid_points_is_one_line(tmp_path):
    z = np.full((4, 5), np.nan)
    path = write_areal(tmp_path / "a.nc", z, 0.01, 0.01, {})
    with pytest.raises(RawDataError, match=r"a\.nc: z_um: the scan has only invalid points "
                       r"\(5 × 4, all NaN\)"):
        read_areal(path)
    assert "only invalid points" in scan_problem(path)  # the workflow's DAG-time check
    good = write_areal(tmp_path / "g.nc", np.ones((3, 4)), 0.01, 0.01, {})
    assert scan_problem(good) is None
    with pytest.raises(RawDataError, match=r"x\.sdf: file: not readable as an areal scan"):
        bad = tmp_path / "x.sdf"
        bad.write_text("not a scan\n")
        read_topography_file(bad)


def test_height_parameters_of_known_surfaces():
    y, x = np.mgrid[0:64, 0:128] * 0.01
    sine = 2.0 * np.sin(2 * np.pi * x / 0.32)  # whole periods along x
    p = height_parameters(sine)
    assert p["Sq_um"] == pytest.approx(2.0 / np.sqrt(2), rel=1e-9)
    assert p["Sa_um"] == pytest.approx(2 * 2.0 / np.pi, rel=5e-3)  # 32 samples a period
    assert p["Ssk"] == pytest.approx(0.0, abs=1e-9) and p["Sku"] == pytest.approx(1.5, rel=1e-9)
    assert p["Sz_um"] == pytest.approx(4.0, rel=1e-3)
    # form removal: a tilted quadric is removed exactly, whatever lies on it
    form = 5 + 3 * x - 2 * y + 4 * x**2 - x * y
    resid, fitted = remove_form(form, 0.01, 0.01, 2)
    assert np.abs(resid).max() < 1e-9
    np.testing.assert_allclose(remove_form(sine + form, 0.01, 0.01, 2)[0],
                               remove_form(sine, 0.01, 0.01, 2)[0], atol=1e-9)
    assert remove_form(form, 0.01, 0.01, 1)[0].std() > 0.1  # a plane cannot


def test_areal_psd_parseval_and_feed_directions():
    """Feed marks of wavelength 0.08 mm along the feed, the feed at 0° then at 90° in the
    scan: the along-feed PSD peaks at 12.5 /mm, the across-feed one does not."""
    rng = np.random.default_rng(3)
    y, x = np.mgrid[0:128, 0:256] * 0.005
    marks = 0.5 * np.cos(2 * np.pi * x / 0.08)
    z = marks + 0.05 * rng.standard_normal(x.shape)
    ky, kx, c = psd_2d(z, 0.005, 0.005)
    dk = (kx[1] - kx[0]) * (ky[1] - ky[0])
    assert c.sum() * dk == pytest.approx(np.mean((z - z.mean()) ** 2), rel=0.1)
    kr, cr = radial_psd(z, 0.005, 0.005)
    assert kr[np.argmax(cr)] == pytest.approx(12.5, abs=2 * (kr[1] - kr[0]))
    for angle, surface in ((0.0, z), (90.0, z.T)):
        s, along = extract_lines(surface, 0.005, 0.005, angle)
        k, pa = line_psd(along, s[1] - s[0])
        assert k[np.argmax(pa)] == pytest.approx(12.5, abs=0.5)
        s, across = extract_lines(surface, 0.005, 0.005, angle + 90)
        kc, pc = line_psd(across, s[1] - s[0])
        assert pc.max() < 0.01 * pa.max()


def test_extract_lines_at_an_oblique_feed():
    """Marks across a feed at 30° in the scan: the lines along 30° see the 0.1 mm period."""
    y, x = np.mgrid[0:200, 0:200] * 0.004
    u = np.array([np.cos(np.radians(30)), np.sin(np.radians(30))])
    z = np.cos(2 * np.pi * (x * u[0] + y * u[1]) / 0.1)
    s, lines = extract_lines(z, 0.004, 0.004, 30.0)
    k, p = line_psd(lines, s[1] - s[0])
    assert k[np.argmax(p)] == pytest.approx(10.0, abs=0.6)
    # and across it the surface is flat along each line
    s, lines = extract_lines(z, 0.004, 0.004, 120.0)
    assert np.nanmax(np.nanstd(lines, axis=1)) < 0.05


def test_analyse_scan_on_the_real_scan():
    z, dx, dy, _ = read_x3p_grid(LAND)
    ds, (x, zp) = analyse_scan(z, dx, dy, 90.0, {"areal_form_degree": 2})
    assert float(ds["Sq_um"]) == pytest.approx(SQ_QUADRIC_UM, rel=1e-9)
    assert ds.sizes["line"] == 918 and x.size > 50 and np.isfinite(zp).all()
    assert 0.85 < float(ds["valid_share"]) < 0.95
    with pytest.raises(ValueError, match="no valid point"):
        analyse_scan(np.full((3, 3), np.nan), dx, dy, 0.0, {"areal_form_degree": 1})


def test_x3p_areal_import_of_a_scan_with_only_invalid_points(tmp_path):
    """The openGPS binary sample with every bit of valid.bin cleared: one line, no file."""
    src = REAL / "x3p" / "ISO5436-sample1_bin.x3p"
    bad = tmp_path / "dead.x3p"
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(bad, "w") as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename.endswith("valid.bin"):
                old_md5 = hashlib.md5(data).hexdigest().encode()
                data = bytes(len(data))
                new_md5 = hashlib.md5(data).hexdigest().encode()
            zout.writestr(item, data)
    with pytest.raises(RawDataError, match=r"MD5ChecksumValidPoints: bindata/valid\.bin MD5 is"):
        read_x3p_grid(bad)  # a valid.bin that is not the one main.xml describes
    with zipfile.ZipFile(bad) as zin:  # main.xml states the new valid.bin's MD5
        members = {i.filename: zin.read(i.filename) for i in zin.infolist()}
    members["main.xml"] = members["main.xml"].replace(old_md5, new_md5)
    with zipfile.ZipFile(bad, "w") as zout:
        for name, data in members.items():
            zout.writestr(name, data)
    staging = tmp_path / "staging"
    with pytest.raises(RawDataError, match=r"dead\.x3p: main\.xml: Record3: the scan has only "
                       r"invalid points \(4 × 4\)"):
        _import("x3p", [bad], staging, ["--areal"])
    assert not staging.exists() or not any(p.is_file() for p in staging.rglob("*"))
    # the same file, readable points: the 4 x 4 grid with its one invalid point
    e = _import("x3p", [src], staging, ["--areal", "--cut", "s"])
    z, *_ = read_areal(staging / e[0]["path"])
    assert z.shape == (4, 4) and int(np.isnan(z).sum()) == 1
