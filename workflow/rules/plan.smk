# Stage 'plan' (chapter 7): the next cuts from what was measured. The request is
# plan.yaml (config plan.request); each prediction's source is an input only when the raw
# folder has the measurements behind it (the plan says which prediction is missing).


from robomill.experiment import tracker_pass
from robomill.plan import NEXT_RUN_DIR

PLAN_REQUEST = config["plan"]["request"]
# every cut's chatter verdict, one row per cut and recording (columns cut, verdict, chatter_hz,
# source, evidence): the stability outcome of a run's cuts
STUDY_VERDICTS = "results/chatter/verdicts.csv"
STUDY_HAS_VERDICTS = any(STUDY_VERDICTS in map(str, r.output) for r in workflow.rules)
PLAN_MEASURED = {
    **(
        {"modes": "results/modal/modes.csv", "modal_fit": "results/modal/frf_synth.nc"}
        if has_kind("impact")
        else {}
    ),
    **(
        {
            "coefficients": "results/forces/cutting_coefficients.csv",
            "means": "results/forces/mean_forces.csv",
        }
        if has_kind("force")
        else {}
    ),
    **(
        {"joints": f"results/stiffness/{CELL_ROBOT}/joint_stiffness.csv"}
        if CELL_ROBOT in FOLDER_ROBOTS
        else {}
    ),
    # the gear lines and, for their component amplitudes, the runs' spectra
    **(
        {
            "peaks": "results/straightness/peaks.csv",
            "profiles": "results/straightness/profiles.nc",
        }
        if has_kind("tracker")
        else {}
    ),
}
PLAN_OUTPUTS = {
    "candidates": "results/plan/candidates.nc",
    "pose_map": "results/plan/pose_map.nc",
    "plan": "results/plan/plan.csv",
    "pareto": "results/plan/pareto.csv",
    "study": "results/plan/study_cuts.csv",
    "comparison": "results/plan/comparison.csv",
    "manifest": "results/plan/next/manifest.yaml",
    "config": "results/plan/next/config.yaml",
    "path_summary": "results/plan/path_summary.csv",
    # the production plan's binding interval (robomill.plan.binding), beside an earlier plan's
    "binding": "results/plan/binding.csv",
    # the study's cuts whose chatter verdicts conditioned the stability limit
    # (robomill.plan.conditioning)
    "evidence": "results/plan/evidence_used.csv",
    # the artefacts and parameters the plan read (robomill.plan.inputs): robomill predict
    # predicts any cuts from them with the same code
    "model": "results/plan/model.yaml",
}
# the controller program of the planned cuts and its stations.csv (robomill.plan.program)
PLAN_PROGRAM = "results/plan/next/program"
# an earlier plan's results/plan/binding.csv (config plan.binding_before; "" none)
PLAN_BINDING_BEFORE = config["plan"]["binding_before"]
# The planned cuts' own run (snakemake all --configfile results/plan/next/config.yaml, which
# writes under NEXT_RUN_DIR; on the virtual cell, or a lab's files of the planned cuts): its
# outcomes are inputs of plan_check once it has made them (another run of the workflow makes
# them, not this one). The planned cuts' outcomes come from these files only.
PLAN_NEXT_OUTCOMES = {
    name: f"{NEXT_RUN_DIR}/{path}"
    for name, path in (
        ("next_mean_forces", "results/forces/mean_forces.csv"),
        ("next_force_peaks", "results/forces/peaks.csv"),
        ("next_verdicts", "results/chatter/verdicts.csv"),
        ("next_deflection", "results/straightness/deflection.csv"),
        ("next_gears", "results/straightness/gears.csv"),
        ("next_profiles", "results/straightness/profiles.nc"),
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
        experiment=STUDY_EXPERIMENT,
        waviness_noise=config["plan"]["waviness_noise"],
        fmin_cycles=config["straightness"]["fmin_cycles"],
        level=config["plan"]["interval_level"],
        raw_folders=len(RAW_DIRS),
    script:
        "../scripts/plan_make.py"


rule plan_check:
    input:
        **(
            {"mean_forces": "results/forces/mean_forces.csv"}
            if has_kind("force")
            else {}
        ),
        # the waviness outcome: the tracker spectra at the attributed gear lines
        **(
            {
                "peaks": "results/straightness/peaks.csv",
                "gears": "results/straightness/gears.csv",
                "profiles": "results/straightness/profiles.nc",
            }
            if has_kind("tracker")
            else {}
        ),
        # the study's stability outcome: its chatter verdicts where a rule makes them, else
        # its force spectrum
        **({"verdicts": STUDY_VERDICTS} if STUDY_HAS_VERDICTS else {}),
        **({"force_peaks": "results/forces/peaks.csv"} if has_kind("force") else {}),
        # the study's static deflection, where it tracked a cut loaded and in the air
        **(
            {"deflection": "results/straightness/deflection.csv"}
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
    output:
        check="results/plan/check.csv",
        summary="results/plan/check_summary.csv",
        misses="results/plan/misses.csv",
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
        check="results/plan/check.csv",
        check_summary="results/plan/check_summary.csv",
        misses="results/plan/misses.csv",
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
        "results/plan/check.csv",
        "results/plan/check_summary.csv",
        "results/plan/misses.csv",
        "results/chapters/ch7.html",
