"""The candidate grid's own predictions at a path's stations, so that a path is scored and
refused by the same predictions as the candidates are (one set of predictions).

Each station × rotation of a cut is posed to the grid as a candidate of its own: the cut's
direction at the station's placement point on the top face
(the grid's placements lie on the top face, :mod:`robomill.plan.request`), over a cut of
:data:`STATION_CUT_MM` so that the candidate is the station's pose alone (a full-length cut
centred on an end station would reach past the slot, where the robot need not go). The
grid's public functions predict it (:func:`robomill.plan.predict.predict_grid`), flag and
widen what lies outside the study (:func:`robomill.plan.predict.apply_extrapolation`, over
the request's own speed, depth and feed grids: its widening depends on them) and check the
request's constraints (:func:`robomill.plan.choose.feasible`; a learn plan's, which leave out
the stability margin, :func:`robomill.plan.learn.learn_allowed`): a station the grid
would refuse is not feasible on the path, and the path's margin at a station is the grid's
pessimistic, widened ``stability_margin_low``. The waviness, which counts a gear line's
cycles along the whole cut, belongs to the cut, not to a station: the grid checks it on the
chosen candidate itself, whose rotations bound the middle station's
(:func:`robomill.plan.pathout.rotations_meeting_constraints`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

STATION_CUT_MM = 1e-3
"""Length of the candidate cut posed at a station [mm] (its postures are the station's)."""


def station_grid(req, measured, cell, reach, top_points_mm: np.ndarray, direction_deg: float,
                 spindle_rpm: float, depth_mm: float, feed_mm_s: float) -> dict[str, np.ndarray]:
    """Per station × rotation ``(S, R)``: the grid's ``stability_margin_low`` (NaN where the
    grid cannot predict it) and ``feasible`` (reachable and meeting every constraint)."""
    from robomill.plan.choose import feasible
    from robomill.plan.predict import apply_extrapolation, predict_grid

    sub = replace(req, placements_mm=np.asarray(top_points_mm, float).reshape(-1, 3),
                  direction_deg=np.array([float(direction_deg)]), direction_names=("path",),
                  length_mm=STATION_CUT_MM, path_stations=3)
    cand = predict_grid(sub, measured, cell)
    if reach is not None:        # widened over the request's own grids, as the candidates
        cand = apply_extrapolation(cand, sub, measured, cell, reach)
    one = {"direction": 0}
    for dim, value in (("spindle_rpm", spindle_rpm), ("depth_mm", depth_mm),
                       ("feed_mm_s", feed_mm_s)):
        one[dim] = int(np.argmin(np.abs(cand[dim].values - float(value))))
    margin = cand["stability_margin_low"]
    margin = margin.isel({d: i for d, i in one.items() if d in margin.dims})
    if sub.purpose == "learn":  # a learn cut's constraints leave out the stability margin
        from robomill.plan.learn import learn_allowed
        ok = learn_allowed(cand, sub).isel(one)
    else:
        ok = feasible(cand, sub).isel(one)
    return {"stability_margin_low": np.asarray(margin.transpose("placement", "rotation").values,
                                               float),
            "feasible": np.asarray(ok.transpose("placement", "rotation").values, bool)}
