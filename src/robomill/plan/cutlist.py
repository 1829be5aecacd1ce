"""Any list of cuts predicted from a study (``robomill predict STUDY CUTS``): read the cuts
(CSV or YAML, the manifest's cut keys), predict each at its own pose, speed, depth and feed
with the plan's code (:func:`robomill.plan.compare.predict_study_cut`, the stability model
weighted by the study's verdicts), one row per cut. Each listed cut becomes a planning
candidate through the plan's one adapter (:func:`robomill.plan.candidate.study_candidate`),
its process resolved once as the ingestion rule resolves a study's cuts
(:func:`robomill.study.study_cut`).

The cut list is read by :mod:`robomill.io.cutlist` (CSV or YAML, the manifest's cut keys; a
bad entry is one line naming the file, the cut and the key).
"""

from __future__ import annotations

import pandas as pd

PREDICT_COLUMNS = ("cut", "spindle_rpm", "depth_mm", "feed_mm_s", "feed_per_tooth_mm",
                   "reachable", "p_stable", "a_crit_mm", "a_crit_low_mm", "a_crit_high_mm",
                   "stability_margin", "force_N", "force_low_N", "force_high_N",
                   "deflection_normal_um", "deflection_normal_low_um",
                   "deflection_normal_high_um", "deflection_axial_um",
                   "deflection_axial_low_um", "deflection_axial_high_um", "waviness_um",
                   "waviness_low_um", "waviness_high_um", "extrapolation",
                   "extrapolation_reason", "pose_note")
"""Columns of ``robomill predict``'s table."""


def predict_table(inputs, cuts: list) -> pd.DataFrame:
    """One row per cut (:data:`PREDICT_COLUMNS`): the plan's predictions at the cut's own pose
    and process (:func:`robomill.plan.compare.predict_study_cut`), the stability model
    weighted by the study's verdicts as in the plan."""
    from robomill.plan.compare import predict_study_cut
    from robomill.plan.make import verdict_conditioned

    measured = verdict_conditioned(inputs.measured, inputs.req, inputs.cell,
                                   inputs.study_cuts, inputs.experiment, inputs.stability)[0]
    rows = [predict_study_cut(cut, inputs.experiment, inputs.req, measured, inputs.cell,
                              inputs.reach) for cut in cuts]
    t = pd.DataFrame(rows)
    return t.reindex(columns=list(PREDICT_COLUMNS))
