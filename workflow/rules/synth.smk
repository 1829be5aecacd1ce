# The virtual cell: every instrument simulator, the planted truth and the manifest of the
# synthetic raw files. The only rules that read config["synth"] (a test enforces it): the
# analyses read the raw folder (results/synthetic/raw/: manifest.yaml, cell.yaml, data files)
# exactly as they read real data.
from robomill.experiment import tracker_pass
from robomill.synth.cutstate import planned_cut_states

SYNTH_CFG = {
    "cell": config["cell"],
    "synth": config["synth"],
    "experiment": config["experiment"],
}
SYNTH_FORCE_FORMAT = config["synth"]["dynamometer"]["format"]


# the planned synthetic raw files of each kind (none in raw mode; PLAN: the virtual cell's
# folder only, not the later raw folders of data.raw_dirs)
SYNTH_FILES = {}
for _f in PLAN.files if SYNTHETIC else []:
    SYNTH_FILES.setdefault(_f["kind"], []).append(_f)
SYNTH_TRACKER_RUNS = {tracker_run(f): f for f in SYNTH_FILES.get("tracker", [])}
SYNTH_CUT_BY_ID = {c.id: c for c in CUTS}
# every cut an instrument samples, integrated once: its span and whether an air pass is
# recorded (robomill.synth.cutstate)
SYNTH_CUT_STATES = planned_cut_states(SYNTH_CFG, PLAN.files if SYNTHETIC else [])


rule synth_cell:
    input:
        code=code_inputs("cell_write.py"),
    output:
        "results/synthetic/raw/cell.yaml",
    log:
        "results/logs/synth/cell.log",
    benchmark:
        "results/benchmarks/rules/synth/cell.tsv"
    conda:
        ENV
    params:
        cell=config["cell"],
    script:
        "../scripts/cell_write.py"


rule synth_truth:
    input:
        code=code_inputs("synth_truth.py"),
    output:
        artefact("synthetic.truth"),
    log:
        "results/logs/synth/truth.log",
    benchmark:
        "results/benchmarks/rules/synth/truth.tsv"
    conda:
        ENV
    params:
        cfg=SYNTH_CFG,
    script:
        "../scripts/synth_truth.py"


# The closed-loop cuts themselves: each cut integrated once over the longest span any
# instrument samples (with its air pass where one is recorded), one job for all (Python, the
# library and the compiled kernels start once), one file per cut. Every instrument's job below
# samples these files.
rule synth_cuts:
    input:
        code=code_inputs("synth_cuts.py"),
    output:
        [artefact("synthetic.cut_state", cut=c) for c in SYNTH_CUT_STATES],
    log:
        "results/logs/synth/cuts.log",
    benchmark:
        "results/benchmarks/rules/synth/cuts.tsv"
    # first when cores are free: every instrument's job, then every analysis, waits for it
    priority: 10
    conda:
        ENV
    params:
        cfg=SYNTH_CFG,
        cuts=[
            {"cut": SYNTH_CUT_BY_ID[c].as_dict(), **spec}
            for c, spec in SYNTH_CUT_STATES.items()
        ],
    script:
        "../scripts/synth_cuts.py"


# Stylus profiles, dynamometer records, tracker runs and impact hits: one simulator job each
# for all the planned cuts, runs or hits, simulated one after the other in one process, so that
# Python and the library start once (a per-cut job would pay the start-up 45 times for under a
# second of work each). The files of one instrument always change together: all come from the
# same configuration.
SYNTH_PROFILE_CUTS = [
    c for c in CUTS if c.id in {f["cut"] for f in SYNTH_FILES.get("profile", [])}
]
SYNTH_FORCE_CUTS = [
    c for c in CUTS if c.id in {f["cut"] for f in SYNTH_FILES.get("force", [])}
]


rule surface_synth_profiles:
    input:
        code=code_inputs("synth_profiles.py"),
        states=[artefact("synthetic.cut_state", cut=c.id) for c in SYNTH_PROFILE_CUTS],
    output:
        [f"results/synthetic/raw/profiles/{c.id}.csv" for c in SYNTH_PROFILE_CUTS],
    log:
        "results/logs/surface/synth.log",
    benchmark:
        "results/benchmarks/rules/surface/synth.tsv"
    conda:
        ENV
    params:
        cfg=SYNTH_CFG,
        cuts=[c.as_dict() for c in SYNTH_PROFILE_CUTS],
    script:
        "../scripts/synth_profiles.py"


rule synth_dynamometer:
    input:
        code=code_inputs("synth_dynamometer.py"),
        states=[artefact("synthetic.cut_state", cut=c.id) for c in SYNTH_FORCE_CUTS],
    output:
        [
            f"results/synthetic/raw/forces/{c.id}.{SYNTH_FORCE_FORMAT}"
            for c in SYNTH_FORCE_CUTS
        ],
    log:
        "results/logs/forces/synth.log",
    benchmark:
        "results/benchmarks/rules/forces/synth.tsv"
    conda:
        ENV
    params:
        cfg=SYNTH_CFG,
        cuts=[c.as_dict() for c in SYNTH_FORCE_CUTS],
    script:
        "../scripts/synth_dynamometer.py"


# The microphone's and the spindle accelerometer's recordings of the same cuts (off by
# default: synth.recordings), each with its air pass (synth.recordings.air_pass), one job for
# all, as the dynamometer's.
# (in the layout's order: a cut's sound and vibration follow each other, integrated once)
SYNTH_RECORDINGS = [
    f for f in (PLAN.files if SYNTHETIC else []) if f["kind"] in ("sound", "vibration")
]


rule synth_recordings:
    input:
        code=code_inputs("synth_recordings.py"),
        states=[artefact("synthetic.cut_state", cut=f["cut"]) for f in SYNTH_RECORDINGS],
    output:
        [f"results/synthetic/raw/{f['path']}" for f in SYNTH_RECORDINGS],
    log:
        "results/logs/synth/recordings.log",
    benchmark:
        "results/benchmarks/rules/synth/recordings.tsv"
    conda:
        ENV
    params:
        cfg=SYNTH_CFG,
        files=[
            {
                "kind": f["kind"],
                "cut": SYNTH_CUT_BY_ID[f["cut"]].as_dict(),
                "pass": f.get("pass") or "loaded",
                "state": artefact("synthetic.cut_state", cut=f["cut"]),
            }
            for f in SYNTH_RECORDINGS
        ],
    script:
        "../scripts/synth_recordings.py"


rule synth_tracker:
    input:
        code=code_inputs("synth_tracker.py"),
        states=sorted(
            {
                artefact("synthetic.cut_state", cut=f["cut"])
                for f in SYNTH_TRACKER_RUNS.values()
                if tracker_pass(f) == "loaded"
            }
        ),
    output:
        [f"results/synthetic/raw/tracker/{run}.csv" for run in SYNTH_TRACKER_RUNS],
    log:
        "results/logs/straightness/synth.log",
    benchmark:
        "results/benchmarks/rules/straightness/synth.tsv"
    conda:
        ENV
    params:
        cfg=SYNTH_CFG,
        runs=[
            {
                "direction": f["direction"],
                "feed_mm_s": f["feed_mm_s"],
                "cut": f["cut"],
                "pass": tracker_pass(f),
                "run": run,
                "state": (
                    artefact("synthetic.cut_state", cut=f["cut"])
                    if tracker_pass(f) == "loaded"
                    else None
                ),
            }
            for run, f in SYNTH_TRACKER_RUNS.items()
        ],
    script:
        "../scripts/synth_tracker.py"


rule synth_impact:
    input:
        code=code_inputs("synth_impact.py"),
    output:
        [f"results/synthetic/raw/{f['path']}" for f in SYNTH_FILES.get("impact", [])],
    log:
        "results/logs/synth/impact.log",
    benchmark:
        "results/benchmarks/rules/synth/impact.tsv"
    conda:
        ENV
    params:
        cfg=SYNTH_CFG,
        hits=[
            {"direction": f["direction"], "hit": int(f["hit"])}
            for f in SYNTH_FILES.get("impact", [])
        ],
    script:
        "../scripts/synth_impact.py"


rule synth_ctrack:
    input:
        code=code_inputs("synth_ctrack.py"),
    output:
        "results/synthetic/raw/ctrack/{table}.csv",
    log:
        "results/logs/synth/ctrack_{table}.log",
    benchmark:
        "results/benchmarks/rules/synth/ctrack_{table}.tsv"
    wildcard_constraints:
        table="circles|home|steps|base|loads|accuracy",
    conda:
        ENV
    params:
        cfg=SYNTH_CFG,
        table=lambda w: w.table,
    script:
        "../scripts/synth_ctrack.py"


rule synth_loadtests_robot:
    input:
        code=code_inputs("synth_loadtests_robot.py"),
    output:
        robot="results/synthetic/raw/stiffness/{robot}.yaml",
    log:
        "results/logs/synth/stiffness/{robot}_robot.log",
    benchmark:
        "results/benchmarks/rules/synth/stiffness/{robot}_robot.tsv"
    wildcard_constraints:
        robot="[A-Za-z0-9_-]+",
    conda:
        ENV
    params:
        cfg=SYNTH_CFG,
        robot=lambda w: w.robot,
    script:
        "../scripts/synth_loadtests_robot.py"


rule synth_loadtests:
    input:
        code=code_inputs("synth_loadtests.py"),
    output:
        tests="results/synthetic/raw/stiffness/load_tests_{robot}.csv",
    log:
        "results/logs/synth/stiffness/{robot}_tests.log",
    benchmark:
        "results/benchmarks/rules/synth/stiffness/{robot}_tests.tsv"
    wildcard_constraints:
        robot="[A-Za-z0-9_-]+",
    conda:
        ENV
    params:
        cfg=SYNTH_CFG,
        robot=lambda w: w.robot,
    script:
        "../scripts/synth_loadtests.py"


rule synth_manifest:
    input:
        files=[f"results/synthetic/raw/{f['path']}" for f in PLAN.files],
        truth=artefact("synthetic.truth"),
        code=code_inputs("synth_manifest.py"),
    output:
        "results/synthetic/raw/manifest.yaml",
    log:
        "results/logs/synth/manifest.log",
    benchmark:
        "results/benchmarks/rules/synth/manifest.tsv"
    conda:
        ENV
    params:
        experiment=EXPERIMENT,
        cuts=[c.as_dict() for c in PLAN.cuts],
        files=PLAN.files,
        raw_dir=lambda w, output: os.path.dirname(output[0]),
    script:
        "../scripts/synth_manifest.py"
