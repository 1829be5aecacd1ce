# Stage 'plan' (chapter 7): the next cuts from what was measured. The request is
# plan.yaml (config plan.request); each prediction's source is an input only when the raw
# folder has the measurements behind it (the plan says which prediction is missing).


from robomill.experiment import tracker_pass
from robomill.plan import NEXT_RUN_DIR

PLAN_REQUEST = config["plan"]["request"]
# every cut's chatter verdict, one row per cut and recording (columns cut, verdict, chatter_hz,
# source, evidence): the stability outcome of a run's cuts
STUDY_VERDICTS = artefact("chatter.verdicts")
STUDY_HAS_VERDICTS = STUDY_VERDICTS in map(str, rules.chatter_verdicts.output)
PLAN_MEASURED = {
    **(
        {"modes": artefact("modal.modes"), "modal_fit": artefact("modal.frf_synth")}
        if has_kind("impact")
        else {}
    ),
    **(
        {
            "coefficients": artefact("forces.cutting_coefficients"),
            "means": artefact("forces.mean_forces"),
        }
        if has_kind("force")
        else {}
    ),
    **(
        {"joints": artefact("stiffness.joint_stiffness", robot=CELL_ROBOT)}
        if CELL_ROBOT in FOLDER_ROBOTS
        else {}
    ),
    # the gear lines and, for their component amplitudes, the runs' spectra
    **(
        {
            "peaks": artefact("straightness.peaks"),
            "profiles": artefact("straightness.profiles"),
        }
        if has_kind("tracker")
        else {}
    ),
}
PLAN_OUTPUTS = {
    "candidates": artefact("plan.candidates"),
    "pose_map": artefact("plan.pose_map"),
    "plan": artefact("plan.plan"),
    "pareto": artefact("plan.pareto"),
    "study": artefact("plan.study_cuts"),
    "comparison": artefact("plan.comparison"),
    "manifest": artefact("plan.next_manifest"),
    "config": artefact("plan.next_config"),
    "path_summary": artefact("plan.path_summary"),
    # the production plan's binding interval (robomill.plan.binding), beside an earlier plan's
    "binding": artefact("plan.binding"),
    # the study's cuts whose chatter verdicts conditioned the stability limit
    # (robomill.plan.conditioning)
    "evidence": artefact("plan.evidence_used"),
    # the artefacts and parameters the plan read (robomill.plan.inputs): robomill predict
    # predicts any cuts from them with the same code
    "model": artefact("plan.model"),
}
# the controller program of the planned cuts and its stations.csv (robomill.plan.program)
PLAN_PROGRAM = artefact("plan.next_program")
# an earlier plan's results/plan/binding.csv (config plan.binding_before; "" none)
PLAN_BINDING_BEFORE = config["plan"]["binding_before"]
# The planned cuts' own run (snakemake all --configfile results/plan/next/config.yaml, which
# writes under NEXT_RUN_DIR; on the virtual cell, or a lab's files of the planned cuts): its
# outcomes are inputs of plan_check once it has made them (another run of the workflow makes
# them, not this one). The planned cuts' outcomes come from these files only.
PLAN_NEXT_OUTCOMES = {
    name: f"{NEXT_RUN_DIR}/{path}"
    for name, path in (
        ("next_mean_forces", artefact("forces.mean_forces")),
        ("next_force_peaks", artefact("forces.peaks")),
        ("next_verdicts", artefact("chatter.verdicts")),
        ("next_deflection", artefact("straightness.deflection")),
        ("next_gears", artefact("straightness.gears")),
        ("next_profiles", artefact("straightness.profiles")),
    )
    if os.path.exists(f"{NEXT_RUN_DIR}/{path}")
}


rule plan_make:
    input:
        **PLAN_MEASURED,
        **({"binding_before": PLAN_BINDING_BEFORE} if PLAN_BINDING_BEFORE else {}),
        # the study's chatter verdicts: evidence on the stability limit
        **({"verdicts": STUDY_VERDICTS} if STUDY_HAS_VERDICTS else {}),
        request=PLAN_REQUEST,
        cell=CELL,
        study=STUDY,
        code=code_inputs("plan_make.py"),
    output:
        **PLAN_OUTPUTS,
        program=directory(PLAN_PROGRAM),
    log:
        "results/logs/plan/make.log",
    benchmark:
        "results/benchmarks/rules/plan/make.tsv"
    conda:
        ENV
    params:
        waviness_noise=config["plan"]["waviness_noise"],
        fmin_cycles=config["straightness"]["fmin_cycles"],
        level=config["plan"]["interval_level"],
        raw_folders=len(RAW_DIRS),
    script:
        "../scripts/plan_make.py"


rule plan_check:
    input:
        **({"mean_forces": artefact("forces.mean_forces")} if has_kind("force") else {}),
        # the waviness outcome: the tracker spectra at the attributed gear lines
        **(
            {
                "peaks": artefact("straightness.peaks"),
                "gears": artefact("straightness.gears"),
                "profiles": artefact("straightness.profiles"),
            }
            if has_kind("tracker")
            else {}
        ),
        # the study's stability outcome: its chatter verdicts where a rule makes them, else
        # its force spectrum
        **({"verdicts": STUDY_VERDICTS} if STUDY_HAS_VERDICTS else {}),
        **({"force_peaks": artefact("forces.peaks")} if has_kind("force") else {}),
        # the study's static deflection, where it tracked a cut loaded and in the air
        **(
            {"deflection": artefact("straightness.deflection")}
            if any(
                f["kind"] == "tracker" and tracker_pass(f) == "air" for f in RAW_FILES
            )
            else {}
        ),
        **PLAN_NEXT_OUTCOMES,
        plan=PLAN_OUTPUTS["plan"],
        study=PLAN_OUTPUTS["study"],
        # the band the impact test measured (attribute modal_band_hz), for the misses
        candidates=PLAN_OUTPUTS["candidates"],
        # the cuts whose verdicts the stability limit was conditioned on: in-sample
        evidence=PLAN_OUTPUTS["evidence"],
        code=code_inputs("plan_check.py"),
    output:
        check=artefact("plan.check"),
        summary=artefact("plan.check_summary"),
        misses=artefact("plan.misses"),
    log:
        "results/logs/plan/check.log",
    benchmark:
        "results/benchmarks/rules/plan/check.tsv"
    conda:
        ENV
    params:
        tolerance=config["plan"]["check_tolerance"],
        # a folder, not a prefix of the inputs (they exist only once the run has made them)
        next_run=lambda w: NEXT_RUN_DIR,
        chatter_fraction_of_mean=config["plan"]["chatter_fraction_of_mean"],
        nominal_coverage=config["plan"]["interval_level"],
        waviness_noise=config["plan"]["waviness_noise"],
        fmin_cycles=config["straightness"]["fmin_cycles"],
    script:
        "../scripts/plan_check.py"


use rule chapter as ch7 with:
    input:
        **chapter_files("ch7"),
        candidates=PLAN_OUTPUTS["candidates"],
        pose_map=PLAN_OUTPUTS["pose_map"],
        plan=PLAN_OUTPUTS["plan"],
        pareto=PLAN_OUTPUTS["pareto"],
        study=PLAN_OUTPUTS["study"],
        comparison=PLAN_OUTPUTS["comparison"],
        path_summary=PLAN_OUTPUTS["path_summary"],
        binding=PLAN_OUTPUTS["binding"],
        evidence=PLAN_OUTPUTS["evidence"],
        check=artefact("plan.check"),
        check_summary=artefact("plan.check_summary"),
        misses=artefact("plan.misses"),
        program=PLAN_PROGRAM,
        cell=CELL,
        request=PLAN_REQUEST,
    output:
        **chapter_outputs("ch7"),
    log:
        chapter_log("ch7"),
    benchmark:
        chapter_benchmark("ch7")


# `all` builds the study; `plan` builds the plan from it and chapter 7
rule plan:
    input:
        *PLAN_OUTPUTS.values(),
        PLAN_PROGRAM,
        artefact("plan.check"),
        artefact("plan.check_summary"),
        artefact("plan.misses"),
        "results/chapters/ch7.html",
