# Chapter 0 (the experiment) and the chapter 3 target. Every chapter is the one rule of
# chapter.smk used under its target's name; each chapter's lives with its stage file.


CHAPTER_PARAMETERS["ch0"] = EXPERIMENT_PARAM


use rule chapter as ch0 with:
    input:
        notebook=notebook("ch0_experiment.ipynb"),
        templates=notebook("templates/ch0.yaml"),
        findings="results/ingest/findings.yaml",
        cuts="results/ingest/cuts.csv",
    output:
        **chapter_outputs("ch0"),
    log:
        chapter_log("ch0"),
    benchmark:
        chapter_benchmark("ch0")


add_chapter("0", "results/chapters/ch0_experiment.html", needs=("cuts",))


rule ch3:
    input:
        "results/chapters/ch3_1_forces.html",
        "results/chapters/ch3_2_straightness.html",
        "results/chapters/ch3_3_modal.html",
