"""Parsing a Snakemake log into the one-screen failure summary."""

from robomill.pipeline.failures import first_error_line, parse_failed_jobs, summarize_failures

LOG = """\
[Mon Nov 23 16:35:04 2026]
Error in rule ch2:
    message: None
    jobid: 1
    input: notebooks/ch2.ipynb
    output: results/chapters/ch2.html
    log: {log1} (check log file(s) for error details)
Error in rule ingest_profile:
    jobid: 7
    wildcards: cut=s1_g1_px
    log: {log2} (check log file(s) for error details)
Exiting because a job execution failed.
"""


def test_summary_names_jobs_errors_logs_and_notebooks(tmp_path):
    log1 = tmp_path / "ch2.log"
    log1.write_text("Traceback (most recent call last):\n  File x\n"
                    "robomill.pipeline.chapters.ChapterError: chapter notebook n failed: cell 3: "
                    "KeyError:"
                    " 'x'; executed notebook kept at results/logs/chapters/ch2.failed.ipynb\n")
    log2 = tmp_path / "p.log"
    log2.write_text("INFO start\nTraceback (most recent call last):\n  File y\n"
                    "robomill.errors.RawDataError: profiles/s1_g1_px.csv: row 5, column z_um:"
                    " value 'abc' is not a number (expected a finite number)\n")
    slog = tmp_path / "snakemake.log"
    slog.write_text(LOG.format(log1=log1, log2=log2))
    jobs = parse_failed_jobs(slog.read_text())
    assert [j.rule for j in jobs] == ["ch2", "ingest_profile"]
    assert jobs[0].notebook == "results/logs/chapters/ch2.failed.ipynb"
    assert jobs[1].wildcards == "cut=s1_g1_px"
    text = summarize_failures(slog)
    assert "2 failed job(s)" in text
    assert "RawDataError: profiles/s1_g1_px.csv: row 5, column z_um" in text
    assert f"log: {log2}" in text


def test_first_error_line_falls_back_to_last_line():
    assert first_error_line("a\nsomething odd happened\n") == "something odd happened"
    assert first_error_line("") == "(empty log)"
