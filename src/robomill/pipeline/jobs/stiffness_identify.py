"""Joint-stiffness identification of one robot from its load tests [Yi 2025, §3].

The job of the rule script ``workflow/scripts/stiffness_identify.py``."""

from __future__ import annotations

import logging

from robomill.io import write_table
from robomill.io.robots import read_load_tests, read_robot_file
from robomill.stiffness.identify import identify_from_tests
from robomill.study import load_study


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    manifest = load_study(inputs.study)
    manifest.verify_file(params.robot_rel)
    manifest.verify_file(params.tests_rel)
    robot, _ = read_robot_file(inputs.robot)
    tests = read_load_tests(inputs.tests, robot.n_joints)
    opts = params.options
    out = identify_from_tests(robot, tests, rtol=opts["null_rtol"], level=opts["level"])
    for _, row in out["models"].iterrows():
        log.info("model %s: %d poses, condition number %.3g, residual %.3g um", row["model"],
                 row["n_poses"], row["condition_number"], row["residual_rms_um"])
        for msg in filter(None, str(row["warnings"]).split(" | ")):
            log.warning("%s (model %s): %s", params.robot, row["model"], msg)
    write_table(out["joint_stiffness"], outputs.joints)
    write_table(out["models"], outputs.models)
    write_table(out["validation"], outputs.validation)
