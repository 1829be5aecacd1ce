# Stage 'surface' (chapter 2): stylus profiles -> detrend, Gaussian waviness/roughness
# split, thesis spectra, segment RMS tables 2.1/2.2, peaks and their mechanism.
# One simulator job (virtual cell), one analysis job per cut (one for all the virtual cell's
# cuts), then one gather job.
SURFACE_FILES = {f["cut"]: f for f in RAW_FILES if f["kind"] == "profile"}
# Areal scans (kind areal): ISO 25178 parameters and spectra per scan; a cut with a scan and
# no stylus profile gets the scan's profile along the feed as its profile. A scan that cannot
# be analysed (only invalid points, unreadable) is left out with one line; the rest runs.
AREAL_FILES = {}
_AREAL = [f for f in RAW_FILES if f["kind"] == "areal"]
if _AREAL:  # (xarray is imported only for a folder with scans)
    from robomill.io.areal import scan_problem
for _f in _AREAL:
    _p = Path(f"{RAW}/{_f['path']}")
    _why = scan_problem(_p) if _p.exists() else None
    if _why is None:
        AREAL_FILES[_f["cut"]] = _f
    elif workflow.is_main_process:
        print(f"robomill: {_why}: scan left out", file=sys.stderr)
SURFACE_PROFILE_CUTS = [
    c.id for c in CUTS if c.id in SURFACE_FILES or c.id in AREAL_FILES
]
SURFACE_CUTS = {c.id: c.as_dict() for c in CUTS if c.id in SURFACE_PROFILE_CUTS}
# the thesis design gets Tables 2.1/2.2 and the thesis comparison; any other design one
# per-cut table grouped by what varies (robomill.surface.design_table)
SURFACE_THESIS = is_thesis_design([c for c in CUTS if c.id in SURFACE_PROFILE_CUTS])
SURFACE_TABLES = (
    {
        "waviness": artefact("surface.table_2_1_waviness_rms"),
        "roughness": artefact("surface.table_2_2_roughness_rms"),
        "comparison": artefact("surface.thesis_comparison"),
    }
    if SURFACE_THESIS
    else {"by_design": artefact("surface.metrics_by_design")}
)


rule surface_areal:
    input:
        raw=lambda w: f"{RAW}/{AREAL_FILES[w.cut]['path']}",
        study=STUDY,
        code=code_inputs("surface_areal.py"),
    output:
        nc=artefact("surface.areal_cut"),
        profile=artefact("surface.areal_profile"),
    log:
        "results/logs/surface/areal_{cut}.log",
    benchmark:
        "results/benchmarks/rules/surface/areal_{cut}.tsv"
    conda:
        ENV
    params:
        settings=config["surface"],
        relpath=lambda w: AREAL_FILES[w.cut]["path"],
        entry=lambda w: AREAL_FILES[w.cut],
    script:
        "../scripts/surface_areal.py"


rule surface_profile:
    input:
        # a cut's stylus profile, or the profile along the feed of its areal scan
        raw=lambda w: (
            f"{RAW}/{SURFACE_FILES[w.cut]['path']}"
            if w.cut in SURFACE_FILES
            else artefact("surface.areal_profile", cut=w.cut)
        ),
        study=STUDY,
        code=code_inputs("surface_profile.py"),
    output:
        nc=artefact("surface.cut"),
        peaks=artefact("surface.cut_peaks"),
    log:
        "results/logs/surface/profile_{cut}.log",
    benchmark:
        "results/benchmarks/rules/surface/profile_{cut}.tsv"
    conda:
        ENV
    params:
        settings=config["surface"],
        # a stylus profile is read from the raw folder (sha256 checked); a scan's profile
        # along the feed from its analysis (None: the input file itself)
        relpath=lambda w: [
            SURFACE_FILES[w.cut]["path"] if w.cut in SURFACE_FILES else None
        ],
        cut=lambda w: [SURFACE_CUTS[w.cut]],
    script:
        "../scripts/surface_profile.py"


# The virtual cell's profiles all come from one simulator job and always change together:
# there they are analysed in one job (the per-cut split would buy no caching, and each job
# pays ~1.5 s of start-up for ~0.2 s of work). A real file can change alone: one job per cut.
if SYNTHETIC and SURFACE_FILES:

    rule surface_profiles:
        input:
            raw=[f"{RAW}/{f['path']}" for f in SURFACE_FILES.values()],
            study=STUDY,
            code=code_inputs("surface_profile.py"),
        output:
            nc=[artefact("surface.cut", cut=c) for c in SURFACE_FILES],
            peaks=[artefact("surface.cut_peaks", cut=c) for c in SURFACE_FILES],
        log:
            "results/logs/surface/profiles.log",
        benchmark:
            "results/benchmarks/rules/surface/profiles.tsv"
        conda:
            ENV
        params:
            settings=config["surface"],
            relpath=[f["path"] for f in SURFACE_FILES.values()],
            cut=[SURFACE_CUTS[c] for c in SURFACE_FILES],
        script:
            "../scripts/surface_profile.py"

    ruleorder: surface_profiles > surface_profile


rule surface_gather:
    input:
        data=kind_input(
            "surface", "profile" if SURFACE_FILES or not AREAL_FILES else "areal"
        ),
        cuts=expand(artefact("surface.cut"), cut=SURFACE_PROFILE_CUTS),
        peaks=expand(artefact("surface.cut_peaks"), cut=SURFACE_PROFILE_CUTS),
        study=STUDY,
        code=code_inputs("surface_gather.py"),
    output:
        **{
            name: report(
                path,
                caption="../report/ch2.rst",
                category="Chapter 2",
                subcategory="Tables",
            )
            for name, path in SURFACE_TABLES.items()
        },
        peaks=artefact("surface.peaks"),
        metrics=artefact("surface.metrics"),
        spectra=artefact("surface.spectra"),
        profiles=artefact("surface.profiles"),
    log:
        "results/logs/surface/gather.log",
    benchmark:
        "results/benchmarks/rules/surface/gather.tsv"
    conda:
        ENV
    params:
        settings=config["surface"],
        cuts=list(SURFACE_CUTS.values()),
    script:
        "../scripts/surface_gather.py"


# Areal scans gathered: ISO 25178 parameters with each instrument's statements, the spectra,
# and for cuts with both a stylus profile and a scan the two side by side.
AREAL_OUTPUTS = {
    "areal": artefact("surface.areal"),
    "areal_spectra": artefact("surface.areal_spectra"),
    "profile_vs_areal": artefact("surface.profile_vs_areal"),
}
if AREAL_FILES:

    rule surface_areal_gather:
        input:
            scans=expand(artefact("surface.areal_cut"), cut=AREAL_FILES),
            profiles=expand(artefact("surface.areal_profile"), cut=AREAL_FILES),
            stylus=[
                artefact("surface.cut", cut=c)
                for c in AREAL_FILES
                if c in SURFACE_FILES
            ],
            code=code_inputs("surface_areal_gather.py"),
        output:
            **AREAL_OUTPUTS,
        log:
            "results/logs/surface/areal_gather.log",
        benchmark:
            "results/benchmarks/rules/surface/areal_gather.tsv"
        conda:
            ENV
        params:
            settings=config["surface"],
            cuts=list(AREAL_FILES),
            entries=list(AREAL_FILES.values()),
            stylus_cuts=[c for c in AREAL_FILES if c in SURFACE_FILES],
        script:
            "../scripts/surface_areal_gather.py"


# Profiles whose file states its own parameters (SMATS XML ROUGHNESS_/WAVINESS_SURFACE_
# PARAMETERS, kept in the manifest entry's `reference`): ours beside them, with the filter.
SURFACE_REFERENCE = [c for c, f in SURFACE_FILES.items() if f.get("reference")]
SURFACE_REFERENCE_CSV = artefact("surface.reference_comparison")
if SURFACE_REFERENCE:

    rule surface_reference:
        input:
            raw=[f"{RAW}/{SURFACE_FILES[c]['path']}" for c in SURFACE_REFERENCE],
            study=STUDY,
            code=code_inputs("surface_reference.py"),
        output:
            SURFACE_REFERENCE_CSV,
        log:
            "results/logs/surface/reference.log",
        benchmark:
            "results/benchmarks/rules/surface/reference.tsv"
        conda:
            ENV
        params:
            settings=config["surface"],
            cuts=SURFACE_REFERENCE,
            relpath=[SURFACE_FILES[c]["path"] for c in SURFACE_REFERENCE],
            reference=[SURFACE_FILES[c]["reference"] for c in SURFACE_REFERENCE],
        script:
            "../scripts/surface_reference.py"


rule surface_recovery:
    input:
        metrics=artefact("surface.metrics"),
        truth=artefact("synthetic.truth"),
        code=code_inputs("surface_recovery.py"),
    output:
        artefact("surface.recovery"),
    log:
        "results/logs/surface/recovery.log",
    benchmark:
        "results/benchmarks/rules/surface/recovery.tsv"
    conda:
        ENV
    script:
        "../scripts/surface_recovery.py"


# Chapter 2's findings: the numbers, flags and verdicts the chapter states (the mechanism per
# band against surface.mechanism_share_min, the resolution flag against
# surface.min_peak_cycles), with the stage's scorecard rows ("Against the thesis").
rule surface_findings:
    input:
        unpack(
            lambda w: {"recovery": artefact("surface.recovery")} if SYNTHETIC else {}
        ),
        unpack(
            lambda w: {"reference": SURFACE_REFERENCE_CSV} if SURFACE_REFERENCE else {}
        ),
        unpack(lambda w: AREAL_OUTPUTS if AREAL_FILES else {}),
        # Tables 2.1/2.2 and the thesis comparison (the scorecard reads the tables)
        **SURFACE_TABLES,
        metrics=artefact("surface.metrics"),
        peaks=artefact("surface.peaks"),
        profiles=artefact("surface.profiles"),
        cuts=artefact("ingest.cuts"),
        references=package_data("references.yaml"),
        # the scorecard checks: their reasons are quoted in the findings
        checks=package_data("scorecard.yaml"),
        code=code_inputs("surface_findings.py"),
    output:
        findings=artefact("surface.findings"),
    log:
        "results/logs/surface/findings.log",
    benchmark:
        "results/benchmarks/rules/surface/findings.tsv"
    conda:
        ENV
    params:
        settings=config["surface"],
        thesis_layout=SURFACE_THESIS,
        synthetic=SYNTHETIC,
        experiment=dict(EXPERIMENT),
        thesis_study=THESIS_STUDY,
    script:
        "../scripts/surface_findings.py"


rule surface:
    input:
        artefact("surface.findings"),
        list(SURFACE_TABLES.values()),
        artefact("surface.peaks"),
        artefact("surface.metrics"),
        artefact("surface.spectra"),
        optional_input(SYNTHETIC, artefact("surface.recovery")),
        optional_input(bool(SURFACE_REFERENCE), SURFACE_REFERENCE_CSV),
        optional_input(bool(AREAL_FILES), list(AREAL_OUTPUTS.values())),


use rule chapter as ch2 with:
    input:
        unpack(
            lambda w: {"recovery": artefact("surface.recovery")} if SYNTHETIC else {}
        ),
        unpack(
            lambda w: {"reference": SURFACE_REFERENCE_CSV} if SURFACE_REFERENCE else {}
        ),
        unpack(lambda w: AREAL_OUTPUTS if AREAL_FILES else {}),
        **SURFACE_TABLES,
        **chapter_files("ch2"),
        findings=artefact("surface.findings"),
        cuts=artefact("ingest.cuts"),
        peaks=artefact("surface.peaks"),
        metrics=artefact("surface.metrics"),
        spectra=artefact("surface.spectra"),
        profiles=artefact("surface.profiles"),
    output:
        **chapter_outputs("ch2"),
    log:
        chapter_log("ch2"),
    benchmark:
        chapter_benchmark("ch2")
