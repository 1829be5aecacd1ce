# The chapters the registry describes whole (a row with `inputs`: chapter 0, and any chapter
# added by one row, a notebook and a template: docs/chapters.md), and the targets that build
# several chapters (a row's `groups`: `ch3`, `ch6`). The other chapters' rules live with their
# stage files (`use rule chapter as ch2 with:`), for inputs that depend on the raw folder.
for _c in CHAPTERS.values():
    if _c.inputs is None:
        continue

    rule:
        name:
            _c.id
        input:
            **chapter_files(_c.id),
            **_c.inputs,
        output:
            **chapter_outputs(_c.id),
        log:
            chapter_log(_c.id),
        benchmark:
            chapter_benchmark(_c.id)
        conda:
            ENV
        params:
            options=config["chapters"],
            failed_copy=chapter_failed_copy,
            parameters=chapter_parameters,
            shown=chapter_shown_parameters,
        script:
            "../scripts/render_chapter.py"


for _group in dict.fromkeys(g for c in CHAPTERS.values() for g in c.groups):

    rule:
        name:
            _group
        input:
            [c.page for c in CHAPTERS.values() if _group in c.groups],
