# Stage 'stiffness' (chapter 5; Yi 2025 and Cai 2015): joint-stiffness identification for every
# robot in the manifest, working-plane maps (one job per height and redundancy angle), the
# stiffness-optimal pose, the beam-frame model and the thesis-robot slot comparison.


wildcard_constraints:
    robot="[A-Za-z0-9_-]+",
    height="[0-9]+",
    angle="-?[0-9]+",


STIFF_REL = {
    (f["kind"], f["robot"]): f["path"]
    for f in RAW_FILES
    if f["kind"] in ("robot", "stiffness")
}
STIFF_ROBOTS = FOLDER_ROBOTS  # the robots the folder holds, the cell's first
STIFF_CFG = config["stiffness"]  # validated: the schema's defaults filled
MAP_ROBOT = folder_robot(STIFF_CFG["map_robot"])
THESIS_ROBOT = folder_robot(STIFF_CFG["thesis_robot"])
MAP_JOBS = [
    (int(round(h)), int(round(a)))
    for h in STIFF_CFG["map"]["heights_mm"]
    for a in STIFF_CFG["map"]["redundancy_deg"]
]
STIFF_SEED = int(STIFF_CFG["seed"])


rule stiffness_identify:
    input:
        data=kind_input("stiffness", "robot", "stiffness", robot=lambda w: w.robot),
        robot=lambda w: robot_file(w.robot),
        tests=lambda w: robot_file(w.robot, "stiffness"),
        study=STUDY,
    output:
        joints="results/stiffness/{robot}/joint_stiffness.csv",
        models="results/stiffness/{robot}/identification.csv",
        validation="results/stiffness/{robot}/validation.csv",
    log:
        "results/logs/stiffness/{robot}/identify.log",
    benchmark:
        "results/benchmarks/rules/stiffness/{robot}/identify.tsv"
    conda:
        ENV
    params:
        robot=lambda w: w.robot,
        robot_rel=lambda w: STIFF_REL.get(("robot", w.robot)),
        tests_rel=lambda w: STIFF_REL.get(("stiffness", w.robot)),
        options=config["stiffness"]["identification"],
    script:
        "../scripts/stiffness_identify.py"


rule stiffness_map:
    input:
        robot=robot_file(MAP_ROBOT),
        joints=f"results/stiffness/{MAP_ROBOT}/joint_stiffness.csv",
        study=STUDY,
    output:
        map="results/stiffness/maps/h{height}_r{angle}.nc",
    log:
        "results/logs/stiffness/maps/h{height}_r{angle}.log",
    benchmark:
        "results/benchmarks/rules/stiffness/maps/h{height}_r{angle}.tsv"
    conda:
        ENV
    params:
        robot_rel=STIFF_REL.get(("robot", MAP_ROBOT), ""),
        height_mm=lambda w: float(w.height),
        redundancy_deg=lambda w: float(w.angle),
        map=config["stiffness"]["map"],
    script:
        "../scripts/stiffness_map.py"


rule stiffness_maps:
    input:
        maps=[f"results/stiffness/maps/h{h}_r{a}.nc" for h, a in MAP_JOBS],
        robot=robot_file(MAP_ROBOT),
    output:
        maps="results/stiffness/maps.nc",
    log:
        "results/logs/stiffness/maps.log",
    benchmark:
        "results/benchmarks/rules/stiffness/maps.tsv"
    conda:
        ENV
    params:
        map=config["stiffness"]["map"],
        seed=STIFF_SEED,
    script:
        "../scripts/stiffness_maps.py"


rule stiffness_optimal:
    input:
        maps="results/stiffness/maps.nc",
        robot=robot_file(MAP_ROBOT),
        joints=f"results/stiffness/{MAP_ROBOT}/joint_stiffness.csv",
    output:
        poses=report(
            "results/stiffness/optimal_poses.csv",
            caption="../report/ch5.rst",
            category="Chapter 5",
            subcategory="Tables",
        ),
    log:
        "results/logs/stiffness/optimal.log",
    benchmark:
        "results/benchmarks/rules/stiffness/optimal.tsv"
    conda:
        ENV
    params:
        map=config["stiffness"]["map"],
        seed=STIFF_SEED,
    script:
        "../scripts/stiffness_optimal.py"


rule stiffness_beamframe:
    output:
        beamframe="results/stiffness/beamframe.nc",
    log:
        "results/logs/stiffness/beamframe.log",
    benchmark:
        "results/benchmarks/rules/stiffness/beamframe.tsv"
    conda:
        ENV
    params:
        beamframe=config["stiffness"]["beamframe"],
    script:
        "../scripts/stiffness_beamframe.py"


rule stiffness_thesis:
    input:
        robot=robot_file(THESIS_ROBOT),
        joints=f"results/stiffness/{THESIS_ROBOT}/joint_stiffness.csv",
        study=STUDY,
        cell=CELL,
    output:
        slots="results/stiffness/thesis_slots.csv",
    log:
        "results/logs/stiffness/thesis.log",
    benchmark:
        "results/benchmarks/rules/stiffness/thesis.tsv"
    conda:
        ENV
    params:
        robot_rel=STIFF_REL.get(("robot", THESIS_ROBOT), ""),
        cell_relpath=CELL_RELPATH,
        experiment=STUDY_EXPERIMENT,
        cuts=[c.as_dict() for c in CUTS],
        beamframe=config["stiffness"]["beamframe"],
    script:
        "../scripts/stiffness_thesis.py"


# the cell's own robot at every cut (any design other than the thesis'): needs load tests of
# the robot named in cell.yaml
CUT_STIFFNESS = (
    {"cut_stiffness": "results/stiffness/cut_stiffness.csv"}
    if CELL_ROBOT in STIFF_ROBOTS and not THESIS_DESIGN
    else {}
)


rule stiffness_cuts:
    input:
        joints=f"results/stiffness/{CELL_ROBOT}/joint_stiffness.csv",
        study=STUDY,
        cell=CELL,
    output:
        cuts="results/stiffness/cut_stiffness.csv",
    log:
        "results/logs/stiffness/cuts.log",
    benchmark:
        "results/benchmarks/rules/stiffness/cuts.tsv"
    conda:
        ENV
    params:
        cell_relpath=CELL_RELPATH,
        experiment=STUDY_EXPERIMENT,
        cuts=[c.as_dict() for c in CUTS],
    script:
        "../scripts/stiffness_cuts.py"


STIFF_OUTPUTS = [
    f"results/stiffness/{r}/{name}.csv"
    for r in STIFF_ROBOTS
    for name in ("joint_stiffness", "validation")
] + ["results/stiffness/beamframe.nc"]
if MAP_ROBOT in STIFF_ROBOTS and MAP_JOBS:
    STIFF_OUTPUTS += [
        "results/stiffness/maps.nc",
        "results/stiffness/optimal_poses.csv",
    ]
# the thesis robot at the thesis' slots, beside Table 2.1: for the thesis' design only
THESIS_SLOTS = (
    {
        "slots": "results/stiffness/thesis_slots.csv",
        "waviness": "results/surface/table_2_1_waviness_rms.csv",
    }
    if THESIS_ROBOT in STIFF_ROBOTS and THESIS_DESIGN
    else {}
)
STIFF_OUTPUTS += [THESIS_SLOTS["slots"]] if THESIS_SLOTS else []
STIFF_OUTPUTS += list(CUT_STIFFNESS.values())


# Chapter 5's findings: workspace, identification, maps, optimal poses, beam frame, the
# stiffness along the cuts and the verdict on the slots' asymmetry; with the stage's scorecard
# rows ("Against the source").
rule stiffness_findings:
    input:
        **optional_input(SYNTHETIC, truth="results/synthetic/truth.nc"),
        **THESIS_SLOTS,
        **optional_input(
            bool(THESIS_SLOTS),
            thesis_joints=f"results/stiffness/{THESIS_ROBOT}/joint_stiffness.csv",
        ),
        **CUT_STIFFNESS,
        maps="results/stiffness/maps.nc",
        optimal="results/stiffness/optimal_poses.csv",
        beamframe="results/stiffness/beamframe.nc",
        joints=f"results/stiffness/{MAP_ROBOT}/joint_stiffness.csv",
        validation=f"results/stiffness/{MAP_ROBOT}/validation.csv",
        references=str(REPO / "src" / "robomill" / "data" / "references.yaml"),
        # the scorecard checks: their reasons are quoted in the findings
        checks=str(REPO / "src" / "robomill" / "data" / "scorecard.yaml"),
    output:
        findings="results/stiffness/findings.yaml",
    log:
        "results/logs/stiffness/findings.log",
    benchmark:
        "results/benchmarks/rules/stiffness/findings.tsv"
    conda:
        ENV
    params:
        map_robot=MAP_ROBOT,
        slot_asymmetry_pct=config["stiffness"]["slot_asymmetry_pct"],
        thesis_study=THESIS_STUDY,
    script:
        "../scripts/stiffness_findings.py"


if MAP_ROBOT in STIFF_ROBOTS and MAP_JOBS:
    STIFF_OUTPUTS += ["results/stiffness/findings.yaml"]


rule stiffness:
    input:
        STIFF_OUTPUTS,


use rule chapter as ch5 with:
    input:
        **THESIS_SLOTS,
        **CUT_STIFFNESS,
        **({"cuts": "results/ingest/cuts.csv"} if CUT_STIFFNESS else {}),
        **chapter_files("ch5"),
        findings="results/stiffness/findings.yaml",
    output:
        **chapter_outputs("ch5"),
    log:
        chapter_log("ch5"),
    benchmark:
        chapter_benchmark("ch5")


# Chapter 6.2 (reference studies): Yi 2025's joint-stiffness study on its robot (workspace,
# identification, maps, optimal pose) and Cai 2015's beam frame.
use rule chapter as ch6_stiffness with:
    input:
        **chapter_files("ch6_stiffness"),
        findings="results/stiffness/findings.yaml",
        maps="results/stiffness/maps.nc",
        optimal="results/stiffness/optimal_poses.csv",
        beamframe="results/stiffness/beamframe.nc",
        map_joints=f"results/stiffness/{MAP_ROBOT}/joint_stiffness.csv",
        map_models=f"results/stiffness/{MAP_ROBOT}/identification.csv",
        map_validation=f"results/stiffness/{MAP_ROBOT}/validation.csv",
    output:
        **chapter_outputs("ch6_stiffness"),
    log:
        chapter_log("ch6_stiffness"),
    benchmark:
        chapter_benchmark("ch6_stiffness")
