"""A study cut as a planning candidate: the one adapter between the study
(:class:`robomill.study.StudyCut`, its process as the ingestion rule resolved it) and the
planner's models.

A candidate is one point of the planner's design space: a place, a feed direction, a
rotation about the tool axis, a spindle speed, a depth and a feed, with the tool and the
engagement it is cut with. The planner predicts candidates on a
grid (:func:`robomill.plan.predict.predict_grid`); :meth:`Candidate.grid` is the grid of one
candidate: the request's model settings (stability prior, interval level, extrapolation)
with every axis of the design space reduced to the candidate's own value. Nothing here
resolves a cut's process: the values are the study's (:func:`study_candidate`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from robomill.experiment import Cut, cut_endpoints_mm, cut_redundancy_deg
from robomill.plan.request import PlanRequest

if TYPE_CHECKING:  # robomill.study reads the manifest: imported where a cut needs resolving
    from robomill.study import StudyCut

MILLING = ("slot", "up", "down")
"""The engagements the planner's force and stability models know."""


@dataclass(frozen=True)
class Candidate:
    """One cut as the planner predicts it: ``id``; the midpoint of its path in the robot base
    frame ``placement_mm`` [mm] and its length ``length_mm``; the feed direction
    ``direction_deg`` in the base XY plane; the rotation about the tool axis
    ``rotation_deg`` (0: the cell's tool orientation); ``spindle_rpm``, ``depth_mm``,
    ``feed_mm_s``; the tool (``flutes``, ``tool_diameter_mm``: None, the request's) and the
    engagement (``radial_immersion``, ``milling``: one of :data:`MILLING`)."""

    id: str
    placement_mm: tuple[float, float, float]
    length_mm: float
    direction_deg: float
    rotation_deg: float
    spindle_rpm: float
    depth_mm: float
    feed_mm_s: float
    flutes: int
    tool_diameter_mm: float | None
    radial_immersion: float
    milling: str

    def grid(self, req: PlanRequest) -> PlanRequest:
        """The planner's grid of this one candidate: ``req``'s model settings, every axis
        of the design space the candidate's own value. The cut was cut, so its pose counts
        whatever the request's pose margins (``joint_limit_margin_deg`` and
        ``min_wrist_angle_deg`` 0 here; the caller judges the margins against ``req``)."""
        return replace(req, milling=self.milling, radial_immersion=self.radial_immersion,
                       length_mm=self.length_mm, direction_deg=np.array([self.direction_deg]),
                       direction_names=(self.id,),
                       tool_diameter_mm=(self.tool_diameter_mm or req.tool_diameter_mm),
                       flutes=self.flutes,
                       placements_mm=np.asarray(self.placement_mm, float)[None],
                       rotations_deg=np.array([self.rotation_deg]),
                       spindle_rpm=np.array([self.spindle_rpm]),
                       depth_mm=np.array([self.depth_mm]),
                       feed_mm_s=np.array([self.feed_mm_s]), path_stations=3,
                       joint_limit_margin_deg=0.0, min_wrist_angle_deg=0.0)


def study_candidate(cut: StudyCut | Cut, experiment: Mapping[str, Any]) -> Candidate:
    """The planning candidate of a study cut: its resolved process as it is (speed, flutes,
    tool, immersion, milling, feed direction), its place from the study's geometry
    (:func:`robomill.experiment.cut_endpoints_mm`) and its rotation about the tool axis.
    A :class:`~robomill.experiment.Cut` that no ingestion resolved (a cut list) is resolved
    once, as the ingestion rule resolves the study's (:func:`robomill.study.study_cut`).

    Raises
    ------
    ValueError
        One line naming the cut when the study gives no spindle speed or flutes for it.
    """
    if isinstance(cut, Cut):  # a cut no ingestion saw (robomill predict's list)
        from robomill.study import study_cut

        sc = study_cut(cut, experiment)
    else:
        sc = cut
    if sc.spindle_rpm is None or sc.flutes is None:
        raise ValueError(f"cut {sc.id}: no spindle_rpm or flutes (neither the cut's nor the "
                         "experiment's): the planner cannot predict it")
    a, b = cut_endpoints_mm(sc.cut, experiment)
    return Candidate(
        id=sc.id, placement_mm=tuple(float(x) for x in (a + b) / 2),
        length_mm=float(np.linalg.norm(b - a)), direction_deg=float(sc.direction_deg),
        rotation_deg=cut_redundancy_deg(sc.cut), spindle_rpm=float(sc.spindle_rpm),
        depth_mm=float(sc.depth_mm), feed_mm_s=float(sc.feed_mm_s), flutes=int(sc.flutes),
        tool_diameter_mm=(None if sc.tool_diameter_mm is None
                          else float(sc.tool_diameter_mm)),
        radial_immersion=float(sc.radial_immersion),
        milling=sc.milling if sc.milling in MILLING else "slot")
