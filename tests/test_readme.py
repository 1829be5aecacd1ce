"""The README a newcomer reads in two minutes (issue 31.4): the two commands first, at most
about 120 lines, one picture, and links to the docs pages that hold the rest (each of which
exists)."""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
README = REPO / "README.md"
FIRST = (
    "# robomill\n\n```bash\n"
    "make all    # sets up .venv from environment.lock, then runs `snakemake -j2 all` on the "
    "synthetic default\n"
    "make test   # runs the test suite (unit tests, data-contract tests, the pipeline on the tiny "
    "config)\n```\n")


def test_the_readme_opens_with_the_two_commands_and_is_short():
    text = README.read_text()
    assert text.startswith(FIRST)
    assert len(text.splitlines()) <= 120


def test_every_local_link_and_the_picture_exist():
    text = README.read_text()
    links = re.findall(r"\]\(([^)#\s]+)\)", text)
    local = [t for t in links if not re.match(r"[a-z]+://", t)]
    assert {"docs/usage.md", "docs/own-data.md", "docs/configuration.md",
            "docs/performance.md", "docs/data-contract.md", "docs/artefacts.md"} <= set(local)
    for target in local:
        assert (REPO / target).exists(), target
    pictures = re.findall(r"!\[[^\]]+\]\(([^)]+\.png)\)", text)
    assert len(pictures) == 1 and (REPO / pictures[0]).stat().st_size > 10_000


def test_the_docs_pages_link_to_existing_pages():
    for page in ("usage", "own-data", "configuration", "performance", "performance-history"):
        text = (REPO / "docs" / f"{page}.md").read_text()
        for target in re.findall(r"\]\(([^)#\s]+\.md)\)", text):
            assert (REPO / "docs" / target).exists(), (page, target)


def test_the_four_commands_for_your_own_data_are_in_the_readme():
    text = README.read_text()
    for verb in ("robomill init", "robomill import", "robomill manifest", "robomill check",
                 "snakemake -j2 all --config data="):
        assert verb in text
