"""The next experiment runs in its own folder (deliver item 4): the configuration the
plan writes (results/plan/next/config.yaml) names a run folder under results/plan/next, so
`snakemake all --configfile results/plan/next/config.yaml` leaves the study's results as they
are, and plan_check puts the outcomes of that run beside the predictions."""

import subprocess
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
import yaml
from conftest import REPO, SNAKEMAKE

from robomill.errors import ConfigError
from robomill.pipeline.config import check_run_folder, run_folder
from robomill.plan.check import RunOutcomes, check_table
from robomill.plan.outputs import NEXT_RUN_DIR, next_config

CUT = {"feed_mm_s": 10.0, "depth_mm": 0.2, "direction": "px", "spindle_rpm": 28000.0,
       "flutes": 2, "tool_diameter_mm": 6.0, "radial_immersion": 1.0, "milling": "slot",
       "start_mm": [580.0, -50.0, 200.0]}
MANIFEST = {"experiment": {"spindle_rpm": 28000.0, "flutes": 2, "tool_diameter_mm": 6.0,
                           "cut_length_mm": 40.0},
            "cuts": [{"id": "plan_01", **CUT}, {"id": "plan_02", **CUT, "depth_mm": 0.1}],
            "files": [], "plan": {"cuts": {}}}


def test_the_next_config_names_its_own_run_folder_inside_the_plan():
    cfg = next_config(MANIFEST)
    assert cfg["workdir"] == NEXT_RUN_DIR
    folder = Path(cfg["workdir"])
    assert not folder.is_absolute()
    assert folder.parts[:3] == ("results", "plan", "next") and len(folder.parts) > 3
    assert [c["id"] for c in cfg["experiment"]["cuts"]] == ["plan_01", "plan_02"]
    # each planned cut tracked on its own, loaded and in the air
    assert cfg["synth"] == {"tracker": {"per_cut": True, "air_pass": True,
                                        "directions": ["px"], "feeds_mm_s": None},
                            "recordings": {"vibration": True}}


def test_the_next_runs_cell_is_the_studys_wherever_its_cuts_lie():
    """A study that does not say where its impact test was made has its cell's modes planted
    at the centre of its cuts; the next run's cuts lie elsewhere, so its configuration pins
    the point its impact files state, and the next run's arm is the study's arm: the same
    modes at the same posture. Without the point, the same cuts would shake another arm."""
    import copy

    from snakemake.utils import update_config

    from robomill.io.synthetic_layout import impact_tcp_mm, synthetic_cuts
    from robomill.pipeline.config import load_config
    from robomill.synth.cell import cell_from_config
    from robomill.synth.structure import modes_at

    study = load_config(REPO / ".test" / "config.yaml")
    assert study["synth"]["process"]["reference_point_mm"] is None
    tcp = impact_tcp_mm(study)

    def next_run(pinned: bool) -> dict:
        overlay = next_config(MANIFEST, impact_tcp_mm=np.array(tcp) if pinned else None)
        overlay.pop("workdir")
        cfg = copy.deepcopy(study)
        update_config(cfg, overlay)
        return cfg

    pinned = next_run(True)
    assert pinned["synth"]["process"]["reference_point_mm"] == tcp
    assert pinned["synth"]["process"]["servo_force_N"] == study["synth"]["process"][
        "servo_force_N"]                          # merged key by key, the rest is the study's
    cut = synthetic_cuts(pinned)[0]
    cell = cell_from_config(pinned)
    q = cell.joint_path_rad(cut, np.array([20.0]))[0]

    def modes(cfg):
        return np.array([(m.f_hz, m.k_N_m) for m in modes_at(cell_from_config(cfg), q)])

    np.testing.assert_allclose(modes(pinned), modes(study), rtol=1e-12)
    moved = modes(next_run(False))
    assert np.max(np.abs(moved[:, 1] / modes(study)[:, 1] - 1.0)) > 0.05


def test_per_cut_tracking_gives_each_cut_its_own_run():
    """Two planned cuts at one direction and feed: one tracker run each, keyed by the cut's
    id (manifest key run), where one run per direction and feed would follow the last only."""
    from snakemake.utils import update_config

    from robomill.experiment import tracker_run
    from robomill.io.synthetic_layout import instrument_files
    from robomill.pipeline.config import load_config

    base = load_config(REPO / "config.yaml")
    overlay = next_config(MANIFEST)
    overlay.pop("workdir")
    shared = instrument_files({**base, "experiment": overlay["experiment"]}, "tracker")
    assert [f["cut"] for f in shared] == ["plan_02"] and "run" not in shared[0]
    # a study whose tracker followed other directions and feeds only (as the tiny test
    # study's px-only runs): the planned cuts are tracked all the same
    base["synth"]["tracker"].update({"directions": ["my"], "feeds_mm_s": [1.0]})
    update_config(base, overlay)
    own = instrument_files(base, "tracker")
    assert [(f["cut"], tracker_run(f), f["path"], f["pass"]) for f in own] == [
        ("plan_01", "plan_01", "tracker/plan_01.csv", "loaded"),
        ("plan_01", "plan_01_air", "tracker/plan_01_air.csv", "air"),
        ("plan_02", "plan_02", "tracker/plan_02.csv", "loaded"),
        ("plan_02", "plan_02_air", "tracker/plan_02_air.csv", "air")]
    # the manifest of the planned cuts' files reads them as the contract says
    from robomill.experiment import tracker_pass_pairs
    from robomill.io.manifest import parse_manifest
    from robomill.io.synthetic_layout import synthetic_manifest

    m = parse_manifest(synthetic_manifest(base), "next", require_sha256=False)
    runs = {tracker_run(f): f for f in m.files if f["kind"] == "tracker"}
    assert tracker_pass_pairs(runs) == [
        {"cut": "plan_01", "loaded_run": "plan_01", "air_run": "plan_01_air"},
        {"cut": "plan_02", "loaded_run": "plan_02", "air_run": "plan_02_air"}]


def test_run_folder_keeps_a_relative_raw_folder_where_it_was(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert run_folder({"data": {"source": "raw", "raw_dir": "lab"}}) is None
    cfg = {"workdir": "results/plan/next/run", "data": {"source": "raw", "raw_dir": "lab"}}
    assert run_folder(cfg) == "results/plan/next/run"
    assert cfg["data"]["raw_dir"] == str(tmp_path / "lab")


def _tree(folder: Path) -> dict[str, float]:
    return {str(p.relative_to(folder)): p.stat().st_mtime_ns for p in folder.rglob("*")
            if p.is_file()}


def _next_study(tmp_path: Path) -> Path:
    """A study folder with results and the plan's next-run configuration."""
    study = tmp_path / "study"
    (study / "results" / "plan" / "next").mkdir(parents=True)
    (study / "results" / "forces").mkdir()
    (study / "results" / "forces" / "mean_forces.csv").write_text("cut,Fx_N,Fy_N,Fz_N\n")
    nxt = study / "results" / "plan" / "next" / "config.yaml"
    nxt.write_text(yaml.safe_dump(next_config(MANIFEST), sort_keys=False))
    return study


@pytest.mark.parametrize("directory", [True, False], ids=["--directory", "cwd"])
def test_a_dry_run_of_the_next_experiment_targets_its_run_folder_only(tmp_path, directory):
    """`snakemake -n all --configfile results/plan/next/config.yaml` in a study folder (or
    with `--directory` the run's own folder): the jobs are planned in results/plan/next/run
    (its own .snakemake, its synthetic raw folder), nothing else of the study's results/ is
    touched."""
    study = _next_study(tmp_path)
    nxt = study / "results" / "plan" / "next" / "config.yaml"
    before = _tree(study / "results")
    cmd = [SNAKEMAKE, "-s", str(REPO / "Snakefile"), *(["--directory", str(study / NEXT_RUN_DIR)]
                                                        if directory else []),
           "--configfile", str(REPO / ".test" / "config.yaml"),
           str(nxt) if directory else "results/plan/next/config.yaml", "-n", "all"]
    proc = subprocess.run(cmd, cwd=study, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    run = study / NEXT_RUN_DIR
    assert (run / ".snakemake").is_dir()
    assert not (run / NEXT_RUN_DIR).exists()     # not a run folder inside the run folder
    # the planned cuts' synthetic raw files are outputs of this run (in its folder)
    assert "results/synthetic/raw/forces/plan_01." in proc.stdout
    assert "results/synthetic/raw/forces/s1_g1" not in proc.stdout  # the study's cuts: none
    after = {k: v for k, v in _tree(study / "results").items()
             if not k.startswith(NEXT_RUN_DIR.removeprefix("results/"))}
    assert after == before                      # the study's results untouched


def test_the_next_experiment_under_the_studys_directory_stops_before_writing(tmp_path):
    """`--directory STUDY` overrides Snakemake's workdir directive: the run would write the
    planned cuts' results over the study's, so it stops with one line naming both ways."""
    study = _next_study(tmp_path)
    before = _tree(study)
    cmd = [SNAKEMAKE, "-s", str(REPO / "Snakefile"), "--directory", str(study),
           "--configfile", str(REPO / ".test" / "config.yaml"),
           str(study / "results" / "plan" / "next" / "config.yaml"), "-n", "all"]
    proc = subprocess.run(cmd, cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 1
    line = [ln for ln in proc.stderr.splitlines() if ln.startswith("robomill:")]
    assert len(line) == 1 and "Traceback" not in proc.stderr, proc.stderr[-2000:]
    assert "'workdir'" in line[0] and f"--directory {study / NEXT_RUN_DIR}" in line[0]
    assert {k: v for k, v in _tree(study).items() if not k.startswith(".snakemake")} == before


def test_check_run_folder_accepts_the_entered_folder_or_a_directory_that_is_it(tmp_path):
    run = tmp_path / NEXT_RUN_DIR
    run.mkdir(parents=True)
    check_run_folder(NEXT_RUN_DIR, tmp_path, run)             # the directive entered it
    check_run_folder(NEXT_RUN_DIR, run, run)                  # --directory the run folder
    check_run_folder(str(run), tmp_path, run)                 # an absolute folder
    with pytest.raises(ConfigError, match="workdir"):
        check_run_folder(NEXT_RUN_DIR, tmp_path, tmp_path)    # --directory the study
    with pytest.raises(ConfigError, match="workdir"):
        check_run_folder(NEXT_RUN_DIR, tmp_path / "results", tmp_path / "results")


PRED = pd.DataFrame({
    "cut": ["plan_01", "plan_02", "s1"],
    "stability_margin": [0.8, 0.5, 0.1], "stability_margin_low": [0.6, 0.3, -0.1],
    "stability_margin_high": [1.0, 0.7, 0.3],
    "force_N": [15.0, 12.0, 7.0], "force_low_N": [14.0, 11.0, 6.0],
    "force_high_N": [16.0, 13.0, 8.0],
    "waviness_um": [1.0, 1.0, np.nan], "waviness_low_um": [0.8, 0.8, np.nan],
    "waviness_high_um": [1.2, 1.2, np.nan]})
NEXT_GEARS = pd.DataFrame({"run": ["r1", "r1", "r2", "r2", "a1", "a1"],
                           "cut": ["plan_01", "plan_01", "plan_02", "plan_02", "plan_01",
                                   "plan_01"],
                           "joint": [2, 3, 2, 3, 2, 3], "stage": "motor", "order": "mesh",
                           "f_spatial_per_mm": [0.3, 0.5, 0.3, 0.5, 0.3, 0.5]})
NEXT = RunOutcomes(
    NEXT_RUN_DIR,
    mean_forces=pd.DataFrame({"cut": ["plan_01", "plan_02"], "Fx_N": [0.0, 0.0],
                              "Fy_N": [15.5, 12.0], "Fz_N": [0.0, 0.0]}),
    force_peaks=pd.DataFrame({"cut": ["plan_01", "plan_02"], "dominant_power": [4.0, 4.0]}),
    # tracker spectra of the planned runs: plan_01 has lateral lines 0.5 and 0.6 µm at the
    # two predicted gear lines, plan_02 only a 9 µm vertical line there (lateral 0); a1 is
    # plan_01's air pass (5 µm lines: not the wall the cut left, not read)
    run_gears=NEXT_GEARS,
    profiles=xr.Dataset(
        {"amplitude_um": (("run", "component", "f"),
                          [[[0, 0, 0.5, 0, 0.6, 0], [0] * 6],
                           [[0] * 6, [0, 0, 0, 0, 9.0, 0]],
                           [[0, 0, 5.0, 0, 5.0, 0], [0] * 6]])},
        coords={"run": ["r1", "r2", "a1"], "component": ["lateral", "vertical"],
                "f": [0.1, 0.2, 0.3, 0.4, 0.5, 0.6],
                "length_mm": ("run", [40.0, 40.0, 40.0]),
                "resolution_per_mm": ("run", [0.025, 0.025, 0.025])}),
    deflection=pd.DataFrame({"cut": ["plan_01"], "loaded_run": ["r1"], "air_run": ["a1"],
                             "deflection_normal_um": [3.0], "deflection_axial_um": [1.0]}))
STUDY_PEAKS = pd.DataFrame({"mechanism": "gear", "joint": [2, 3], "stage": "motor",
                            "order": "mesh", "component": "vertical"})
STUDY = RunOutcomes(mean_forces=pd.DataFrame({"cut": ["s1", "plan_01"], "Fx_N": [7.0, 20.0],
                                              "Fy_N": 0.0, "Fz_N": 0.0}))


def test_the_planned_runs_outcomes_come_first_one_row_per_cut_and_quantity():
    t = check_table(PRED, study=STUDY, planned_run=NEXT, peaks=STUDY_PEAKS)
    assert not t.duplicated(["cut", "quantity"]).any()
    t = t.set_index(["cut", "quantity"])
    # force: the planned run's dynamometer (15.5 N), not the study's 20 N under that id
    f = t.loc[("plan_01", "force")]
    assert f["outcome"] == pytest.approx(15.5) and f["within_interval"]
    assert f["source"] == f"{NEXT_RUN_DIR}/results/forces/mean_forces.csv"
    # waviness: in-phase sum of the loaded pass' lateral spectrum at the predicted gear
    # lines, 0.5 + 0.6 um (the air pass a1 not read)
    w = t.loc[("plan_01", "waviness")]
    assert w["outcome"] == pytest.approx(1.1) and w["within_interval"]
    assert w["source"] == f"{NEXT_RUN_DIR}/results/straightness/profiles.nc"
    # no lateral line there: measured 0 µm (the vertical 9 µm is not the wall normal)
    assert t.loc[("plan_02", "waviness"), "outcome"] == 0.0
    # stability without verdicts: the planned run's force spectrum: line √4 = 2 N on 12 N
    # is 17 % > 5 % of the mean -> chatter
    s = t.loc[("plan_02", "stability")]
    assert s["outcome"] == 0.0 and s["source"] == f"{NEXT_RUN_DIR}/results/forces/peaks.csv"
    # the study's cut keeps the study's sources
    assert t.loc[("s1", "force"), "source"] == "results/forces/mean_forces.csv"


def test_without_a_planned_run_the_table_is_as_before():
    a = check_table(PRED, study=STUDY)
    b = check_table(PRED, study=STUDY, planned_run=RunOutcomes(NEXT_RUN_DIR))
    pd.testing.assert_frame_equal(a, b)


def test_the_next_run_records_each_planned_cut_and_its_air_pass_by_accelerometer():
    """The planned cuts' run writes an accelerometer record and its air pass per cut, so that
    its chatter verdicts can call a line forced (the servo-excited learn cut of the study)."""
    from snakemake.utils import update_config

    from robomill.io.synthetic_layout import instrument_files
    from robomill.pipeline.config import load_config

    base = load_config(REPO / "config.yaml")
    overlay = next_config(MANIFEST)
    overlay.pop("workdir")
    update_config(base, overlay)
    files = [f for f in instrument_files(base, "recordings") if f["kind"] == "vibration"]
    passes = sorted((f["cut"], f.get("pass", "loaded")) for f in files)
    assert passes == [("plan_01", "air"), ("plan_01", "loaded"), ("plan_02", "air"),
                      ("plan_02", "loaded")]
