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


def test_a_quiet_run_names_the_failed_script_job_and_its_error(tmp_path, monkeypatch):
    """``snakemake -q`` writes no ``Error in rule`` block: the rule comes from the failed
    script's name, its error from the job log written during the run."""
    from datetime import datetime, timedelta

    monkeypatch.chdir(tmp_path)
    (tmp_path / "results/logs/plan").mkdir(parents=True)
    (tmp_path / "results/logs/plan/make.log").write_text(
        "INFO start\nTraceback (most recent call last):\n  File z\n"
        "robomill.plan.choose.PlanInfeasible: plan.yaml: no candidate meets "
        "constraints.min_stability_margin\n")
    (tmp_path / "results/logs/plan/check.log").write_text("INFO fine\n")
    start = (datetime.now() - timedelta(minutes=1)).strftime("%Y-%m-%dT%H%M%S")
    slog = tmp_path / f"{start}.085317.snakemake.log"
    slog.write_text("Execute 1 jobs...\nRuleException:\nCalledProcessError in file "
                    "\"/w/workflow/rules/plan.smk\", line 100:\nCommand 'set -euo pipefail; "
                    " /w/.venv/bin/python /t/.snakemake/scripts/tmppeoe0xvk.plan_make.py' "
                    "returned non-zero exit status 1.\nExiting because a job execution failed.\n")
    text = summarize_failures(str(slog))
    assert "1 failed job(s)" in text
    assert "- plan_make: robomill.plan.choose.PlanInfeasible: plan.yaml: no candidate meets" \
        in text
    assert "results/logs/plan/make.log" in text and "check.log" not in text
