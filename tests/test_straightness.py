"""Straightness analysis (thesis §3.2) against exact synthetic truth."""

from __future__ import annotations

import copy

import numpy as np
import pandas as pd
import pytest
import scipy.interpolate

from robomill import straightness as st
from robomill.synth import tracker
from robomill.synth.cell import cell_from_config
from robomill.synth.process import simulate_cut


def _wavy_line(wavelength_mm=2.5, amp_um=3.0, length_mm=40.0, fs_hz=815.0, v=4.0):
    """A straight path along (1, 1, 0)/√2 with a lateral sinusoid, trapezoidal speed."""
    t, s = tracker.motion_law(length_mm, v, 50.0, fs_hz)
    u = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
    lat = st.perpendicular_axes(u)[0]
    p = (np.array([600.0, -50.0, 200.0]) + np.outer(s, u)
         + 1e-3 * amp_um * np.outer(np.sin(2 * np.pi * s / wavelength_mm), lat))
    return t, p


@pytest.mark.parametrize("detrend_order", [1, 3])
def test_reordering_of_a_known_wavy_path_returns_its_wavelength(detrend_order):
    t, p = _wavy_line()
    prof = st.spatial_profile(t, p, ds_mm=0.01, trim_mm=1.0, detrend_order=detrend_order)
    spec = st.profile_spectrum(prof, nfft=2**15)
    assert prof.speed_mm_s == pytest.approx(4.0, rel=1e-3)
    peaks = st.spectrum_peaks(spec, fmin_per_mm=0.05, fmax_per_mm=20, threshold=25, n_peaks=5)
    top = peaks.loc[peaks["amplitude_um"].idxmax()]
    assert 1 / top["f_spatial_per_mm"] == pytest.approx(2.5, rel=0.01)
    assert top["amplitude_um"] == pytest.approx(3.0, rel=0.03)
    assert top["component"] == "lateral"
    # the lateral deviation is the sinusoid itself (best line removed)
    assert np.abs(prof.deviation_um[1]).max() < 1e-6


def test_reordering_does_not_depend_on_the_time_order_of_samples():
    t, p = _wavy_line(v=2.0)
    rng = np.random.default_rng(0)
    idx = rng.permutation(t.size)
    a = st.spatial_profile(t, p, ds_mm=0.01)
    b = st.spatial_profile(t[idx], p[idx], ds_mm=0.01)
    np.testing.assert_allclose(a.deviation_um, b.deviation_um, atol=1e-9)


def test_resample_uniform_averages_dense_samples_and_interpolates_sparse_ones():
    s = np.array([0.0, 0.001, 0.002, 0.5, 1.0])
    y = np.array([1.0, 2.0, 3.0, 5.0, 7.0])
    grid, out = st.resample_uniform(s, y, 0.25)
    np.testing.assert_allclose(grid, [0, 0.25, 0.5, 0.75, 1.0])
    np.testing.assert_allclose(out[0], [2.0, 3.5, 5.0, 6.0, 7.0])


@pytest.fixture(scope="module")
def cell(tiny_config):
    return cell_from_config(tiny_config)


def _timed_motion(cell, cut, feed):
    t, s = tracker.motion_law(40.0, feed, 100.0, 815.0)
    grid = np.linspace(0, 40, 201)
    q = scipy.interpolate.CubicSpline(grid, cell.joint_path_rad(cut, grid), axis=0)(s)
    return t, q, cell.cut_path_mm(cut, s)


def test_gear_spatial_frequencies_do_not_change_with_feed(cell, tiny_config):
    cut = next(c for c in tracker.tracker_runs(tiny_config) if c["direction"] == "px")["cut"]
    out = {}
    for feed in (2.0, 10.0):
        t, q, p = _timed_motion(cell, cut, feed)
        out[feed] = st.gear_frequencies_from_motion(t, q, p, cell.gears)
    np.testing.assert_allclose(out[2.0]["f_spatial_per_mm"], out[10.0]["f_spatial_per_mm"],
                               rtol=1e-3, atol=1e-9)
    moving = out[2.0]["f_temporal_hz"] > 1e-6
    ratio = out[10.0]["f_temporal_hz"][moving] / out[2.0]["f_temporal_hz"][moving]
    np.testing.assert_allclose(ratio, 5.0, rtol=1e-3)
    # and the same as from the path alone (joint angles vs distance, no time at all)
    grid = np.linspace(0, 40, 201)
    ref = st.gear_spatial_frequencies(cell.joint_path_rad(cut, grid), grid, cell.gears)
    np.testing.assert_allclose(out[2.0]["f_spatial_per_mm"], ref["f_spatial_per_mm"],
                               rtol=2e-2, atol=1e-4)
    # ... and the cell's own helper agrees
    cell_f = [g["f_spatial_per_mm"] for g in cell.gear_spatial_frequency_per_mm(cut)]
    np.testing.assert_allclose(ref["f_spatial_per_mm"], cell_f, rtol=1e-6, atol=1e-8)


def _single_gear_config(tiny_config, joint=3, stage="motor"):
    cfg = copy.deepcopy(tiny_config)
    for g in cfg["synth"]["gears"]:
        keep = g["joint"] == joint and g["stage"] == stage
        g["runout_arcsec"] = 0.0
        g["mesh_arcsec"] = 3.0 if keep else 0.0
    return cfg


ANALYSIS = dict(ds_mm=0.01, trim_mm=1.0, nfft=2**15, fmin_cycles=2.5, fmax_per_mm=20.0,
                threshold=25.0, n_peaks=20, tol_bins=0.5, detrend_order=3)


def _analyse(cfg, cell, run):
    df = tracker.simulate_run(cfg, cell, run["direction"], run["feed_mm_s"], run["cut"],
                              sim=simulate_cut(cell, run["cut"], cfg))
    prof, spec, gears, peaks = st.analyse_run(
        df["t_s"].to_numpy(), df[["x_mm", "y_mm", "z_mm"]].to_numpy(), robot=cell.robot,
        gears=cell.gears, tool_rotation=cell.tool_rotation(), q0_rad=cell.q_home_rad, **ANALYSIS)
    peaks.insert(0, "direction", run["direction"])
    peaks.insert(1, "feed_mm_s", run["feed_mm_s"])
    peaks["run"] = run["run"]
    return spec, peaks


def test_a_single_planted_eccentric_gear_is_attributed_to_its_joint_and_stage(tiny_config):
    cfg = _single_gear_config(tiny_config, joint=3, stage="motor")
    cell = cell_from_config(cfg)
    runs = [r for r in tracker.tracker_runs(cfg) if r["direction"] == "px"]
    assert len(runs) == 2
    parts, res = [], {}
    for r in runs:
        spec, peaks = _analyse(cfg, cell, r)
        parts.append(peaks)
        res[r["run"]] = spec.resolution_per_mm
    peaks = st.classify_peaks(pd.concat(parts, ignore_index=True), res)
    gear = peaks[peaks["mechanism"] == "gear"]
    assert len(gear) == 2  # one per feed
    assert set(gear["joint"]) == {3} and set(gear["stage"]) == {"motor"}
    assert set(gear["order"]) == {"mesh"}
    planted = tracker.planted_gear_table(cfg, cell, runs[0]["cut"])
    truth = planted[(planted["joint"] == 3) & (planted["stage"] == "motor")
                    & (planted["order"] == "mesh")].iloc[0]
    row = gear[gear["feed_mm_s"] == runs[0]["feed_mm_s"]].iloc[0]
    assert row["f_spatial_per_mm"] == pytest.approx(truth["f_spatial_per_mm"], abs=0.01)
    assert row["amplitude_um"] == pytest.approx(truth["amplitude_um"], rel=0.15)
    # the 13 Hz servo ripple is temporal at both feeds, never a gear
    temporal = peaks[peaks["mechanism"] == "temporal"]
    np.testing.assert_allclose(temporal["f_temporal_hz"], 13.0, atol=0.1)
    assert len(temporal) == 2
    assert set(peaks["mechanism"]) == {"gear", "temporal"}


def test_classification_uses_several_feeds():
    peaks = pd.DataFrame({
        "direction": ["py"] * 6, "feed_mm_s": [2.0, 4.0, 8.0, 2.0, 4.0, 8.0],
        "f_spatial_per_mm": [6.5, 3.25, 1.625, 0.45, 0.45, 0.45],
        "joint": pd.array([pd.NA, pd.NA, pd.NA, 1, 1, pd.NA], dtype="Int64"),
        "stage": ["", "", "", "motor", "motor", ""], "order": ["", "", "", "mesh", "mesh", ""],
        "gear_f_spatial_per_mm": [np.nan] * 3 + [0.45, 0.45, np.nan],
        "run": ["py_a", "py_b", "py_c"] * 2})
    res = {r: 1 / 38.0 for r in ("py_a", "py_b", "py_c")}
    out = st.classify_peaks(peaks, res)
    assert list(out["mechanism"]) == ["temporal"] * 3 + ["gear", "gear", "spatial"]
    np.testing.assert_allclose(out["f_temporal_hz"][:3], 13.0)


def test_match_tolerance_is_tied_to_resolution():
    gears = pd.DataFrame({"joint": [1, 3], "stage": ["motor", "motor"],
                          "order": ["mesh", "mesh"], "f_spatial_per_mm": [0.50, 0.20]})
    peaks = pd.DataFrame({"f_spatial_per_mm": [0.505, 0.23, 0.8]})
    out = st.match_peaks_to_gears(peaks, gears, tolerance_per_mm=0.5 / 40)
    assert list(out["joint"].astype(object).where(out["joint"].notna(), None)) == [1, None, None]


def test_evaluation_counts_found_missed_and_false():
    peaks = pd.DataFrame({"run": ["r1", "r1"], "direction": ["px", "px"],
                          "feed_mm_s": [2.0, 2.0],
                          "f_spatial_per_mm": [0.5, 0.3], "amplitude_um": [2.0, 1.0],
                          "mechanism": ["gear", "gear"],
                          "joint": pd.array([3, 5], dtype="Int64"),
                          "stage": ["motor", "motor"], "order": ["mesh", "mesh"]})
    planted = pd.DataFrame({"run": ["r1"] * 3, "direction": ["px"] * 3,
                            "feed_mm_s": [2.0] * 3,
                            "joint": [3, 5, 1], "stage": ["motor"] * 3,
                            "order": ["mesh"] * 3, "f_spatial_per_mm": [0.5, 0.3, 0.9],
                            "amplitude_um": [2.0, 0.001, 2.0]})
    runs = pd.DataFrame({"run": ["r1"], "resolution_per_mm": [0.025],
                         "fmin_per_mm": [0.05], "floor_um2": [1e-4]})
    ev = st.evaluate_attribution(peaks, planted, runs, threshold=25, tol_bins=0.5,
                                 fmax_per_mm=20)
    c = st.attribution_counts(ev)
    assert c["above_noise"] == 2 and c["found"] == 1 and c["missed"] == 1
    assert c["false_attributions"] == 1


def _cell_file(tiny_config, **extra):
    from robomill.io.cell import cell_mapping, parse_cell

    return parse_cell({**cell_mapping(tiny_config["cell"]), **extra}, "raw/cell.yaml")


def test_a_tracker_run_in_its_own_frame_is_refused_then_registered(tiny_config):
    """Points in the tracker's frame (3 m and 30° from the robot base) give a RawDataError that
    names the file and points at base_from_instrument; registering the frame in the cell file
    gives back exactly the base-frame analysis."""
    from robomill.io import RawDataError

    cell = cell_from_config(tiny_config)
    run = next(r for r in tracker.tracker_runs(tiny_config) if r["direction"] == "px")
    df = tracker.simulate_run(tiny_config, cell, run["direction"], run["feed_mm_s"], run["cut"],
                              sim=simulate_cut(cell, run["cut"], tiny_config))
    t, p_base = df["t_s"].to_numpy(), df[["x_mm", "y_mm", "z_mm"]].to_numpy()
    c, s = np.cos(np.pi / 6), np.sin(np.pi / 6)
    R, T = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]]), np.array([3000.0, -500.0, 100.0])
    p_tracker = (p_base - T) @ R  # p_base = R p_tracker + T
    with pytest.raises(RawDataError, match=r"^tracker/px_f2\.csv: .*not reachable by robot "
                       r"'irb1600' of raw/cell\.yaml.*base_from_instrument\.tracker"):
        st.analyse_tracker_run(t, p_tracker, _cell_file(tiny_config),
                               data_file="tracker/px_f2.csv", **ANALYSIS)
    registered = _cell_file(tiny_config, base_from_instrument={
        "tracker": {"rotation": R.tolist(), "translation_mm": T.tolist()}})
    _, spec_a, gears_a, peaks_a = st.analyse_tracker_run(
        t, p_tracker, registered, data_file="tracker/px_f2.csv", **ANALYSIS)
    _, spec_b, gears_b, peaks_b = st.analyse_run(
        t, p_base, robot=cell.robot, gears=cell.gears, tool_rotation=cell.tool_rotation(),
        q0_rad=cell.q_home_rad, **ANALYSIS)
    np.testing.assert_allclose(gears_a["f_spatial_per_mm"], gears_b["f_spatial_per_mm"],
                               rtol=1e-6, atol=1e-9)  # round-off of the registered points
    np.testing.assert_allclose(peaks_a["f_spatial_per_mm"], peaks_b["f_spatial_per_mm"],
                               rtol=1e-6)
    assert list(peaks_a["stage"].fillna("")) == list(peaks_b["stage"].fillna(""))
    assert len(peaks_a) > 0


def test_gather_profiles_gears_and_truth_check_without_truth():
    import xarray as xr

    from robomill import straightness as st

    def run(direction, feed, n):
        f = np.linspace(0, 1, n)
        attrs = {"direction": direction, "feed_mm_s": feed, "cut": f"s1_g1_{direction}",
                 "resolution_per_mm": 0.02, "length_mm": 50.0, "speed_mm_s": feed,
                 "fmin_per_mm": 0.05, "floor_um2": 1e-4}
        return xr.Dataset({"power_um2": ("f", f**2)}, coords={"f": f}, attrs=attrs)

    a, b = run("py", 2.0, 5), run("my", 4.0, 7)
    prof = st.gather_profiles([a, b], ["py_f2", "my_f4"])
    assert prof["run"].values.tolist() == ["py_f2", "my_f4"]
    assert prof["feed_mm_s"].values.tolist() == [2.0, 4.0]
    assert prof.sizes["f"] == 5 + 7 - 3  # outer join of both grids (0, 0.5, 1 shared)
    assert a.attrs["direction"] == "py"  # inputs untouched
    with pytest.raises(ValueError, match="floor_um2"):
        bad = a.copy()
        bad.attrs = {k: v for k, v in a.attrs.items() if k != "floor_um2"}
        st.gather_profiles([bad], ["py_f2"])
    gears = st.gather_gears([pd.DataFrame({"f_spatial_per_mm": [0.5], "feed_mm_s": [4.0]})])
    assert gears["f_temporal_hz"].tolist() == [2.0]
    empty = st.truth_check(None, None, None, {})
    assert list(empty.columns) == st.TRUTH_CHECK_COLUMNS and len(empty) == 0


def test_end_trim_is_capped_at_a_tenth_of_a_short_path():
    """A 40 mm run trims the full trim_mm; a 1.8 mm export (a few ms of tracker stream) keeps
    80 % of its path instead of being refused (TRIM_MAX_FRACTION)."""
    t = np.arange(1500) / 815.0
    p = np.column_stack([600 + 1.0 * t, np.zeros_like(t), 200 + 0 * t])
    prof = st.spatial_profile(t, p, ds_mm=0.01, trim_mm=1.0)
    path = t[-1] - t[0]
    assert prof.trim_mm == pytest.approx(st.TRIM_MAX_FRACTION * path)
    assert prof.length_mm == pytest.approx(0.8 * path, abs=0.011)
    t, p = _wavy_line()
    assert st.spatial_profile(t, p, ds_mm=0.01, trim_mm=1.0).trim_mm == 1.0
    with pytest.raises(ValueError, match="too short"):
        st.spatial_profile(t[:3], p[:3], ds_mm=0.01, trim_mm=1.0)


def test_gear_lines_closer_than_the_resolution_are_listed_as_candidates_and_merged():
    L = 40.0
    gears = pd.DataFrame({"joint": [2, 3, 1, 4], "stage": ["motor"] * 4,
                          "order": ["mesh", "mesh", "mesh", "runout"],
                          "f_spatial_per_mm": [0.500, 0.500 + 1.5 / L, 0.200, 0.800]})
    # a peak next to joint 2's line; joint 3's line is 1.5 bins away (beyond the 0.5-bin match
    # tolerance of the peak, within the 2-bin resolution); an isolated line; no line
    peaks = pd.DataFrame({"f_spatial_per_mm": [0.500 + 0.2 / L, 0.201, 0.65]})
    out = st.match_peaks_to_gears(peaks, gears, tolerance_per_mm=0.5 / L,
                                  resolution_per_mm=2.0 / L)
    assert out["joint"].iloc[0] == 2 and out["candidates"].iloc[0] == "2:motor:mesh;3:motor:mesh"
    assert list(out["merged"]) == [True, False, False]
    assert list(out["candidates"])[1:] == ["1:motor:mesh", ""]
    assert list(out["n_candidates"]) == [1, 1, 0]   # within the tolerance of the peak only
    assert st.parse_candidates(out["candidates"].iloc[0]) == [(2, "motor", "mesh"),
                                                              (3, "motor", "mesh")]
    # one bin resolution: the two lines are resolved, nothing merged
    one_bin = st.match_peaks_to_gears(peaks, gears, tolerance_per_mm=0.5 / L,
                                      resolution_per_mm=1.0 / L)
    assert not one_bin["merged"].any()
    # a peak classified temporal is attributed to no gear: no candidates
    peaks2 = out.assign(direction="px", feed_mm_s=[2.0, 2.0, 2.0], run="px_f2")
    res = {"px_f2": 1 / L}
    cls = st.classify_peaks(peaks2, res)
    assert list(cls["mechanism"]) == ["gear", "gear", "unclassified"]
    assert cls["merged"].iloc[0]


def _puma_cell(teeth3):
    """The examples/other_cell PUMA 560 with ``teeth3`` pinion teeth on joint 3."""
    import yaml

    from robomill.io.cell import cell_mapping, parse_cell

    root = __import__("pathlib").Path(__file__).resolve().parents[1]
    c = yaml.safe_load((root / "examples/other_cell/config.yaml").read_text())["cell"]
    c["transmissions"][2]["teeth"] = teeth3
    return parse_cell(cell_mapping(c), "cell.yaml")


def _planted_run(cell, amp_um, start=(600.0, -170.0, -200.0), length_mm=30.0, feed=2.0):
    """A -X tracker run of the example's n18k_mx_v2 cut with planted lateral sinusoids at the
    mesh lines of the joints in ``amp_um`` ({joint: amplitude}) and 0.05 µm noise."""
    start, u = np.asarray(start), np.array([-1.0, 0.0, 0.0])
    q, s = st.joint_path_for_line(cell.robot, start + u, start + (length_mm - 1) * u,
                                  cell.tool_rotation, cell.q_home_rad, 41)
    lines = st.gear_spatial_frequencies(q, s, cell.transmissions)
    mesh = lines[lines["order"] == "mesh"].set_index("joint")["f_spatial_per_mm"]
    t, sp = tracker.motion_law(length_mm, feed, 100.0, 815.0)
    dev = sum(a * np.sin(2 * np.pi * mesh[j] * sp + j) for j, a in amp_um.items())
    rng = np.random.default_rng(7)
    lat = st.perpendicular_axes(u)[0]
    p = (start + np.outer(sp, u) + 1e-3 * np.outer(dev, lat)
         + 0.05e-3 * rng.standard_normal((sp.size, 3)))
    planted = pd.DataFrame({"run": "mx_f2", "direction": "mx", "feed_mm_s": feed,
                            "joint": list(amp_um),
                            "stage": "motor", "order": "mesh",
                            "f_spatial_per_mm": [mesh[j] for j in amp_um],
                            "amplitude_um": list(amp_um.values())})
    return t, p, planted


@pytest.mark.parametrize("teeth3", [16, 22])
def test_two_joints_mesh_lines_within_a_bin_are_flagged_merged_not_missed(teeth3):
    """The example's PUMA: with 16 pinion teeth on joint 3, the joint-2 and joint-3 mesh lines
    of a 28 mm run are 1.03 bins apart and make one peak; the analysis lists both candidates
    and flags the peak merged, and the truth check counts joint 3 merged (not missed). With
    the example's 22 teeth (5.5 bins apart) both are found."""
    cell = _puma_cell(teeth3)
    t, p, planted = _planted_run(cell, {2: 2.0, 3: 1.5})
    prof, spec, _, peaks = st.analyse_tracker_run(t, p, cell, data_file="mx_f2.csv", **ANALYSIS)
    gap = np.diff(planted["f_spatial_per_mm"].to_numpy())[0] / spec.resolution_per_mm
    peaks = peaks.assign(direction="mx", feed_mm_s=2.0, mechanism="gear", run="mx_f2")
    peaks = peaks[peaks["joint"].isin([2, 3])]
    runs = pd.DataFrame({"run": ["mx_f2"],
                         "resolution_per_mm": [spec.resolution_per_mm], "fmin_per_mm": [0.05],
                         "floor_um2": [float(np.median(spec.power_um2[spec.f_per_mm > 0.05]))]})
    ev = st.evaluate_attribution(peaks, planted, runs, threshold=25, tol_bins=0.5,
                                 fmax_per_mm=20).set_index("joint")
    counts = st.attribution_counts(ev.reset_index())
    assert counts["above_noise"] == 2 and counts["missed"] == 0
    if teeth3 == 16:
        assert gap == pytest.approx(1.03, abs=0.01)
        assert len(peaks) == 1
        row = peaks.iloc[0]
        assert row["merged"] and row["joint"] == 2
        assert set(row["candidates"].split(";")) == {"2:motor:mesh", "3:motor:mesh"}
        assert ev.loc[2, "found"] and not ev.loc[3, "found"] and ev.loc[3, "merged"]
        assert ev.loc[3, "merged_into"] == "2:motor:mesh"
        assert counts["found"] == 1 and counts["merged"] == 1
    else:
        assert gap > 5
        assert len(peaks) == 2 and not peaks["merged"].any()
        assert list(peaks["candidates"]) == ["2:motor:mesh", "3:motor:mesh"]
        assert ev["found"].all() and not ev["merged"].any()
        assert counts["found"] == 2 and counts["merged"] == 0
        np.testing.assert_allclose(peaks["amplitude_um"], [2.0, 1.5], rtol=0.05)


def test_run_summary_table_rms_largest_peak_and_counts():
    """Planted: run a has a sine of amplitude 3 µm (RMS 3/√2) laterally and 1 µm vertically;
    run b is flat with one NaN sample and no peaks."""
    import xarray as xr

    from robomill.straightness import run_summary_table

    s = np.arange(400) * 0.05
    a = np.stack([3 * np.sin(2 * np.pi * s / 2.0), np.sin(2 * np.pi * s / 5.0)])
    b = np.zeros_like(a)
    b[0, 7] = np.nan
    prof = xr.Dataset({"deviation_um": (("run", "component", "s"), np.stack([a, b]))},
                      coords={"run": ["mx_f2", "d45_f6"], "component": ["lateral", "vertical"],
                              "s": s, "direction": ("run", ["mx", "d45"]),
                              "feed_mm_s": ("run", [2.0, 6.0])})
    peaks = pd.DataFrame({"run": ["mx_f2", "mx_f2", "mx_f2", "py_f2"],
                          "amplitude_um": [3.0, 1.0, 0.2, 9.0],
                          "f_spatial_per_mm": [0.5, 0.2, 1.0, 0.1],
                          "mechanism": ["gear", "gear", "temporal", "gear"]})
    t = run_summary_table(prof, peaks).set_index("run")
    assert t.loc["mx_f2", "rms_lateral_um"] == pytest.approx(3 / np.sqrt(2), rel=1e-3)
    assert t.loc["mx_f2", "rms_vertical_um"] == pytest.approx(1 / np.sqrt(2), rel=1e-2)
    assert t.loc["d45_f6", "rms_lateral_um"] == 0.0  # the NaN sample skipped
    assert t.loc["mx_f2", "largest_peak_um"] == 3.0
    assert t.loc["mx_f2", "largest_peak_wavelength_mm"] == pytest.approx(2.0)
    assert t.loc["mx_f2", "largest_peak_mechanism"] == "gear"
    assert (t.loc["mx_f2", "gear_peaks"], t.loc["mx_f2", "temporal_peaks"]) == (2, 1)
    assert np.isnan(t.loc["d45_f6", "largest_peak_um"])  # the py peak belongs to no run
    assert (t.loc["d45_f6", "gear_peaks"], t.loc["d45_f6", "temporal_peaks"]) == (0, 0)
