"""A one-screen summary of failed jobs, printed last when a workflow run fails.

The Snakefile's ``onerror:`` handler calls :func:`summarize_failures` with Snakemake's log.
For each failed job: the rule (and wildcards), the first line of its error (for bad data, our
``RawDataError`` message naming file and field), the job's log, and for chapters the kept
failed notebook.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

_ERROR_BLOCK = re.compile(r"^Error in rule (?P<rule>\S+):\s*$")
_FIELD = re.compile(r"^\s+(?P<key>\w+): (?P<value>.*)$")
_EXC_LINE = re.compile(
    r"^(?:[\w.]+\.)?(?P<name>\w*(?:Error|Exception|Exit|Interrupt))\b:? ?(?P<msg>.*)$"
)
_KEPT = re.compile(r"executed notebook kept at (?P<path>\S+)")


@dataclass
class FailedJob:
    rule: str
    wildcards: str
    logs: list[str]
    error: str
    notebook: str | None


def first_error_line(text: str) -> str:
    """The exception line of the last traceback in ``text`` (or its last non-empty line)."""
    lines = [ln.rstrip() for ln in text.splitlines() if ln.strip()]
    for ln in reversed(lines):
        m = _EXC_LINE.match(ln.strip())
        if m and not ln.startswith(" "):
            return f"{m['name']}: {m['msg']}".strip().rstrip(":")
    return lines[-1] if lines else "(empty log)"


_JOB_BLOCK = re.compile(r"^(?:local)?rule (?P<rule>\w+):\s*$")


def _wildcards_by_jobid(lines: list[str]) -> dict[str, str]:
    """``{jobid: wildcards}`` from the job announcements (the error blocks omit wildcards)."""
    out: dict[str, str] = {}
    i = 0
    while i < len(lines):
        if _JOB_BLOCK.match(lines[i]):
            fields = {}
            i += 1
            while i < len(lines) and (fm := _FIELD.match(lines[i])):
                fields[fm["key"]] = fm["value"]
                i += 1
            if "jobid" in fields and "wildcards" in fields:
                out[fields["jobid"].strip()] = fields["wildcards"].strip()
        else:
            i += 1
    return out


def parse_failed_jobs(snakemake_log: str) -> list[FailedJob]:
    """Failed jobs listed in a Snakemake log (``Error in rule …`` blocks)."""
    jobs: list[FailedJob] = []
    lines = snakemake_log.splitlines()
    wildcards = _wildcards_by_jobid(lines)
    i = 0
    while i < len(lines):
        m = _ERROR_BLOCK.match(lines[i])
        if not m:
            i += 1
            continue
        fields: dict[str, str] = {}
        i += 1
        while i < len(lines) and (fm := _FIELD.match(lines[i])):
            fields[fm["key"]] = fm["value"]
            i += 1
        logs = [p.strip() for p in
                fields.get("log", "").split(" (check log")[0].split(",") if p.strip()]
        error, notebook = "(no log)", None
        for p in logs:
            if Path(p).exists():
                text = Path(p).read_text(errors="replace")
                error = first_error_line(text)
                if km := _KEPT.search(text):
                    notebook = km["path"].rstrip(".;,")
                break
        if error == "(no log)" and "message" in fields and fields["message"] != "None":
            error = fields["message"]
        wc = fields.get("wildcards") or wildcards.get(fields.get("jobid", "").strip(), "")
        jobs.append(FailedJob(m["rule"], wc, logs, error, notebook))
    return jobs


_QUIET_SCRIPT = re.compile(r"scripts/tmp\w+\.(?P<rule>\w+)\.py' returned non-zero")
_RUN_START = re.compile(r"(?P<ts>\d{4}-\d\d-\d\dT\d{6})\.\d+\.snakemake\.log$")


def quiet_failed_jobs(snakemake_log: str, snakemake_log_path: str | Path,
                      logs_dir: str | Path = "results/logs") -> list[FailedJob]:
    """Failed script jobs of a quiet run (``snakemake -q`` writes no ``Error in rule`` block,
    only the failed script's command): the rule from the script's name, its log the job log
    under ``logs_dir`` written during this run whose path spells the rule
    (``results/logs/plan/make.log`` for ``plan_make``), else none named."""
    from datetime import datetime

    rules = list(dict.fromkeys(m["rule"] for m in _QUIET_SCRIPT.finditer(snakemake_log)))
    m = _RUN_START.search(Path(snakemake_log_path).name)
    start = datetime.strptime(m["ts"], "%Y-%m-%dT%H%M%S").timestamp() if m else 0.0
    fresh = [p for p in Path(logs_dir).rglob("*.log") if p.stat().st_mtime >= start - 1.0]
    jobs = []
    for rule in rules:
        own = [p for p in fresh
               if "_".join(p.relative_to(logs_dir).with_suffix("").parts) == rule]
        error = first_error_line(own[0].read_text(errors="replace")) if own else "(no log)"
        jobs.append(FailedJob(rule, "", [str(p) for p in own], error, None))
    return jobs


def summarize_failures(snakemake_log_path: str | Path | list | None) -> str:
    """The summary text for the failed jobs recorded in ``snakemake_log_path`` (Snakemake 9
    passes ``onerror`` a list of log files: the first existing one is used)."""
    if isinstance(snakemake_log_path, list | tuple):
        existing = [p for p in snakemake_log_path if p and Path(p).exists()]
        snakemake_log_path = existing[0] if existing else None
    if not snakemake_log_path or not Path(snakemake_log_path).exists():
        return "robomill: the run failed (no Snakemake log to summarize)."
    text = Path(snakemake_log_path).read_text(errors="replace")
    jobs = parse_failed_jobs(text) or quiet_failed_jobs(text, snakemake_log_path)
    if not jobs:
        return (f"robomill: the run failed before any job ran; see {snakemake_log_path}")
    out = [f"==== robomill: {len(jobs)} failed job(s) ===="]
    for j in jobs:
        what = j.rule + (f" ({j.wildcards})" if j.wildcards else "")
        out.append(f"- {what}: {j.error}")
        if j.logs:
            out.append(f"    log: {', '.join(j.logs)}")
        if j.notebook:
            out.append(f"    failed notebook: {j.notebook}")
    out.append(f"(full Snakemake log: {snakemake_log_path})")
    return "\n".join(out)
