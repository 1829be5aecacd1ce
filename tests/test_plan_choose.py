"""The plan's choice (robomill.plan.choose): constraints decide between the stiffest and the
most stable pose, infeasible requests name the binding constraint in one line, the Pareto front
and the smooth redundancy angle."""

import numpy as np
import pytest
import xarray as xr

from robomill.plan.choose import (
    PlanInfeasible,
    check_needs,
    choose,
    pareto_front,
)
from robomill.plan.predict import form_error
from robomill.plan.request import parse_request

DEPTHS = np.array([0.1, 0.2, 0.3, 0.4, 0.5])
FEEDS = np.array([2.0])
RPM = np.array([20000.0])


def request(**constraints):
    return parse_request({
        "kind": "plan", "operation": {"length_mm": 40, "directions": ["px"]},
        "tool": {"diameter_mm": 6, "flutes": 2},
        "placement": {"points_mm": [[600, 0, 200], [700, 0, 200], [650, 0, 200]]},
        "spindle_rpm": RPM.tolist(), "depth_mm": DEPTHS.tolist(), "feed_mm_s": FEEDS.tolist(),
        "constraints": constraints}, "planted.yaml")


def planted(a_crit_mm, defl_um_per_mm, reachable=(True, True, True)):
    """Candidates of three placements with a given critical depth and a deflection
    proportional to depth (the truth written by hand, not by the predictor)."""
    P = len(a_crit_mm)
    dims = ("placement", "rotation", "direction", "spindle_rpm", "depth_mm", "feed_mm_s")
    a = np.asarray(a_crit_mm, float).reshape(P, 1, 1, 1)
    margin = (a[..., None, None] / DEPTHS[None, None, None, None, :, None] - 1)
    margin = np.broadcast_to(margin, (P, 1, 1, 1, len(DEPTHS), 1))
    defl = (np.asarray(defl_um_per_mm, float).reshape(P, 1, 1, 1, 1, 1)
            * DEPTHS.reshape(1, 1, 1, 1, -1, 1)) * np.ones((P, 1, 1, 1, len(DEPTHS), 1))
    zero = np.zeros((P, 1, 1))
    ds = xr.Dataset(
        {"reachable": (("placement", "rotation", "direction"),
                       np.asarray(reachable).reshape(P, 1, 1)),
         "a_crit_low_mm": (dims[:4], a),
         "stability_margin_low": (dims, margin),
         "deflection_normal_um": (dims, defl), "deflection_normal_high_um": (dims, defl),
         "deflection_axial_high_um": (dims, 0 * defl),
         "waviness_um": (dims[:3], zero), "waviness_ident_high_um": (dims[:3], zero),
         "force_high_N": (dims[3:], np.ones((1, len(DEPTHS), 1))),
         "feed_mark_um": (("spindle_rpm", "feed_mm_s"), np.zeros((1, 1))),
         "mrr_mm3_s": (("depth_mm", "feed_mm_s"), DEPTHS[:, None] * 6 * FEEDS[None])},
        coords={"placement": np.arange(P),
                "placement_x_mm": ("placement", 600.0 + 50 * np.arange(P)),
                "placement_y_mm": ("placement", np.zeros(P)),
                "placement_z_mm": ("placement", np.full(P, 200.0)),
                "rotation": [0.0], "direction": ["px"], "direction_deg": ("direction", [0.0]),
                "spindle_rpm": RPM, "depth_mm": DEPTHS, "feed_mm_s": FEEDS})
    return form_error(ds)


# placement 0: the stiffest (least normal deflection per mm of depth) but the least stable;
# placement 1: the most stable but the most compliant; placement 2: between.
A_CRIT = [0.25, 1.0, 0.5]          # mm
DEFL = [20.0, 80.0, 40.0]          # um per mm of depth


def test_stiffest_and_most_stable_differ_and_constraints_decide():
    ds = planted(A_CRIT, DEFL)
    stiffest = int(np.argmin(DEFL))
    most_stable = int(np.argmax(A_CRIT))
    assert stiffest != most_stable
    # tight deflection: the stiff pose wins (placement 0 at 0.2 mm; the stable one only 0.1 mm)
    chosen, _ = choose(ds, request(min_stability_margin=0.2, max_deflection_normal_um=10))
    assert (chosen.loc[0, "placement"], chosen.loc[0, "depth_mm"]) == (0, 0.2)
    # loose deflection: the stable pose wins at the deepest cut
    chosen, _ = choose(ds, request(min_stability_margin=0.2, max_deflection_normal_um=50))
    assert (chosen.loc[0, "placement"], chosen.loc[0, "depth_mm"]) == (1, 0.5)
    # in between: the pose that is neither the stiffest nor the most stable wins
    chosen, _ = choose(ds, request(min_stability_margin=0.2, max_deflection_normal_um=12))
    assert chosen.loc[0, "placement"] not in (stiffest, most_stable)
    assert (chosen.loc[0, "placement"], chosen.loc[0, "depth_mm"]) == (2, 0.3)


def test_no_reachable_placement_is_one_line():
    ds = planted(A_CRIT, DEFL, reachable=(False, False, False))
    with pytest.raises(PlanInfeasible, match=r"^no reachable placement: none of the 3 "
                       r"placements") as e:
        choose(ds, request(min_stability_margin=0.2))
    assert "\n" not in str(e.value)


def test_no_stable_speed_names_the_margin():
    ds = planted(A_CRIT, DEFL)
    with pytest.raises(PlanInfeasible, match=r"^no stable speed in range: the largest "
                       r"pessimistic critical depth .* is 1 mm") as e:
        choose(ds, request(min_stability_margin=20.0))
    assert "constraints.min_stability_margin 20" in str(e.value)


def test_binding_deflection_is_named_with_its_best_value():
    ds = planted(A_CRIT, DEFL)
    with pytest.raises(PlanInfeasible, match=r"constraints.max_deflection_normal_um binds: .* "
                       r"is 2, the limit is 1$"):
        choose(ds, request(min_stability_margin=0.2, max_deflection_normal_um=1.0))


def test_missing_measurement_needed_by_a_constraint_refuses():
    req = request(max_waviness_um=5.0)
    with pytest.raises(PlanInfeasible, match=r"constraints.max_waviness_um needs the waviness "
                       r"prediction: no tracker runs"):
        check_needs(req, {"waviness": "no tracker runs with gear lines (x)"})
    check_needs(request(min_stability_margin=0.1), {"waviness": "no tracker runs"})  # fine


def test_pareto_front_keeps_only_non_dominated_points():
    mrr = np.array([30, 24, 18, 12, 24])
    err = np.array([8.0, 9.0, 5.0, 6.0, 4.0])
    # (24, 9) is dominated by (24, 4); (12, 6) by (18, 5) and (24, 4)
    assert list(pareto_front(mrr, err)) == [0, 4]



def test_min_feed_per_tooth_and_the_line_for_fewer_cuts():
    """The feed per tooth here is 2·60/(2·20000) = 0.003 mm: a minimum of 0.01 mm refuses
    every candidate, in one line naming the constraint; 0.001 mm keeps them. With the
    critical depth at 0.25 mm and a margin of 0.2, only the depths 0.1 and 0.2 remain: fewer
    cuts than n_cuts, and the line says the stability margin binds the larger removal rates."""
    ds = planted([0.25, 0.25, 0.25], [10.0, 10.0, 10.0])
    ds["feed_per_tooth_mm"] = (("spindle_rpm", "feed_mm_s"),
                               FEEDS[None] * 60 / (2 * RPM[:, None]))
    with pytest.raises(PlanInfeasible) as e:
        choose(ds, request(min_feed_per_tooth_mm=0.01, min_p_stable=None))
    assert "min_feed_per_tooth_mm" in str(e.value) and "\n" not in str(e.value)
    chosen, _ = choose(ds, request(min_feed_per_tooth_mm=0.001, min_p_stable=None,
                                   min_stability_margin=0.2))
    assert len(chosen) < 5
    line = ds.attrs["shortfall"]
    assert line.startswith(f"{len(chosen)} of n_cuts 5 planned")
    assert "constraints.min_stability_margin" in line and "\n" not in line
