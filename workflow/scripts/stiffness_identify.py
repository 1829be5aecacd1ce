"""Joint-stiffness identification of one robot from its load tests [Yi 2025, §3]."""

from robomill.io import write_table
from robomill.io.robots import read_load_tests, read_robot_file
from robomill.pipeline.runlog import setup
from robomill.stiffness.identify import identify_from_tests
from robomill.study import load_study

log = setup(snakemake.log[0], "stiffness")
manifest = load_study(snakemake.input.study)
manifest.verify_file(snakemake.params.robot_rel)
manifest.verify_file(snakemake.params.tests_rel)
robot, _ = read_robot_file(snakemake.input.robot)
tests = read_load_tests(snakemake.input.tests, robot.n_joints)
opts = snakemake.params.options
out = identify_from_tests(robot, tests, rtol=opts["null_rtol"], level=opts["level"])
for _, row in out["models"].iterrows():
    log.info("model %s: %d poses, condition number %.3g, residual %.3g um", row["model"],
             row["n_poses"], row["condition_number"], row["residual_rms_um"])
    for msg in filter(None, str(row["warnings"]).split(" | ")):
        log.warning("%s (model %s): %s", snakemake.params.robot, row["model"], msg)
write_table(out["joint_stiffness"], snakemake.output.joints)
write_table(out["models"], snakemake.output.models)
write_table(out["validation"], snakemake.output.validation)
