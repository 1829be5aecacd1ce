# The one chapter rule. Every chapter is this rule used under its target's name
# (`use rule chapter as ch2 with:`), so that `snakemake -j2 ch2` keeps working: its stage file
# gives only the chapter's inputs (each named input is a notebook parameter) and its other
# notebook parameters come from the chapter registry (robomill.registry, CHAPTERS of
# common.smk), as do its outputs, log and benchmark. A chapter whose registry row lists its
# `inputs` needs no stage file: chapters.smk makes its rule.
# The notebook is an input; the executed .ipynb, the .html and the figure folder are outputs.


# The template itself builds nothing: its outputs are named by the target, as each chapter's
# own are (results/chapters/ch2.html, results/figures/ch2), and Snakemake picks the chapter's
# copy, a rule without wildcards.
rule chapter:
    input:
        notebook=lambda w: chapter_files(w.target)["notebook"],
    output:
        ipynb="results/chapters/{target}.ipynb",
        html="results/chapters/{target}.html",
        figures=directory("results/figures/{target}"),
    log:
        "results/logs/chapters/{target}.log",
    benchmark:
        "results/benchmarks/rules/chapters/{target}.tsv"
    wildcard_constraints:
        target="|".join(CHAPTERS),
    conda:
        ENV
    params:
        options=config["chapters"],
        failed_copy=chapter_failed_copy,
        parameters=chapter_parameters,
        shown=chapter_shown_parameters,
    script:
        "../scripts/render_chapter.py"
