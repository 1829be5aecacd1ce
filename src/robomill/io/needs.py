"""What each chapter needs from a raw folder: the file kinds that feed it and the experiment and
cut keys of the manifest it reads, as the chapter registry (:mod:`robomill.registry`) states
them.

:data:`CHAPTER_NEEDS`, read by the manifest validator
(:func:`robomill.io.manifest.parse_manifest`), ``robomill manifest``, ``robomill check`` and
the workflow (``workflow/rules/common.smk``): a folder is asked only for the keys of the
chapters its kinds feed, so that an impact-test-only folder needs no spindle speed.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from robomill.registry import chapters


@dataclass(frozen=True)
class ChapterNeeds:
    """What one chapter reads from the raw folder (:class:`robomill.registry.Needs`, with the
    chapter's target).

    ``kinds``: raw-data kinds (``cuts`` for the manifest's cut list) that must all be present
    for the chapter to be built; ``experiment``: keys of the manifest's ``experiment`` it
    reads; ``cut``: keys every cut must carry; ``experiment_with_cuts``: experiment keys read
    only when the folder lists cuts (chapter 5's stiffness at every cut)."""

    target: str
    kinds: tuple[str, ...]
    experiment: tuple[str, ...] = ()
    cut: tuple[str, ...] = ()
    experiment_with_cuts: tuple[str, ...] = ()


CHAPTER_NEEDS: dict[str, ChapterNeeds] = {
    c.label: ChapterNeeds(c.id, c.needs.kinds, c.needs.experiment, c.needs.cut,
                          c.needs.experiment_with_cuts)
    for c in chapters() if c.in_all
}
"""Chapter label → what it needs, for the chapters ``all`` builds (the chapter registry's rows;
the chapters' own inputs follow from their rules)."""

def kind_present(kind: str, have: Iterable[str]) -> bool:
    """Whether ``have`` holds ``kind``; ``profile|areal`` is met by either alternative."""
    have = set(have)
    return any(k in have for k in kind.split("|"))


def fed_chapters(kinds: Iterable[str], has_cuts: bool) -> list[str]:
    """The chapters a folder with files of ``kinds`` (and cuts if ``has_cuts``) feeds."""
    have = set(kinds) | ({"cuts"} if has_cuts else set())
    return [label for label, n in CHAPTER_NEEDS.items()
            if all(kind_present(k, have) for k in n.kinds)]


def chapter_list(labels: Iterable[str]) -> str:
    """``chapter 2`` / ``chapters 0, 2`` for a message."""
    labels = list(labels)
    return ("chapter " if len(labels) == 1 else "chapters ") + ", ".join(labels)


def required_experiment_keys(kinds: Iterable[str], has_cuts: bool) -> dict[str, list[str]]:
    """Experiment key → the chapters (labels) that need it, for a folder with ``kinds``."""
    out: dict[str, list[str]] = {}
    for label in fed_chapters(kinds, has_cuts):
        n = CHAPTER_NEEDS[label]
        for key in n.experiment + (n.experiment_with_cuts if has_cuts else ()):
            out.setdefault(key, []).append(label)
    return out


def required_cut_keys(kinds: Iterable[str]) -> dict[str, list[str]]:
    """Cut key → the chapters that need it on every cut (a folder that lists cuts)."""
    out: dict[str, list[str]] = {}
    for label in fed_chapters(kinds, True):
        for key in CHAPTER_NEEDS[label].cut:
            out.setdefault(key, []).append(label)
    return out


def file_kinds(files: Iterable[Mapping]) -> set[str]:
    """The kinds of the manifest entries ``files`` (entries without a text kind skipped)."""
    return {f["kind"] for f in files if isinstance(f, Mapping) and isinstance(f.get("kind"), str)}
