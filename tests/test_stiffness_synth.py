"""The load-test simulator: contract format, planted truth, identification recovers it."""

import numpy as np

from robomill.io.robots import read_load_tests, read_robot_file
from robomill.io.synthetic_layout import instrument_files
from robomill.stiffness import identify_from_tests
from robomill.synth import loadtests


def test_plan_lists_robot_and_load_tests(tiny_config):
    files = instrument_files(tiny_config, "loadtests")
    kinds = {(f["kind"], f["robot"]) for f in files}
    assert {("robot", "kr360"), ("stiffness", "kr360"), ("robot", "irb1600"),
            ("stiffness", "irb1600")} <= kinds


def test_simulated_files_round_trip_and_recover_truth(config, tmp_path):
    tiny_config = config  # the default 53-pose KR360 test plan of Yi 2025
    entry = loadtests.robot_entry(tiny_config, "kr360")
    loadtests.write_robot_file(tiny_config, "kr360", tmp_path / "kr360.yaml")
    loadtests.write_load_tests(tiny_config, "kr360", tmp_path / "lt.csv")
    robot, _ = read_robot_file(tmp_path / "kr360.yaml")
    df = read_load_tests(tmp_path / "lt.csv", robot.n_joints)
    assert (df["role"] == "validate").sum() == entry["validate"]["count"]
    assert (df["pose"].str.startswith("plane")).sum() == entry["plane"]["count"]
    out = identify_from_tests(robot, df)
    js = out["joint_stiffness"]
    k = np.asarray(entry["k_Nm_rad"])
    assert js["observable"].all()
    inside = (js["ci95_low_Nm_rad"] <= k) & (k <= js["ci95_high_Nm_rad"])
    assert inside.all()
    clean = loadtests.simulate_load_tests(tiny_config, "kr360", noise=False)
    exact = identify_from_tests(robot, clean)["joint_stiffness"]
    assert np.allclose(exact["k_Nm_rad"], k, rtol=1e-6)
    truth = loadtests.truth(tiny_config, None)
    assert np.allclose(truth["stiffness_k_Nm_rad"].sel(stiffness_robot="kr360"), k)
