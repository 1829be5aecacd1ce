"""The chapter registry: one row per chapter page, in ``robomill/data/chapters.yaml``.

Every part of the project that needs to know the chapters reads them here: the workflow (each
chapter's target, notebook, template, figure folder, report caption, notebook parameters and
whether ``all`` builds it: ``workflow/rules/common.smk``), ``robomill check`` and ``robomill
manifest`` (what a raw folder must give for each chapter: :mod:`robomill.io.needs`), the book
(its order and its two parts: :mod:`robomill.pipeline.book_print`) and the numbering of figures
and tables of a chapter printed across pages (:meth:`robomill.pipeline.captions.Numbering.
for_chapter`). Adding a chapter is one row here, one notebook and one template
(``docs/chapters.md``).

The table read is the package's own (:data:`REGISTRY_FILE`, package data), or the file a
caller hands over explicitly (``path``); no environment variable chooses it. A copy of the
repository with a chapter of its own is a copy of the package, with its table.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

#: the package's chapter table
REGISTRY_FILE = Path(__file__).parent / "data" / "chapters.yaml"

#: the parts of the book, in order: part key -> the part's title
PARTS = {"study": "The study", "reference": "Reference studies"}

_FIELDS = {"id", "number", "title", "part", "notebook", "template", "figures", "report", "stage",
           "groups", "in_all", "needs", "requires", "parameters", "inputs", "first_figure",
           "first_table"}
_NEEDS = {"kinds", "experiment", "cut", "experiment_with_cuts"}
_PARAMETERS = {"experiment", "settings"}


class RegistryError(ValueError):
    """A row of the chapter table that cannot be read: the message names the file, the row
    and the field."""


@dataclass(frozen=True)
class Needs:
    """What one chapter reads from the raw folder.

    ``kinds``: raw-data kinds (``cuts`` for the manifest's cut list) that must all be present
    for the chapter to be built; ``experiment``: keys of the manifest's ``experiment`` it
    reads; ``cut``: keys every cut must carry; ``experiment_with_cuts``: experiment keys read
    only when the folder lists cuts (chapter 5's stiffness at every cut)."""

    kinds: tuple[str, ...] = ()
    experiment: tuple[str, ...] = ()
    cut: tuple[str, ...] = ()
    experiment_with_cuts: tuple[str, ...] = ()


@dataclass(frozen=True)
class Chapter:
    """One row of the chapter table (the fields are described in ``chapters.yaml``)."""

    id: str
    number: str
    title: str
    part: str
    notebook: str
    template: str
    figures: str
    report: str
    stage: str | None = None
    groups: tuple[str, ...] = ()
    in_all: bool = True
    needs: Needs = field(default_factory=Needs)
    requires: tuple[str, ...] = ()
    parameters: Mapping[str, Any] = field(default_factory=dict)
    inputs: Mapping[str, str] | None = None
    first_figure: int | None = None
    first_table: int | None = None

    @property
    def page(self) -> str:
        """The chapter's page, ``results/chapters/<notebook>.html``."""
        return f"results/chapters/{self.notebook}.html"

    @property
    def label(self) -> str:
        """The number as messages print it (``chapter 3.1: no force files``)."""
        return self.number

    @property
    def figure_prefix(self) -> str:
        """The chapter number of its figure labels: ``"3"`` for page 3.1 (Figure 3.12)."""
        return self.number.split(".")[0]

    @property
    def targets(self) -> tuple[str, ...]:
        """The Snakemake targets that build the chapter: its id, its groups."""
        return (self.id, *self.groups)


def _words(value: Any, where: str) -> tuple[str, ...]:
    if value is None:
        return ()
    if isinstance(value, str) or not isinstance(value, Sequence) or not all(
            isinstance(v, str) for v in value):
        raise RegistryError(f"{where}: expected a list of names, got {value!r}")
    return tuple(value)


def _row(raw: Any, where: str) -> Chapter:
    if not isinstance(raw, Mapping):
        raise RegistryError(f"{where}: expected a mapping of fields, got {raw!r}")
    unknown = sorted(set(raw) - _FIELDS)
    if unknown:
        raise RegistryError(f"{where}: unknown field(s) {unknown} (expected some of "
                            f"{sorted(_FIELDS)})")
    for key in ("id", "number", "title", "part"):
        if not isinstance(raw.get(key), str) or not raw[key]:
            raise RegistryError(f"{where}: field {key!r} missing or not text")
    cid = raw["id"]
    where = f"{where} ({cid})"
    if raw["part"] not in PARTS:
        raise RegistryError(f"{where}: part {raw['part']!r} (expected one of {list(PARTS)})")
    needs = raw.get("needs") or {}
    if not isinstance(needs, Mapping) or set(needs) - _NEEDS:
        raise RegistryError(f"{where}: needs: expected a mapping with keys among "
                            f"{sorted(_NEEDS)}, got {needs!r}")
    params = raw.get("parameters") or {}
    if not isinstance(params, Mapping) or set(params) - _PARAMETERS:
        raise RegistryError(f"{where}: parameters: expected a mapping with keys among "
                            f"{sorted(_PARAMETERS)}, got {params!r}")
    inputs = raw.get("inputs")
    if inputs is not None and not (isinstance(inputs, Mapping) and all(
            isinstance(k, str) and isinstance(v, str) for k, v in inputs.items())):
        raise RegistryError(f"{where}: inputs: expected a mapping name: path, got {inputs!r}")
    requires = _words(raw.get("requires"), f"{where}: requires")
    unknown_req = sorted(set(requires) - set(DESIGN_REQUIREMENTS))
    if unknown_req:
        raise RegistryError(f"{where}: requires: unknown condition(s) {unknown_req} (expected "
                            f"some of {sorted(DESIGN_REQUIREMENTS)})")
    for key in ("first_figure", "first_table"):
        if raw.get(key) is not None and not (isinstance(raw[key], int) and raw[key] >= 1):
            raise RegistryError(f"{where}: {key}: expected a whole number ≥ 1, got "
                                f"{raw[key]!r}")
    return Chapter(
        id=cid, number=str(raw["number"]), title=raw["title"], part=raw["part"],
        notebook=raw.get("notebook") or cid, template=raw.get("template") or cid,
        figures=raw.get("figures") or cid, report=raw.get("report") or cid,
        stage=raw.get("stage"), groups=_words(raw.get("groups"), f"{where}: groups"),
        in_all=bool(raw.get("in_all", True)),
        needs=Needs(**{k: _words(v, f"{where}: needs.{k}") for k, v in needs.items()}),
        requires=requires, parameters=dict(params),
        inputs=dict(inputs) if inputs is not None else None,
        first_figure=raw.get("first_figure"), first_table=raw.get("first_table"))


@cache
def _load(path: str) -> tuple[Chapter, ...]:
    import yaml

    try:
        rows = yaml.load(Path(path).read_text(),  # libyaml's loader where PyYAML has it
                         Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))
    except (OSError, yaml.YAMLError) as exc:
        raise RegistryError(f"{path}: cannot be read as YAML ({exc})") from None
    if not isinstance(rows, list) or not rows:
        raise RegistryError(f"{path}: expected a list of chapter rows")
    chapters = tuple(_row(r, f"{path}: row {i + 1}") for i, r in enumerate(rows))
    for key in ("id", "number", "notebook", "figures"):
        seen: dict[str, str] = {}
        for c in chapters:
            value = getattr(c, key)
            if value in seen:
                raise RegistryError(f"{path}: {key} {value!r} of chapter {c.id} is also "
                                    f"chapter {seen[value]}'s")
            seen[value] = c.id
    return chapters


def chapters(path: str | Path | None = None) -> tuple[Chapter, ...]:
    """Every chapter of the table at ``path`` (default :data:`REGISTRY_FILE`), in the order of
    the book within each part."""
    return _load(str(path if path is not None else REGISTRY_FILE))


def chapter(chapter_id: str, path: str | Path | None = None) -> Chapter:
    """The row of chapter ``chapter_id``."""
    for c in chapters(path):
        if c.id == chapter_id:
            return c
    raise KeyError(f"no chapter {chapter_id!r} in {path or REGISTRY_FILE}")


def by_notebook(path: str | Path | None = None) -> dict[str, Chapter]:
    """Page (notebook) stem -> chapter: ``ch3_forces`` -> the row of ``ch3_forces`` (the stem is
    the id unless a row names another notebook)."""
    return {c.notebook: c for c in chapters(path)}


def book_order(stem: str, path: str | Path | None = None) -> tuple[int, int]:
    """Book order of a chapter page ``stem``: the study's chapters, then the reference
    studies, each in the table's order; pages that are no chapter last."""
    rows = chapters(path)
    for i, c in enumerate(rows):
        if c.notebook == stem:
            return (list(PARTS).index(c.part), i)
    return (len(PARTS), len(rows))


def figure_range(chapter_id: str, kind: str,
                 path: str | Path | None = None) -> tuple[int, int | None]:
    """The figure (``kind="figure"``) or table numbers a page may use: ``(first, end)``, end
    excluded, None for open. Pages that share a chapter number (6.1, 6.2, 6.3) number across
    each other: a page starts at its ``first_figure``/``first_table`` and ends before the next
    page's of the same chapter number; a page without one starts at 1 and is open."""
    key = f"first_{kind}"
    this = chapter(chapter_id, path)
    first = getattr(this, key)
    if first is None:
        return (1, None)
    later = [getattr(c, key) for c in chapters(path)
             if c.figure_prefix == this.figure_prefix and getattr(c, key) is not None
             and getattr(c, key) > first]
    return (first, min(later) if later else None)


def _cutting_coefficients(cuts: Sequence, experiment: Mapping,
                          files: Sequence[Mapping]) -> str | None:
    """Why the force cuts cannot identify the cutting coefficients (one feed per tooth, fewer
    than 3 cuts), or None (:func:`robomill.forces.coefficients.design_not_identified`)."""
    from robomill.forces.coefficients import design_not_identified

    force_cuts = {f["cut"] for f in files if f.get("kind") == "force"}
    return design_not_identified(cuts, experiment, force_cuts)


#: conditions of a study's design that a chapter may require (field ``requires``): name ->
#: function ``(cuts, experiment, manifest files) -> None or the sentence saying why not``
DESIGN_REQUIREMENTS: dict[str, Callable[[Sequence, Mapping, Sequence[Mapping]], str | None]] = {
    "cutting_coefficients": _cutting_coefficients,
}

#: what each condition reads as, in a message (``chapter 4: the stability lobes need ...``)
REQUIREMENT_WORDS = {"cutting_coefficients": "the cutting coefficients"}


def unmet_requirement(name: str, cuts: Sequence, experiment: Mapping,
                      files: Sequence[Mapping]) -> str | None:
    """Why the study's design does not meet condition ``name`` (:data:`DESIGN_REQUIREMENTS`),
    or None."""
    return DESIGN_REQUIREMENTS[name](cuts, experiment, files)
