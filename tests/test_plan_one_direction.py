"""An impact test that measured one direction (robomill.plan.extrapolation,
robomill.plan.tooltip): the plan uses the modes of the measured axis, stays finite, and flags
every candidate whose cut frame has a component along an unmeasured axis, naming the axes."""

import numpy as np
import pandas as pd
import pytest
from plan_cell import coefficients, default_cell

from robomill.plan.choose import choose
from robomill.plan.extrapolation import (
    AXIS_BITS,
    StudyReach,
    axes_not_measured,
    direction_axis_bits,
    reach_from_means,
    reason_text,
)
from robomill.plan.measured import Measured
from robomill.plan.predict import apply_extrapolation, predict_grid
from robomill.plan.request import parse_request

PREDICTIONS = ("a_crit_mm", "a_crit_low_mm", "a_crit_high_mm", "deflection_normal_um",
               "deflection_axial_um", "force_N", "stability_margin_low")


@pytest.fixture(scope="module")
def cell():
    return default_cell()


def _coefficients():
    return coefficients()


def _modes(shape_y, shape_z):
    # two modes with an X component; Y and Z as given (NaN: that axis was not measured)
    return pd.DataFrame({"f_n_hz": [40.0, 90.0], "zeta": [0.04, 0.03],
                         "k_modal_N_m": [1.0e6, 2.0e6], "shape_x": [0.8, 0.6],
                         "shape_y": shape_y, "shape_z": shape_z,
                         "f_n_hz_low": [39.8, 89.5], "f_n_hz_high": [40.2, 90.5],
                         "zeta_low": [0.038, 0.028], "zeta_high": [0.042, 0.032],
                         "k_modal_N_m_low": [0.97e6, 1.94e6],
                         "k_modal_N_m_high": [1.03e6, 2.06e6]})


def _request():
    return parse_request({"kind": "plan", "operation": {"length_mm": 20, "directions": ["px"]},
                          "tool": {"diameter_mm": 6, "flutes": 2},
                          "placement": {"points_mm": [[650, 0, 200]]},
                          "spindle_rpm": {"min": 2000, "max": 12000, "n": 21},
                          "depth_mm": [0.05, 0.5], "feed_mm_s": [1, 4]})


def _plan(cell, modes, reach):
    req = _request()
    m = Measured(modes=modes, coefficients=_coefficients())
    return req, apply_extrapolation(predict_grid(req, m, cell), req, m, cell, reach)


def test_the_unmeasured_axes_are_read_from_the_empty_shape_columns():
    assert axes_not_measured(_modes([np.nan] * 2, [np.nan] * 2)) == "YZ"
    assert axes_not_measured(_modes([0.6, 0.8], [0.0, 0.0])) == ""
    assert axes_not_measured(_modes([0.6, np.nan], [np.nan] * 2)) == "Z"
    assert axes_not_measured(None) == ""
    assert reach_from_means(None, {}, not_measured="YZ").axes_not_measured == "YZ"


def test_feeding_along_x_with_only_x_measured_is_flagged_and_stays_finite(cell):
    modes = _modes([np.nan] * 2, [np.nan] * 2)
    req, ds = _plan(cell, modes, StudyReach(axes_not_measured=axes_not_measured(modes)))
    assert bool(ds["reachable"].all())
    # fed along X: the wall normal is Y, the tool axis Z: both carry force, neither measured
    code = ds["extrapolation_code"].values
    assert ds["extrapolation_code"].dims == ("placement", "direction", "spindle_rpm",
                                             "feed_mm_s")
    assert np.all(code & AXIS_BITS["Y"]) and np.all(code & AXIS_BITS["Z"])
    assert not np.any(code & AXIS_BITS["X"])
    assert bool(ds["extrapolation"].all())
    assert {reason_text(int(c)) for c in code.ravel()} == {"direction not measured: Y, Z"}
    for name in PREDICTIONS:
        assert np.isfinite(ds[name].values).all(), name
    # nothing widens for an unmeasured axis: no distance from the evidence along it
    assert np.all(ds["interval_widening"].values == 1.0)
    chosen, _ = choose(ds, req)
    assert len(chosen) and set(chosen["extrapolation_reason"]) == \
        {"direction not measured: Y, Z"}


def test_an_unmeasured_axis_carries_no_identified_mode(cell):
    # the same predictions as modes whose shapes are zero along Y and Z: the shapes
    # restricted to the measured axis, not a NaN that poisons the model
    _, unmeasured = _plan(cell, _modes([np.nan] * 2, [np.nan] * 2), StudyReach())
    _, restricted = _plan(cell, _modes([0.0, 0.0], [0.0, 0.0]), StudyReach())
    for name in PREDICTIONS:
        np.testing.assert_allclose(unmeasured[name].values, restricted[name].values,
                                   rtol=1e-12, err_msg=name)


def test_every_axis_measured_adds_no_flag(cell):
    modes = _modes([0.6, 0.8], [0.0, 0.0])
    reach = StudyReach(axes_not_measured=axes_not_measured(modes))
    _, ds = _plan(cell, modes, reach)
    assert ds["extrapolation_code"].dims == ("placement", "spindle_rpm", "feed_mm_s")
    assert not bool(ds["extrapolation"].any())
    assert "direction not measured" not in reason_text(int(np.bitwise_or.reduce(
        ds["extrapolation_code"].values.ravel())))


def test_the_bits_follow_the_cut_frame():
    # fed along Y the wall normal is X: with only Y and Z measured, X is named
    assert int(direction_axis_bits([90.0], "X")[0]) == AXIS_BITS["X"]
    # a diagonal feed touches X and Y; every cut frame holds the tool axis Z
    assert int(direction_axis_bits([45.0], "XYZ")[0]) == 32 | 64 | 128
    assert int(direction_axis_bits([0.0], "")[0]) == 0
    assert reason_text(1 | 64 | 128) == "spindle speed; direction not measured: Y, Z"
