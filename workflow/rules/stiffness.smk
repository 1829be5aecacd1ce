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
        code=code_inputs("stiffness_identify.py"),
    output:
        joints=artefact("stiffness.joint_stiffness"),
        models=artefact("stiffness.identification"),
        validation=artefact("stiffness.validation"),
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
        joints=artefact("stiffness.joint_stiffness", robot=MAP_ROBOT),
        study=STUDY,
        code=code_inputs("stiffness_map.py"),
    output:
        map=artefact("stiffness.map"),
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
        maps=[artefact("stiffness.map", height=h, angle=a) for h, a in MAP_JOBS],
        robot=robot_file(MAP_ROBOT),
        code=code_inputs("stiffness_maps.py"),
    output:
        maps=artefact("stiffness.maps"),
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
        maps=artefact("stiffness.maps"),
        robot=robot_file(MAP_ROBOT),
        joints=artefact("stiffness.joint_stiffness", robot=MAP_ROBOT),
        code=code_inputs("stiffness_optimal.py"),
    output:
        poses=report(
            artefact("stiffness.optimal_poses"),
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
    input:
        code=code_inputs("stiffness_beamframe.py"),
    output:
        beamframe=artefact("stiffness.beamframe"),
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
        joints=artefact("stiffness.joint_stiffness", robot=THESIS_ROBOT),
        study=STUDY,
        cell=CELL,
        code=code_inputs("stiffness_thesis.py"),
    output:
        slots=artefact("stiffness.thesis_slots"),
    log:
        "results/logs/stiffness/thesis.log",
    benchmark:
        "results/benchmarks/rules/stiffness/thesis.tsv"
    conda:
        ENV
    params:
        robot_rel=STIFF_REL.get(("robot", THESIS_ROBOT), ""),
        cell_relpath=CELL_RELPATH,
        beamframe=config["stiffness"]["beamframe"],
    script:
        "../scripts/stiffness_thesis.py"


# the cell's own robot at every cut (any design other than the thesis'): needs load tests of
# the robot named in cell.yaml
CUT_STIFFNESS = (
    {"cut_stiffness": artefact("stiffness.cut_stiffness")}
    if CELL_ROBOT in STIFF_ROBOTS and not THESIS_DESIGN
    else {}
)


rule stiffness_cuts:
    input:
        joints=artefact("stiffness.joint_stiffness", robot=CELL_ROBOT),
        study=STUDY,
        cell=CELL,
        code=code_inputs("stiffness_cuts.py"),
    output:
        cuts=artefact("stiffness.cut_stiffness"),
    log:
        "results/logs/stiffness/cuts.log",
    benchmark:
        "results/benchmarks/rules/stiffness/cuts.tsv"
    conda:
        ENV
    params:
        cell_relpath=CELL_RELPATH,
    script:
        "../scripts/stiffness_cuts.py"


STIFF_OUTPUTS = [
    artefact(name, robot=r)
    for r in STIFF_ROBOTS
    for name in ("stiffness.joint_stiffness", "stiffness.validation")
] + [artefact("stiffness.beamframe")]
if MAP_ROBOT in STIFF_ROBOTS and MAP_JOBS:
    STIFF_OUTPUTS += [
        artefact("stiffness.maps"),
        artefact("stiffness.optimal_poses"),
    ]
# the thesis robot at the thesis' slots, beside Table 2.1: for the thesis' design only
THESIS_SLOTS = (
    {
        "slots": artefact("stiffness.thesis_slots"),
        "waviness": artefact("surface.table_2_1_waviness_rms"),
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
        **optional_input(SYNTHETIC, truth=artefact("synthetic.truth")),
        **THESIS_SLOTS,
        **optional_input(
            bool(THESIS_SLOTS),
            thesis_joints=artefact("stiffness.joint_stiffness", robot=THESIS_ROBOT),
        ),
        **CUT_STIFFNESS,
        maps=artefact("stiffness.maps"),
        optimal=artefact("stiffness.optimal_poses"),
        beamframe=artefact("stiffness.beamframe"),
        joints=artefact("stiffness.joint_stiffness", robot=MAP_ROBOT),
        validation=artefact("stiffness.validation", robot=MAP_ROBOT),
        references=package_data("references.yaml"),
        # the scorecard checks: their reasons are quoted in the findings
        checks=package_data("scorecard.yaml"),
        code=code_inputs("stiffness_findings.py"),
    output:
        findings=artefact("stiffness.findings"),
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
    STIFF_OUTPUTS += [artefact("stiffness.findings")]


rule stiffness:
    input:
        STIFF_OUTPUTS,


use rule chapter as ch5 with:
    input:
        **THESIS_SLOTS,
        **CUT_STIFFNESS,
        **({"cuts": artefact("ingest.cuts")} if CUT_STIFFNESS else {}),
        **chapter_files("ch5"),
        findings=artefact("stiffness.findings"),
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
        findings=artefact("stiffness.findings"),
        maps=artefact("stiffness.maps"),
        optimal=artefact("stiffness.optimal_poses"),
        beamframe=artefact("stiffness.beamframe"),
        map_joints=artefact("stiffness.joint_stiffness", robot=MAP_ROBOT),
        map_models=artefact("stiffness.identification", robot=MAP_ROBOT),
        map_validation=artefact("stiffness.validation", robot=MAP_ROBOT),
    output:
        **chapter_outputs("ch6_stiffness"),
    log:
        chapter_log("ch6_stiffness"),
    benchmark:
        chapter_benchmark("ch6_stiffness")
