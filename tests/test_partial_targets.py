"""Partial studies: a folder is asked only for the experiment and cut keys of the chapters its
kinds feed; every chapter target on an empty folder, and on each one-kind folder every target
whose needs some folder holds, gives a plan or one line, never a stack; a bad manifest stops with
its one line; a raw folder of another design gets chapter 4 and 5 parameters from its own
manifest, and the configuration's robots are analysed where the folder holds them.

The folders are built from the synthetic plan
(:func:`robomill.io.synthetic_layout.synthetic_manifest`)
with empty data files: a dry run (``snakemake -n``) reads only the manifest and the cell file.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
import yaml
from conftest import REPO, run_snakemake

from robomill.errors import RawDataError
from robomill.io.manifest import parse_manifest
from robomill.io.needs import CHAPTER_NEEDS, required_cut_keys, required_experiment_keys

EXP = {"spindle_rpm": 28000, "flutes": 2, "tool_diameter_mm": 6.0, "cut_length_mm": 40.0}
CUT = {"id": "c1", "direction": "px", "feed_mm_s": 2.0, "depth_mm": 0.5}


def _file(kind: str, path: str, **meta) -> dict:
    return {"path": path, "kind": kind, "sha256": "0" * 64, **meta}


# --- which keys a folder needs (robomill.io.needs) -----------------------------------------

def test_a_modal_only_or_tracker_only_folder_needs_no_cutting_parameter():
    assert required_experiment_keys({"impact"}, False) == {}
    assert required_experiment_keys({"tracker"}, False) == {}
    assert required_experiment_keys({"ctrack", "robot", "stiffness"}, False) == {}
    impact = _file("impact", "impact/test.uff")
    m = parse_manifest({"experiment": {}, "cuts": [], "files": [impact]}, "manifest.yaml")
    assert m.experiment == {}
    tracker = _file("tracker", "tracker/run.csv", direction="px", feed_mm_s=2.0, fs_hz=100.0)
    parse_manifest({"experiment": {"flutes": None}, "cuts": [], "files": [tracker]},
                   "manifest.yaml")


def test_each_kind_asks_for_the_keys_of_the_chapters_it_feeds():
    assert required_experiment_keys({"profile"}, True) == {
        "spindle_rpm": ["0", "2"], "flutes": ["0", "2"]}
    forces = required_experiment_keys({"force"}, True)
    assert forces["tool_diameter_mm"] == ["3.1"] and "cut_length_mm" not in forces
    assert required_experiment_keys({"impact", "force"}, True)["flutes"] == ["0", "3.1", "4"]
    assert required_experiment_keys({"robot", "stiffness"}, True) == {
        "spindle_rpm": ["0"], "flutes": ["0"], "cut_length_mm": ["5"]}
    assert required_experiment_keys({"robot", "stiffness"}, False) == {}
    assert required_cut_keys({"impact", "force"})["depth_mm"] == ["0", "3.1", "4"]
    # every chapter target is named once
    targets = [n.target for n in CHAPTER_NEEDS.values()]
    assert len(targets) == len(set(targets))


@pytest.mark.parametrize("files, drop, chapters", [
    ([_file("profile", "profiles/c1.csv", cut="c1")], "flutes", "chapters 0, 2"),
    ([_file("force", "forces/c1.csv", cut="c1", fs_hz=1e4)], "tool_diameter_mm", "chapter 3.1"),
])
def test_a_missing_key_names_the_chapters_that_need_it(files, drop, chapters):
    exp = {k: v for k, v in EXP.items() if k != drop}
    with pytest.raises(RawDataError, match=rf"experiment: key '{drop}' is missing .*{chapters} "
                                           r"of this folder"):
        parse_manifest({"experiment": exp, "cuts": [CUT], "files": files}, "manifest.yaml")
    # a key no chapter of the folder reads may be left out, or null
    parse_manifest({"experiment": {**exp, drop: 1, "cut_length_mm": None}, "cuts": [CUT],
                    "files": files}, "manifest.yaml")


def test_check_and_manifest_ask_only_for_the_keys_the_folder_needs(tmp_path, capsys):
    from robomill.cli import main

    raw = tmp_path / "raw"
    (raw / "forces").mkdir(parents=True)
    (raw / "forces" / "c1.csv").write_text("t_s,Fx_N,Fy_N,Fz_N\n0,0,0,0\n0.001,1,1,1\n")
    rc = main(["manifest", str(raw)])
    out = capsys.readouterr().out
    assert rc == 0
    data = yaml.safe_load((raw / "manifest.yaml").read_text())
    # the forces' chapters need speed, flutes, diameter; nothing needs the cut length
    assert set(data["experiment"]) == {"spindle_rpm", "flutes", "tool_diameter_mm"}
    assert "experiment.tool_diameter_mm not inferred (write it; chapter 3.1 need(s) it)" in out
    assert "cut_length_mm" not in out
    main(["check", str(raw)])
    out = capsys.readouterr().out
    assert ("experiment: key 'tool_diameter_mm' is null (expected tool_diameter_mm: "
            "chapter 3.1 of this folder need(s) it)") in out
    assert "cut_length_mm" not in out


# --- dry runs on partial folders -----------------------------------------------------------

def _plan(*configs: Path) -> dict:
    from snakemake.utils import update_config

    from robomill.io.synthetic_layout import synthetic_manifest

    cfg: dict = {}
    for c in configs:
        update_config(cfg, yaml.safe_load(c.read_text()))
    return cfg, synthetic_manifest(cfg)


def _folder(dst: Path, cfg: dict, plan: dict, kinds: set[str], cuts: bool,
            experiment: tuple[str, ...]) -> Path:
    """A raw folder with the plan's files of ``kinds`` (empty files), its cuts if ``cuts``
    (else the files' cut references dropped) and only the ``experiment`` keys given."""
    files = []
    for f in plan["files"]:
        if f["kind"] not in kinds:
            continue
        f = {**f, "sha256": "0" * 64}
        if not cuts:
            f.pop("cut", None)
        path = dst / f["path"]
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(yaml.safe_dump(cfg["cell"]) if f["kind"] == "cell" else "")
        files.append(f)
    dst.mkdir(parents=True, exist_ok=True)
    manifest = {"experiment": {k: plan["experiment"][k] for k in experiment},
                "cuts": plan["cuts"] if cuts else [], "files": files}
    (dst / "manifest.yaml").write_text(yaml.safe_dump(manifest, sort_keys=False))
    return dst


FOLDERS = {  # kinds, cuts listed, experiment keys given (only what the chapters need)
    "empty": (set(), False, ()),
    "modal": ({"impact"}, False, ()),
    "tracker": ({"tracker"}, False, ()),
    "profile": ({"profile"}, True, ("spindle_rpm", "flutes")),
    "forces": ({"force"}, True, ("spindle_rpm", "flutes", "tool_diameter_mm")),
}
TARGETS = [n.target for n in CHAPTER_NEEDS.values()] + ["ch3"]
#: kinds some folder here holds ("cuts": the folders that list their cuts)
HELD = set().union(*(spec[0] for spec in FOLDERS.values())) | {"cuts"}
#: the chapter targets whose outcome can differ between these folders: those that need a kind
#: some folder holds. The others (they need nothing, or only kinds no folder holds) plan, or say
#: their one line, alike on every folder: they are tried on the empty one only
VARYING = {n.target for n in CHAPTER_NEEDS.values()
           if any(set(need.split("|")) & HELD for need in n.kinds)} | {"ch3"}


@pytest.fixture(scope="module")
def folders(tmp_path_factory):
    cfg, plan = _plan(REPO / ".test" / "config.yaml")
    root = tmp_path_factory.mktemp("partial")
    return {name: _folder(root / name, cfg, plan, *spec) for name, spec in FOLDERS.items()}


def _dry(workdir: Path, data: Path, *targets: str) -> subprocess.CompletedProcess:
    return run_snakemake(workdir, "-n", *targets, "--config", f"data={data}",
                         configfile=REPO / "config.yaml", timeout=300)


def _said(stderr: str) -> list[str]:
    """What the run said beyond Snakemake's and the workflow's notes."""
    notes = ("Using workflow specific profile", "Config file ", "Assuming unrestricted",
             "robomill: results/thesis/book.pdf left out", "chapter ")
    return [x for x in stderr.splitlines() if x.strip() and not x.startswith(notes)]


@pytest.mark.parametrize("name", list(FOLDERS))
def test_every_chapter_target_plans_or_says_one_line(folders, tmp_path, name):
    data = folders[name]
    kinds = FOLDERS[name][0]
    targets = TARGETS if name == "empty" else [t for t in TARGETS if t in VARYING]
    for t in targets:
        (tmp_path / t).mkdir()
    with ThreadPoolExecutor(4) as pool:  # dry runs, a few seconds each
        runs = dict(zip(targets, pool.map(lambda t: _dry(tmp_path / t, data, t), targets),
                        strict=True))
    for target, proc in runs.items():
        assert "Traceback" not in proc.stderr and 'File "' not in proc.stderr, (
            target, proc.stderr[-3000:])
        label = next((k for k, n in CHAPTER_NEEDS.items() if n.target == target), None)
        fed = label is not None and set(CHAPTER_NEEDS[label].kinds) <= (
            kinds | ({"cuts"} if FOLDERS[name][1] else set()))
        if fed:
            assert proc.returncode == 0, (target, proc.stderr[-3000:])
        if proc.returncode != 0:
            said = _said(proc.stderr)
            assert len(said) == 1, (target, said)
            assert said[0].startswith("robomill: ") and f"none in {data}/manifest.yaml" in said[0]
    # chapter 3.3 on the modal folder plans without a cutting parameter; chapter 3.2 of a
    # folder without tracker runs names the kind
    if name == "modal":
        assert runs["ch3_modal"].returncode == 0
    if name in ("empty", "modal"):
        assert runs["ch3_straightness"].returncode == 1
        assert "needs tracker files" in _said(runs["ch3_straightness"].stderr)[0]


def test_a_stage_target_without_its_kind_says_one_line(folders, tmp_path):
    proc = _dry(tmp_path, folders["profile"], "straightness")
    assert proc.returncode == 1
    assert _said(proc.stderr) == [
        f"robomill: straightness needs tracker files: none in {folders['profile']}/manifest.yaml"]


def test_a_bad_manifest_stops_with_its_message_alone(folders, tmp_path):
    raw = tmp_path / "raw"
    raw.mkdir()
    bad = yaml.safe_load((folders["forces"] / "manifest.yaml").read_text())
    del bad["experiment"]["flutes"]
    bad["files"] = []
    (raw / "manifest.yaml").write_text(yaml.safe_dump(bad))
    proc = _dry(tmp_path, raw, "all")
    assert proc.returncode == 1
    said = _said(proc.stderr)
    assert len(said) == 1 and "Traceback" not in proc.stderr and 'File "' not in proc.stderr
    assert said[0].startswith(f"{raw}/manifest.yaml: experiment: key 'flutes' is missing")
    assert "chapter 0" in said[0]


# --- another lab's design, its own robots ------------------------------------------------

PARAMS = """
import json, sys
from pathlib import Path
from snakemake.api import SnakemakeApi
from snakemake.settings.types import ConfigSettings, OutputSettings, ResourceSettings
repo, data = Path(sys.argv[1]), sys.argv[2]
with SnakemakeApi(OutputSettings()) as api:
    wf = api.workflow(resource_settings=ResourceSettings(), snakefile=repo / "Snakefile",
                      config_settings=ConfigSettings(config={"data": data},
                                                     configfiles=[repo / "config.yaml"]),
                      workdir=Path.cwd())
    w = wf._workflow  # the parsed workflow: each rule's params as the jobs get them
    print("PARAMS " + json.dumps({r: dict(w.get_rule(r).params.items()) for r in sys.argv[3:]},
                                 default=str))
"""


@pytest.fixture(scope="module")
def other_design(tmp_path_factory):
    """The synthetic raw folder of examples/other_cell (PUMA 560 cell, 3 flutes, 12–24 krpm,
    a_p 0.5 mm, 30 mm cuts, load tests of the KR360 and the PUMA, no IRB 1600) handed over as
    raw data with the default config.yaml."""
    cfg, plan = _plan(REPO / "config.yaml", REPO / "examples/other_cell/config.yaml")
    kinds = {f["kind"] for f in plan["files"]}
    root = tmp_path_factory.mktemp("other_design")
    return _folder(root / "raw", cfg, plan, kinds, True, tuple(plan["experiment"])), plan


def test_chapters_4_and_5_take_the_design_of_the_raw_folder(other_design, tmp_path):
    data, plan = other_design
    default = yaml.safe_load((REPO / "config.yaml").read_text())["experiment"]
    proc = subprocess.run(
        [sys.executable, "-c", PARAMS, str(REPO), str(data), "chatter_thesis",
         "stiffness_cuts"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    line = next(x for x in proc.stdout.splitlines() if x.startswith("PARAMS "))
    params = json.loads(line[len("PARAMS "):])
    chatter, cuts = params["chatter_thesis"], params["stiffness_cuts"]
    # the design reaches them through the study (results/ingest/study.yaml), no rule parameter
    assert not {"spindle_rpm", "flutes", "depths_mm"} & set(chatter), chatter
    assert not {"experiment", "cuts"} & set(cuts), cuts
    # the study the ingestion rule writes for this folder, as its rules read it
    from robomill.chatter.slot_lobes import study_slots
    from robomill.io.rawdirs import load_study_manifest
    from robomill.study import read_study, write_study

    study = read_study(write_study(load_study_manifest(data / "manifest.yaml"),
                                   tmp_path / "study.yaml", layout=default["layout"]))
    # the lab's design, written independently: examples/other_cell/config.yaml
    own = {c["id"]: float(c.get("spindle_rpm", plan["experiment"]["spindle_rpm"]))
           for c in plan["cuts"]}
    assert {c.id: c.spindle_rpm for c in study.cuts} == own
    assert {c.flutes for c in study.cuts} == {3} and {c.depth_mm for c in study.cuts} == {0.5}
    assert (study.experiment["spindle_rpm"], study.experiment["flutes"]) == (18000, 3)
    assert (default["spindle_rpm"], default["flutes"]) == (28000, 2)  # not the config's
    assert study.experiment["cut_length_mm"] == 30.0 != default["cut_length_mm"]
    assert [c.id for c in study.cuts] == [c["id"] for c in plan["cuts"]]
    assert "sets" not in study.experiment
    # chapter 4's slots hold every cut, each at its own speed
    slots = study_slots(study)
    assert sorted(c.id for s in slots for c in s.cuts) == sorted(own)
    assert {p[0] for s in slots for p in s.points} == set(own.values())


def test_the_configured_robots_are_analysed_where_the_folder_holds_them(other_design, tmp_path):
    """The default config names irb1600 (thesis_robot), which this folder lacks: the DAG is
    built (no InputFunctionException) and chapter 5 analyses the PUMA and the KR360."""
    data, _ = other_design
    proc = _dry(tmp_path, data, "all")
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "Traceback" not in proc.stderr
    plan = _dry(tmp_path, data, "ch5")
    assert plan.returncode == 0, plan.stderr[-3000:]
    said = plan.stdout + plan.stderr
    for robot in ("puma560", "kr360"):  # the cell's robot, the map robot: both identified
        assert f"results/stiffness/{robot}/joint_stiffness.csv" in said, robot
    assert "irb1600" not in said
    ident = _dry(tmp_path, data, "results/stiffness/irb1600/joint_stiffness.csv")
    assert ident.returncode == 1
    assert _said(ident.stderr) == [
        f"robomill: stiffness needs robot files and stiffness files of robot irb1600: none in "
        f"{data}/manifest.yaml"]


def _job_counts(proc: subprocess.CompletedProcess) -> dict[str, int]:
    """``{rule: jobs}`` of a dry run's "Job stats" table."""
    lines = proc.stdout.splitlines()
    start = next(i for i, x in enumerate(lines) if x.startswith("Job stats"))
    counts = {}
    for x in lines[start + 3:]:
        parts = x.split()
        if len(parts) != 2 or not parts[1].isdigit() or parts[0] == "total":
            break
        counts[parts[0]] = int(parts[1])
    return counts


def test_real_files_get_a_job_per_cut_the_virtual_cell_one_per_instrument(other_design,
                                                                        tmp_path):
    """Issue 29: a real profile, force or tracker file can change alone, so it is analysed in
    its own job; the virtual cell's files of one instrument come from one simulator job and
    change together, so one job simulates them and one analyses them."""
    data, plan = other_design
    (tmp_path / "raw").mkdir()
    raw = _job_counts(_dry(tmp_path / "raw", data, "all"))
    n_profiles = sum(f["kind"] == "profile" for f in plan["files"])
    n_runs = sum(f["kind"] == "tracker" for f in plan["files"])
    n_forces = sum(f["kind"] == "force" for f in plan["files"])
    assert n_profiles > 1 and n_runs > 1 and n_forces > 1
    assert raw["forces_cut"] == n_forces and "forces_cuts" not in raw
    assert raw["surface_profile"] == n_profiles and "surface_profiles" not in raw
    assert raw["straightness_run"] == n_runs and "straightness_runs" not in raw
    assert not {"synth_impact", "synth_tracker"} & set(raw)
    (tmp_path / "synthetic").mkdir()
    synthetic = _job_counts(run_snakemake(tmp_path / "synthetic", "-n", "all", timeout=300))
    for rule in ("surface_profiles", "straightness_runs", "forces_cuts", "synth_impact",
                 "synth_tracker", "surface_synth_profiles",
                 "synth_dynamometer", "synth_cuts"):
        assert synthetic[rule] == 1, rule
    assert not {"surface_profile", "straightness_run", "forces_cut"} & set(synthetic)


def _is_page_rule(rule: str) -> bool:
    """The rules that make pages: the chapters (ch0, ch3_forces, …), the scorecard (it waits
    for the chapters), the book, its print and `all`."""
    return re.match(r"ch\d", rule) is not None or rule in ("scorecard", "book", "book_pdf",
                                                            "all")


def test_artefacts_plans_every_job_of_all_but_the_pages(folders, tmp_path):
    """Target `artefacts`: on the tiny virtual cell, exactly the jobs of `all` less the pages
    (the chapters, the scorecard, the book); on a folder of force files alone, the jobs of
    what its chapters read, and no page."""
    for d in ("all", "artefacts", "forces"):
        (tmp_path / d).mkdir()
    every = _job_counts(run_snakemake(tmp_path / "all", "-n", "all", timeout=300))
    proc = run_snakemake(tmp_path / "artefacts", "-n", "artefacts", timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    pages = {r for r in every if _is_page_rule(r)}
    assert {"ch0", "ch2", "scorecard", "book"} <= pages
    assert _job_counts(proc) == {**{r: n for r, n in every.items() if r not in pages},
                                 "artefacts": 1}
    proc = _dry(tmp_path / "forces", folders["forces"], "artefacts")
    assert proc.returncode == 0, proc.stderr[-3000:]
    planned = _job_counts(proc)
    assert {"forces_findings", "ingest_findings"} <= set(planned)
    assert not [r for r in planned if _is_page_rule(r)], planned


def test_book_pdf_false_leaves_the_print_out_of_all_with_one_line(tmp_path):
    proc = run_snakemake(tmp_path, "-n", "all", "--config", "book={pdf: false}", timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stderr.count("robomill: results/thesis/book.pdf left out of `all`: "
                             "book.pdf is false") == 1
    planned = _job_counts(proc)
    assert "book" in planned and "book_pdf" not in planned
    bad = run_snakemake(tmp_path, "-n", "all", "--config", "book={pdf: maybe}", timeout=300)
    assert bad.returncode == 1
    assert _said(bad.stderr) == [
        "robomill: config key 'book.pdf': 'maybe' is not true or false (expected true or "
        "false: write e.g. pdf: true in the config file, or --config book='{pdf: true}' on "
        "the command line)"]
