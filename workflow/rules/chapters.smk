# Chapter 0 (the experiment) and the pattern every chapter rule follows: the notebook is an
# input, the executed .ipynb, the .html and the figure folder are outputs. Each chapter's own
# rule lives with its stage file; `chN` targets are rule names.


rule ch0:
    input:
        notebook=notebook("ch0_experiment.ipynb"),
        cuts="results/ingest/cuts.csv",
    output:
        ipynb="results/chapters/ch0_experiment.ipynb",
        html=report(
            "results/chapters/ch0_experiment.html",
            caption="../report/ch0.rst",
            category="Chapter 0",
        ),
        figures=report(
            directory("results/figures/ch0"),
            patterns=["{name}.png"],
            caption="../report/ch0.rst",
            category="Chapter 0",
            subcategory="Figures",
        ),
    log:
        "results/logs/chapters/ch0.log",
    benchmark:
        "results/benchmarks/rules/chapters/ch0.tsv"
    conda:
        ENV
    params:
        options=config["chapters"],
        failed_copy="results/logs/chapters/ch0.failed.ipynb",
        parameters=DESIGN_PARAMS,
    script:
        "../scripts/render_chapter.py"


add_chapter("0", "results/chapters/ch0_experiment.html", needs=("cuts",))


rule ch3:
    input:
        "results/chapters/ch3_1_forces.html",
        "results/chapters/ch3_2_straightness.html",
        "results/chapters/ch3_3_modal.html",
