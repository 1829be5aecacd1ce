"""The scorecard: locators read the cited artefact; verdicts follow the tolerance; on the tiny
run every `ours` equals the value in the artefact it cites (read here independently)."""

import math
import re

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from robomill.pipeline.scorecard import (
    build_scorecard,
    load_checks,
    parse_locator,
    read_locator,
    verdict,
)


def test_locator_reads_cells_aggregates_and_netcdf(tmp_path):
    pd.DataFrame({"segment": [1, 2, 3], "s1_px": [0.5, 0.7, 0.9],
                  "hz": [65.0, 130.0, 90.0]}).to_csv(tmp_path / "t.csv", index=False)
    assert read_locator("t.csv::s1_px[segment=2]", tmp_path) == 0.7
    assert read_locator("t.csv::hz@frac_in(60,120)", tmp_path) == pytest.approx(2 / 3)
    assert read_locator("t.csv::hz@median", tmp_path) == 90.0
    with pytest.raises(ValueError, match="selects 3 values"):
        read_locator("t.csv::hz", tmp_path)
    ds = xr.Dataset({"d": (("a", "e"), np.arange(6.0).reshape(2, 3))},
                    coords={"a": [1, 2], "e": [-1.0, 0.5, 1.0]}, attrs={"t_s": [1.2, 1.8]})
    ds.to_netcdf(tmp_path / "x.nc", engine="h5netcdf")
    assert read_locator("x.nc::d[a=2,e=1.0]", tmp_path) == 5.0
    assert read_locator("x.nc::attrs.t_s@min", tmp_path) == 1.2
    assert parse_locator("p.csv::c[k=v]@max")["sel"] == {"k": "v"}


def test_no_thesis_comparison_for_a_study_that_is_not_the_thesis_design(tmp_path):
    from robomill.experiment import Cut, is_thesis_study

    pd.DataFrame({"hz": [65.0]}).to_csv(tmp_path / "t.csv", index=False)
    checks = [{"source": "thesis", "where": "Fig 3.4", "quantity": "dominant", "unit": "Hz",
               "source_value": 65.0, "tolerance": {"rel": 0.1}, "locator": "t.csv::hz@max"},
              {"source": "thesis", "where": "Table 9", "quantity": "x", "source_value": 1.0,
               "locator": None, "reason": "not computed"}]
    assert len(build_scorecard(tmp_path, checks)) == 2
    empty = build_scorecard(tmp_path, checks, thesis_study=False)
    assert empty.empty and list(empty.columns)[:2] == ["source", "where"]
    cuts = [Cut("s1_g1_px", 1, 1, "px", 1.0, 0.25)]
    thesis = {"spindle_rpm": 28000, "flutes": 2}
    assert is_thesis_study(cuts, thesis)
    assert not is_thesis_study(cuts, {**thesis, "spindle_rpm": 6000})  # thesis ids, not its
    assert not is_thesis_study(cuts, {**thesis, "flutes": 3})          # process
    assert not is_thesis_study([Cut("run7", None, None, "px", 1.0, 0.25)], thesis)
    assert not is_thesis_study([], thesis)


def test_reference_study_rows_are_kept_for_any_study(tmp_path):
    """A check marked ``any_study`` (chapter 6's reference studies: computed from the
    configuration alone) stays in the scorecard of a study that is not the thesis' design;
    the thesis' rows go."""
    pd.DataFrame({"n": [101.0]}).to_csv(tmp_path / "h.csv", index=False)
    checks = [{"source": "thesis", "where": "Fig 3.4", "quantity": "a", "source_value": 100.0,
               "tolerance": {"rel": 0.1}, "locator": "h.csv::n@max"},
              {"source": "Rybak n.d.", "where": "Fig. 5", "quantity": "b", "source_value": 100.0,
               "tolerance": {"rel": 0.1}, "locator": "h.csv::n@max", "any_study": True}]
    other = build_scorecard(tmp_path, checks, thesis_study=False)
    assert list(other["source"]) == ["Rybak n.d."] and list(other["verdict"]) == ["pass"]
    assert len(build_scorecard(tmp_path, checks)) == 2
    shipped = [c for c in load_checks() if c.get("any_study")]
    assert shipped and all(c["locator"].startswith(("results/chatter/simulation.nc",
                                                    "results/chatter/cases/",
                                                    "results/hexapod/")) for c in shipped)


@pytest.mark.parametrize(
    ("ours", "source", "tol", "ok"),
    [(0.9, 0.61, {"factor": 1.5}, True), (1.0, 0.61, {"factor": 1.5}, False),
     (13.1, 13.0, {"rel": 0.02}, True), (1.3, 2.0, {"abs": 0.5}, False),
     (0.02, [0.01, 0.02], None, True), (0.03, [0.01, 0.02], None, False),
     (float("nan"), 1.0, {"rel": 1.0}, False)],
)
def test_verdict(ours, source, tol, ok):
    assert verdict(ours, source, tol) is ok


def _independent(locator: str, root):
    """Re-read a locator without robomill.pipeline.scorecard (pandas / xarray only)."""
    m = re.match(r"^([^:]+)::([\w.]+)(?:\[([^\]]*)\])?(?:@(\w+)(?:\(([^)]*)\))?)?$", locator)
    path, field, sel, agg, args = m.groups()
    pairs = [kv.split("=") for kv in sel.split(",")] if sel else []
    if path.endswith(".csv"):
        df = pd.read_csv(root / path)
        for k, v in pairs:
            df = df[df[k].astype(str) == v]
        values = df[field].to_numpy(float)
    else:
        with xr.open_dataset(root / path, engine="h5netcdf") as ds:
            if field.startswith("attrs."):
                values = np.atleast_1d(ds.attrs[field[6:]]).astype(float)
            else:
                da = ds[field]
                for k, v in pairs:
                    coord = da[k].values
                    da = da.sel({k: type(coord[0].item())(v) if coord.dtype.kind != "U" else v})
                values = np.atleast_1d(da.values).astype(float)
    if agg is None:
        return float(values[0])
    if agg == "frac_in":
        lo, hi = map(float, args.split(","))
        return float(np.mean((values >= lo) & (values <= hi)))
    if agg in ("min", "max", "mean", "median"):  # an empty value (no peak) is not a value
        values = values[~np.isnan(values)]
        if values.size == 0:
            return float("nan")
    return float(getattr(np, agg)(values))


@pytest.mark.pipeline
def test_scorecard_ours_equals_the_cited_artefact(tiny_run):
    card = pd.read_csv(tiny_run / "results/thesis/scorecard.csv")
    assert list(card.columns[:9]) == ["source", "where", "quantity", "source_value", "ours",
                                      "unit", "tolerance", "verdict", "reason"]
    computed = card[card.verdict != "not computed"]
    assert len(computed) >= 20
    for _, row in computed.iterrows():
        expected = _independent(row.artefact, tiny_run)
        assert (math.isclose(row.ours, expected, rel_tol=1e-5, abs_tol=1e-12)
                or (math.isnan(row.ours) and math.isnan(expected))), row.artefact
    misses = card[card.verdict == "miss"]
    assert misses.reason.fillna("").str.len().gt(10).all(), "every miss is explained"
    assert build_scorecard(tiny_run).shape[0] == len(card)
