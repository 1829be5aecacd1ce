# Helpers shared by the rules: where raw data comes from, the study plan, target lists.
# Keep this file small: computation lives in src/robomill/.
import sys
from pathlib import Path

import robomill
from robomill.catalogue import artefact
from robomill.pipeline.codedeps import code_files, load_cache, save_cache
from robomill.experiment import (
    is_thesis_design,
    is_thesis_study,
    missing_data,
    tracker_direction,
    tracker_run,
)
from robomill.io.cell import peek_robot_name
from robomill.errors import RawDataError
from robomill.io.rawdirs import first_plan, raw_folders, study_plan
from robomill.pipeline.prose import TEMPLATES_DIR
from robomill.registry import (
    REQUIREMENT_WORDS,
    chapters as registry_chapters,
    unmet_requirement,
)

REPO = Path(workflow.basedir)
SYNTHETIC = config["data"]["source"] == "synthetic"
RAW = raw_folders(config["data"])[
    0
]  # the first raw folder (synthetic: the virtual cell's)
MANIFEST = f"{RAW}/manifest.yaml"
STUDY = artefact("ingest.study")
ENV = "../envs/robomill.yaml"

# The chapter registry: the package's table (robomill/data/chapters.yaml; robomill.registry).
CHAPTERS = {c.id: c for c in registry_chapters()}

# The study plan, one parser in both modes (robomill.io.rawdirs.study_plan): the raw folders'
# manifest.yaml, or for synthetic data the manifest the simulators will write. The DAG takes
# only its shape from it (cut ids, kinds, files); the analyses read the study the ingestion
# rule writes (STUDY, robomill.study). A bad manifest stops the run with its one line
# (file: where: problem (expected ...)), not a Python stack.
RAW_DIRS = raw_folders(config["data"])
MANIFESTS = [f"{d}/manifest.yaml" for d in RAW_DIRS]
try:
    # the first raw folder's manifest (synthetic: the virtual cell's own files)
    PLAN = first_plan(config)
    STUDY_PLAN = study_plan(config, PLAN)
except RawDataError as exc:
    print(exc, file=sys.stderr)
    sys.exit(1)
CUTS = STUDY_PLAN.cuts
RAW_FILES = STUDY_PLAN.files
EXPERIMENT = STUDY_PLAN.experiment
CUT_IDS = [c.id for c in CUTS]

# The cell (robot, home posture, tool orientation, gear trains): the raw folder's cell.yaml
# (kind cell; synthetic mode writes one from config cell:), else the configuration's cell:
# section written to results/ingest/cell.yaml (raw folders from before cell files).
CELL_RELPATH = next((f["path"] for f in RAW_FILES if f["kind"] == "cell"), "")
CELL = f"{RAW}/{CELL_RELPATH}" if CELL_RELPATH else artefact("ingest.cell")


wildcard_constraints:
    cut="[A-Za-z0-9_.-]+",  # any cut id (robomill.experiment.FREE_CUT_ID)


# Every stage appends the outputs that `all` must build (chapters, book).
ALL_TARGETS = []
# Chapters left out of `all` for want of data (partial raw folders): label -> reason.
SKIPPED = {}


def has_kind(kind):
    """Whether the raw folder has files of `kind` (optional cross-chapter inputs)."""
    return any(f["kind"] == kind for f in RAW_FILES)


def optional_input(present, *path, **named):
    """An input only some raw folders have: `path` (one positional input) or the `named`
    inputs (spread with `**`) when `present`, else nothing ([] or {})."""
    if named:
        return named if present else {}
    return path[0] if present else []


def kind_input(stage, *kinds, **meta):
    """An input function of the job that reads a stage's raw files. No input when the raw
    folder has files of every kind in `kinds` (and `meta`: e.g. robot=name); otherwise one
    line naming what is missing and the folder, and the run stops while the DAG is built,
    before any job (SystemExit: Snakemake prints no stack). Any target built from these
    files is refused that way (docs/data-contract.md)."""

    def check(wildcards):
        want = {k: v(wildcards) if callable(v) else v for k, v in meta.items()}
        lacking = [k for k in kinds if not raw_files(k, **want)]
        if lacking:
            files = " and ".join(f"{k} files" for k in lacking)
            of = "".join(f" of {k} {v}" for k, v in want.items())
            print(
                f"robomill: {stage} needs {files}{of}: none in {MANIFEST}",
                file=sys.stderr,
            )
            raise SystemExit(1)
        return []

    return check


def design_input(stage, what, why):
    """An input function of a job that needs `what` from the study's design: no input when
    `why` (the reason the design cannot give it) is None; otherwise one line and the run
    stops while the DAG is built, as kind_input does (chatter: identified coefficients).
    """

    def check(wildcards):
        if why:
            print(f"robomill: {stage} needs {what}: {why}", file=sys.stderr)
            raise SystemExit(1)
        return []

    return check


# The thesis' design (Tables 2.1/2.2, the thesis-layout artefacts) and the thesis' study (its
# process too: the findings' comparison rows and the scorecard); the chapters take both from
# their findings, never as a parameter. Any other design gets per-cut tables grouped by what
# varies (robomill.pipeline.design_tables).
THESIS_DESIGN = is_thesis_design(CUTS)
THESIS_STUDY = is_thesis_study(CUTS, EXPERIMENT)

# The robots (chapter 5): the cell's own robot, and those the folder holds (a robot file),
# the cell's first.
CELL_ROBOT = config["cell"]["robot"].get("name") if SYNTHETIC else peek_robot_name(CELL)
FOLDER_ROBOTS = sorted(
    {f["robot"] for f in RAW_FILES if f["kind"] == "robot"},
    key=lambda r: (r != CELL_ROBOT, r),
)


def folder_robot(configured):
    """The robot the configuration names (stiffness.map_robot, thesis_robot) where the folder
    holds it, else the folder's robots, the cell's first; the configured name when the folder
    has none (its targets then stop with one line: kind_input)."""
    return (
        configured
        if configured in FOLDER_ROBOTS or not FOLDER_ROBOTS
        else FOLDER_ROBOTS[0]
    )


def robot_file(name, kind="robot"):
    """The robot file (or the load tests: kind stiffness) of robot `name`: an input only
    where the folder holds it."""
    paths = raw_files(kind, robot=name)
    return optional_input(bool(paths), paths[0] if paths else "")


def add_chapter(c):
    """Build chapter `c` (a registry row) in `all` if the raw folder has the kinds it needs
    and the design meets what it requires (e.g. chapter 4: identifiable cutting
    coefficients); otherwise skip it with one line (`chapter 3.3: no impact files in
    manifest.yaml`)."""
    why = missing_data(RAW_FILES, CUTS, c.needs.kinds)
    for name in c.requires:
        unmet = why is None and unmet_requirement(name, CUTS, EXPERIMENT, RAW_FILES)
        if unmet:
            why = f"{REQUIREMENT_WORDS[name]}, {unmet}"
    if why is None:
        ALL_TARGETS.append(c.page)
    else:
        SKIPPED[c.label] = why
        if workflow.is_main_process:
            print(f"chapter {c.label}: {why}", file=sys.stderr)


for _chapter in CHAPTERS.values():
    if _chapter.in_all:
        add_chapter(_chapter)


def all_targets(wildcards):
    return ALL_TARGETS


# the chapters' own outputs: pages and executed notebooks, figure folders, the book
CHAPTER_FOLDERS = ("results/chapters/", "results/figures/", "results/thesis/")


def chapter_artefacts(wildcards):
    """Target `artefacts`: the results/ inputs of every chapter `all` builds (its data
    artefacts), without the chapters' pages and figures, the scorecard and the book. Each
    chapter's rule is found by its page (the rule is named by the chapter's id) and read
    through `rules.<name>.input`; its input functions are called as Snakemake calls them for
    the chapter's job (chapters have no wildcards, so the empty `wildcards` of this target
    serve; an unpacked function gives a mapping)."""
    found = {}
    for page in ALL_TARGETS:
        if page not in CHAPTER_OF_PAGE:
            continue
        for f in flat_inputs(getattr(rules, CHAPTER_OF_PAGE[page]).input, wildcards):
            if f.startswith("results/") and not f.startswith(CHAPTER_FOLDERS):
                found.setdefault(f)
    return list(found)


def flat_inputs(items, wildcards):
    """The paths of a rule's inputs: functions called with `wildcards`, mappings and lists
    flattened."""
    out = []
    for item in items:
        value = item(wildcards) if callable(item) else item
        if isinstance(value, dict):
            value = list(value.values())
        if isinstance(value, (list, tuple)):
            out += flat_inputs(value, wildcards)
        else:
            out.append(str(value))
    return out


def raw_files(kind, **meta):
    """Paths of the raw files of `kind` (matching `meta`) in the active raw folder."""
    return [
        f"{RAW}/{f['path']}"
        for f in RAW_FILES
        if f["kind"] == kind and all(f.get(k) == v for k, v in meta.items())
    ]


def notebook(name):
    """A chapter notebook in the repository (works with --directory elsewhere)."""
    return str(REPO / "notebooks" / name)


# The library files each rule's script (and a chapter's notebook) imports, followed through the
# import graph (robomill.pipeline.codedeps: ast only, cached in .snakemake/), declared as the
# rule's named input `code`, so that editing any of them reruns the rule (Snakemake's own code
# trigger sees only the script). The Snakefile saves the cache once every rule is defined.
CODE_CACHE = Path(".snakemake") / "robomill-codedeps.json"
load_cache(CODE_CACHE)
LIBRARY_ROOT = Path(robomill.__file__).resolve().parents[1]  # src/ of a checkout


def code_inputs(script, *notebooks):
    """The library files `script` (a file of workflow/scripts/) and `notebooks` import."""
    return code_files(
        [str(REPO / "workflow" / "scripts" / script), *notebooks], LIBRARY_ROOT
    )


def package_data(name):
    """A file of the package's data (robomill/data/): references, scorecard checks."""
    return str(LIBRARY_ROOT / "robomill" / "data" / name)


# The chapters (the one chapter rule, chapter.smk, is used under each target's name): their
# outputs, notebook, template and parameters from the registry (CHAPTERS above).
# the target of each chapter page (the rule's params are looked up by its output)
CHAPTER_OF_PAGE = {c.page: c.id for c in CHAPTERS.values()}


def chapter_outputs(target):
    """The outputs of chapter `target`: executed notebook, page and figure folder."""
    c = CHAPTERS[target]
    # its own caption workflow/report/<report>.rst, else the general one
    own = REPO / "workflow" / "report" / f"{c.report}.rst"
    rst = f"../report/{c.report if own.is_file() else 'chapter'}.rst"
    category = f"Chapter {c.figure_prefix}"
    return {
        "ipynb": f"results/chapters/{c.notebook}.ipynb",
        "html": report(c.page, caption=rst, category=category),
        "figures": report(
            directory(f"results/figures/{c.figures}"),
            patterns=["{name}.png"],
            caption=rst,
            category=category,
            subcategory="Figures",
        ),
    }


def chapter_files(target):
    """The chapter's notebook and its prose template (named inputs `notebook`, `templates`:
    package data, robomill/data/templates/) and the library files the notebook and the
    chapter script import (`code`, not a notebook parameter)."""
    c = CHAPTERS[target]
    nb = notebook(f"{c.notebook}.ipynb")
    return {
        "notebook": nb,
        "templates": str(TEMPLATES_DIR / f"{c.template}.yaml"),
        "code": code_inputs("render_chapter.py", nb),
    }


def chapter_log(target):
    return f"results/logs/chapters/{target}.log"


def chapter_benchmark(target):
    return f"results/benchmarks/rules/chapters/{target}.tsv"


def chapter_target(wildcards, output):
    """The target whose job this is (the template's own jobs: its wildcard)."""
    return CHAPTER_OF_PAGE.get(output.html) or wildcards.target


def chapter_parameters(wildcards, output):
    """The chapter's notebook parameters besides its inputs (registry field `parameters`):
    `settings`, the configuration section named, and `experiment`, the study's experiment
    defaults."""
    wanted = CHAPTERS[chapter_target(wildcards, output)].parameters
    shown = {}
    if wanted.get("settings"):
        shown["settings"] = config[wanted["settings"]]
    if wanted.get("experiment"):
        shown["experiment"] = dict(EXPERIMENT)
    return shown


def chapter_shown_parameters(wildcards, output):
    """The page's table "Parameters of this run": the chapter's notebook parameters besides
    its inputs (the study's settings and experiment), else the configuration section of the
    stage whose artefacts it reads (registry field `stage`); never the artefacts' paths.
    """
    shown = chapter_parameters(wildcards, output)
    stage = CHAPTERS[chapter_target(wildcards, output)].stage
    if not shown and stage in config:
        shown = {"settings": config[stage]}
    return shown


def chapter_failed_copy(wildcards, output):
    """Where a failing chapter's executed notebook is kept (beside its log)."""
    return f"results/logs/chapters/{chapter_target(wildcards, output)}.failed.ipynb"


def tracker_run_spec(run, f):
    """What the analysis of tracker run ``run`` needs from its manifest entry ``f``."""
    return {
        "run": run,
        "relpath": f["path"],
        "direction": tracker_direction(f),
        "feed_mm_s": f["feed_mm_s"],
        "fs_hz": f.get("fs_hz"),
        "time_base": f.get("time_base", "time"),
        "cut": f.get("cut", ""),
    }
