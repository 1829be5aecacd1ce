"""What each chapter needs from a raw folder: the file kinds that feed it and the experiment and
cut keys of the manifest it reads (issue 32 point 3).

One table, :data:`CHAPTER_NEEDS`, read by the manifest validator
(:func:`robomill.io.manifest.parse_manifest`), ``robomill manifest``, ``robomill check`` and
the workflow (``workflow/rules/common.smk``): a folder is asked only for the keys of the
chapters its kinds feed, so that an impact-test-only folder needs no spindle speed.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass


@dataclass(frozen=True)
class ChapterNeeds:
    """What one chapter reads from the raw folder.

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
    # the cut table: feed per tooth and tooth passing of every cut
    "0": ChapterNeeds("ch0", ("cuts",), ("spindle_rpm", "flutes"), ("feed_mm_s", "depth_mm")),
    "1": ChapterNeeds("ch1", ("ctrack",)),
    # waviness/roughness per cut; peaks named by tooth passing and feed per tooth
    "2": ChapterNeeds("ch2", ("profile",), ("spindle_rpm", "flutes"),
                      ("feed_mm_s", "depth_mm")),
    # the chip model of the coefficient fit: speed, flutes, tool diameter, feed and depth
    "3.1": ChapterNeeds("ch3_forces", ("force",), ("spindle_rpm", "flutes", "tool_diameter_mm"),
                        ("feed_mm_s", "depth_mm")),
    # tracker runs carry their own feed and direction; the surface peaks beside them
    "3.2": ChapterNeeds("ch3_straightness", ("tracker", "profile")),
    "3.3": ChapterNeeds("ch3_modal", ("impact",)),
    # lobes at the study's spindle speed and flutes, recommendations at its depths
    "4": ChapterNeeds("ch4", ("impact", "force"), ("spindle_rpm", "flutes"), ("depth_mm",)),
    # the robots' joint stiffness; with cuts, the stiffness at the middle of every cut
    "5": ChapterNeeds("ch5", ("robot", "stiffness"), experiment_with_cuts=("cut_length_mm",)),
    # chapter 6, the reference studies: seed 002 and the published lobe cases, seed 001's
    # robot and seed 004's frame (their load tests), seed 003's hexapod
    "6.1": ChapterNeeds("ch6_chatter", ()),
    "6.2": ChapterNeeds("ch6_stiffness", ("robot", "stiffness")),
    "6.3": ChapterNeeds("ch6_hexapod", ()),
}
"""Chapter label → what it needs (the chapters' own inputs follow from their rules)."""

STAGE_KINDS: dict[str, tuple[str, ...]] = {
    "calibration": ("ctrack",),
    "surface": ("profile",),
    "forces": ("force",),
    "straightness": ("tracker",),
    "modal": ("impact",),
    "chatter": ("impact", "force"),
    "stiffness": ("robot", "stiffness"),
}
"""The kinds each stage's analysis reads (``results/<stage>/``; target ``<stage>``)."""


def fed_chapters(kinds: Iterable[str], has_cuts: bool) -> list[str]:
    """The chapters a folder with files of ``kinds`` (and cuts if ``has_cuts``) feeds."""
    have = set(kinds) | ({"cuts"} if has_cuts else set())
    return [label for label, n in CHAPTER_NEEDS.items() if set(n.kinds) <= have]


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
