"""Artefacts round-trip with units, long names and provenance."""

import json

import numpy as np
import pytest
import xarray as xr

from robomill.io import open_artefact, sha256_file, write_artefact


def _ds():
    return xr.Dataset(
        {
            "z": ("x", np.linspace(0, 1, 5), {"units": "um", "long_name": "height"}),
            "ok": ("x", np.array([True, False, True, True, False]),
                   {"units": "1", "long_name": "flag"}),
        },
        coords={"x": ("x", np.arange(5.0), {"units": "mm", "long_name": "position"})},
    )


def test_round_trip_keeps_values_units_and_provenance(tmp_path):
    src = tmp_path / "input.csv"
    src.write_text("a,b\n1,2\n")
    path = write_artefact(_ds(), tmp_path / "a.nc", rule="test_rule", inputs=[src],
                          config_section={"k": 1})
    back = open_artefact(path)
    xr.testing.assert_identical(back[["z", "ok"]].drop_attrs(deep=False),
                                _ds()[["z", "ok"]].drop_attrs(deep=False))
    assert back["z"].attrs["units"] == "um"
    assert back["x"].attrs["units"] == "mm"
    assert back["ok"].dtype == bool
    assert back.attrs["rule"] == "test_rule"
    assert json.loads(back.attrs["inputs_sha256"]) == {str(src): sha256_file(src)}
    assert len(back.attrs["config_digest"]) == 16
    for key in ("robomill_version", "git_commit"):
        assert back.attrs[key]


def test_config_digest_changes_with_values_not_order(tmp_path):
    a = write_artefact(_ds(), tmp_path / "a.nc", rule="r", config_section={"a": 1, "b": 2})
    b = write_artefact(_ds(), tmp_path / "b.nc", rule="r", config_section={"b": 2, "a": 1})
    c = write_artefact(_ds(), tmp_path / "c.nc", rule="r", config_section={"a": 1, "b": 3})
    da, db, dc = (open_artefact(p).attrs["config_digest"] for p in (a, b, c))
    assert da == db != dc


def test_unlabelled_variable_is_refused(tmp_path):
    ds = _ds()
    ds["bare"] = ("x", np.zeros(5))
    with pytest.raises(ValueError, match="bare.units"):
        write_artefact(ds, tmp_path / "a.nc", rule="r")
    assert not (tmp_path / "a.nc").exists()
