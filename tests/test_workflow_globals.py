"""No globals shared between the workflow's stage files: a value one stage needs from another
travels as a file or through the chapter registry, never as a name one .smk file defines and
another reads by include order. Only common.smk (the helpers every rule file shares, included
first) and chapter.smk (the one chapter rule) define names the others read."""

from __future__ import annotations

import re

from conftest import REPO

RULES = REPO / "workflow" / "rules"
SHARED = {"common.smk", "chapter.smk"}
_DEFINED = re.compile(r"^(?:def\s+)?([A-Za-z_]\w*)\s*(?:\(|=(?!=)|:\s*\w[^=\n]*=(?!=))", re.M)


def defined_names(text: str) -> set[str]:
    """Names a rule file defines at its top level: assignments and functions (not rules)."""
    names = set()
    for m in _DEFINED.finditer(text):
        line = text[m.start():text.find("\n", m.start())]
        if line.startswith("def ") or re.match(r"[A-Za-z_]\w*\s*=(?!=)", line):
            names.add(m[1])
    return names - {"rule", "use", "include", "wildcard_constraints", "localrules"}


def cross_file_reads(files: dict[str, str]) -> list[tuple[str, str, str]]:
    """``(reader, name, definer)`` for each name a stage file reads that another stage file
    defines."""
    out = []
    for definer, text in files.items():
        if definer in SHARED:
            continue
        for name in defined_names(text):
            for reader, other in files.items():
                if reader != definer and re.search(rf"\b{re.escape(name)}\b", other):
                    out.append((reader, name, definer))
    return sorted(out)


def test_no_stage_file_reads_another_stage_files_names():
    files = {p.name: p.read_text() for p in sorted(RULES.glob("*.smk"))}
    files["Snakefile"] = (REPO / "Snakefile").read_text()
    assert len(files) > 10
    assert cross_file_reads(files) == []


def test_the_check_finds_a_shared_global():
    """As before: chapter 4 read forces.smk's COEFFICIENTS_NOT_IDENTIFIED."""
    files = {"forces.smk": "FORCE_FILES = {}\nCOEFFICIENTS_NOT_IDENTIFIED = why(CUTS)\n",
             "chatter.smk": "rule a:\n    params:\n        x=COEFFICIENTS_NOT_IDENTIFIED,\n",
             "common.smk": "CUTS = []\n"}
    assert cross_file_reads(files) == [("chatter.smk", "COEFFICIENTS_NOT_IDENTIFIED",
                                        "forces.smk")]
