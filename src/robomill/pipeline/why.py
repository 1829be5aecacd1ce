"""Why would these jobs run? A short table from a Snakemake dry run.

``make why`` (or ``snakemake -n TARGET 2>&1 | python -m robomill.pipeline.why``) prints, for
each job that would run, its rule, wildcards and the reason, classified as one of: missing output,
input changed, code changed, params changed, software changed, upstream job reruns, forced.
"""

from __future__ import annotations

import re
import sys
from dataclasses import dataclass

_RULE = re.compile(r"^(?:local)?rule (?P<rule>\w+):\s*$")
_FIELD = re.compile(r"^\s+(?P<key>\w+): (?P<value>.*)$")

CATEGORIES = (
    ("Missing output files", "missing output"),
    ("Updated input files", "input changed"),
    ("Code has changed", "code changed"),
    ("Params have changed", "params changed"),
    ("Software environment definition has changed", "software changed"),
    ("Input files updated by another job", "upstream job reruns"),
    ("Forced execution", "forced"),
    ("Set of input files has changed", "input set changed"),
)


@dataclass
class PlannedJob:
    rule: str
    wildcards: str
    reason: str

    @property
    def categories(self) -> list[str]:
        found = [label for key, label in CATEGORIES if key.lower() in self.reason.lower()]
        return found or ["other"]


def parse_dry_run(text: str) -> list[PlannedJob]:
    """Jobs (rule, wildcards, reason) in the output of ``snakemake -n``."""
    jobs, current = [], None
    for line in text.splitlines():
        if m := _RULE.match(line):
            current = {"rule": m["rule"], "wildcards": "", "reason": ""}
            jobs.append(current)
        elif current is not None and (f := _FIELD.match(line)):
            if f["key"] in ("wildcards", "reason"):
                current[f["key"]] = f["value"].strip()
        elif not line.strip():
            current = None
    return [PlannedJob(**j) for j in jobs]


def format_table(jobs: list[PlannedJob], width: int = 110) -> str:
    if not jobs:
        return "Nothing would run: every target is up to date."
    rows = [("rule", "wildcards", "why", "details")]
    for j in jobs:
        detail = j.reason if len(j.reason) < 70 else j.reason[:67] + "..."
        rows.append((j.rule, j.wildcards, ", ".join(j.categories), detail))
    w = [max(len(r[i]) for r in rows) for i in range(3)]
    lines = [f"{r[0]:<{w[0]}}  {r[1]:<{w[1]}}  {r[2]:<{w[2]}}  {r[3]}"[:width] for r in rows]
    lines.insert(1, "-" * min(width, len(lines[0]) + 10))
    return "\n".join(lines) + f"\n{len(jobs)} job(s) would run."


def main() -> int:
    print(format_table(parse_dry_run(sys.stdin.read())))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
