# Stage 'calibration' (thesis ch. 1): the C-Track simulator, identification of the
# geometric model, joint errors and compliance, and accuracy before/after.
CTRACK_TABLES = {f["table"]: f["path"] for f in RAW_FILES if f["kind"] == "ctrack"}


rule calibration_identify:
    input:
        data=kind_input("calibration", "ctrack"),
        study=STUDY,
        circles=f"{RAW}/{CTRACK_TABLES.get('circles', 'ctrack/circles.csv')}",
        home=f"{RAW}/{CTRACK_TABLES.get('home', 'ctrack/home.csv')}",
        steps=f"{RAW}/{CTRACK_TABLES.get('steps', 'ctrack/steps.csv')}",
        base=f"{RAW}/{CTRACK_TABLES.get('base', 'ctrack/base.csv')}",
        loads=f"{RAW}/{CTRACK_TABLES.get('loads', 'ctrack/loads.csv')}",
        cell=CELL,
        code=code_inputs("calibration_identify.py"),
    output:
        model=artefact("calibration.model"),
        joint_errors=artefact("calibration.joint_errors"),
        base=artefact("calibration.base"),
        circles=artefact("calibration.circles"),
    log:
        "results/logs/calibration/identify.log",
    benchmark:
        "results/benchmarks/rules/calibration/identify.tsv"
    conda:
        ENV
    params:
        calibration=config["calibration"],
        relpaths={k: v for k, v in CTRACK_TABLES.items() if k != "accuracy"},
        cell_relpath=CELL_RELPATH,
    script:
        "../scripts/calibration_identify.py"


rule calibration_accuracy:
    input:
        study=STUDY,
        model=artefact("calibration.model"),
        accuracy=f"{RAW}/{CTRACK_TABLES.get('accuracy', 'ctrack/accuracy.csv')}",
        code=code_inputs("calibration_accuracy.py"),
    output:
        accuracy=report(
            artefact("calibration.accuracy"),
            caption="../report/ch1.rst",
            category="Chapter 1",
            subcategory="Tables",
        ),
        regions=artefact("calibration.accuracy_by_region"),
        points=artefact("calibration.accuracy_points"),
    log:
        "results/logs/calibration/accuracy.log",
    benchmark:
        "results/benchmarks/rules/calibration/accuracy.tsv"
    conda:
        ENV
    params:
        regions=config["calibration"]["regions"],
        relpath=CTRACK_TABLES.get("accuracy", "ctrack/accuracy.csv"),
    script:
        "../scripts/calibration_accuracy.py"


# Chapter 1's findings: circle fits, regression, base deflection, accuracy; with the
# stage's scorecard rows ("Against the thesis").
rule calibration_findings:
    input:
        model=artefact("calibration.model"),
        accuracy=artefact("calibration.accuracy"),
        references=package_data("references.yaml"),
        code=code_inputs("calibration_findings.py"),
    output:
        findings=artefact("calibration.findings"),
    log:
        "results/logs/calibration/findings.log",
    benchmark:
        "results/benchmarks/rules/calibration/findings.tsv"
    conda:
        ENV
    params:
        thesis_study=THESIS_STUDY,
        holdout_every=config["calibration"]["error_model"]["holdout_every"],
    script:
        "../scripts/calibration_findings.py"


rule calibration:
    input:
        artefact("calibration.findings"),
        artefact("calibration.model"),
        artefact("calibration.accuracy"),


use rule chapter as ch1 with:
    input:
        **chapter_files("ch1"),
        findings=artefact("calibration.findings"),
        model=artefact("calibration.model"),
        accuracy=artefact("calibration.accuracy"),
        regions=artefact("calibration.accuracy_by_region"),
        points=artefact("calibration.accuracy_points"),
        joint_errors=artefact("calibration.joint_errors"),
        base=artefact("calibration.base"),
        circles=artefact("calibration.circles"),
    output:
        **chapter_outputs("ch1"),
    log:
        chapter_log("ch1"),
    benchmark:
        chapter_benchmark("ch1")
