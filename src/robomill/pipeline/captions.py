"""Numbered figures and tables for the chapters, so that the prose can refer to them.

A chapter declares its figures and tables once, near the top, in the order they appear::

    num = Numbering("2")
    num.figure("detrend", "Measured and detrended profile", number=9)   # Figure 2.9
    num.table("rms", "RMS by the segment method, beside the thesis")   # Table 2.1

and then writes ``f"… as {num.ref('detrend')} shows …"`` in its prose (declared figures can
be referred to before they appear), saves with ``num.file('detrend')`` (the figure file name
``fig2_9_detrend`` that the book's index reads,
:func:`robomill.pipeline.book.figure_label`) and puts ``num.caption('detrend')`` under the
figure. :meth:`Numbering.check` at the end of the chapter refuses a figure or table that
was declared but never shown or never referred to.

Numbers follow the thesis where a figure reproduces one of its figures (``number=9`` for the
thesis' Fig. 2.9); otherwise they continue after the largest number used so far. Several
panels of one thesis figure share its number and carry a letter (``part="a"``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path


@dataclass
class _Item:
    kind: str  # "Figure" or "Table"
    key: str
    caption: str
    number: int
    part: str = ""
    stem: str | None = None
    shown: bool = False
    referred: bool = False

    @property
    def label(self) -> str:
        return f"{self.kind} {{chapter}}.{self.number}{self.part}"


@dataclass
class Numbering:
    """Figure and table numbers of one chapter (``chapter`` as printed: ``"2"``, ``"3"``).

    Parameters
    ----------
    chapter
        The chapter number that prefixes every label (``"3"`` gives ``Figure 3.12``).
    fig_dir
        The chapter's figure folder, where :meth:`show` saves.
    """

    chapter: str
    fig_dir: str | None = None
    #: kind ("Figure", "Table") -> the numbers this page may use, (first, end) with end
    #: excluded or None: a chapter printed across pages (:meth:`for_chapter`)
    ranges: dict[str, tuple[int, int | None]] = field(default_factory=dict)
    _items: dict[str, _Item] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.fig_dir is not None:  # a chapter: its figure style and inline backend apply
            import robomill.plotting  # noqa: F401  from the first figure on

    def _add(self, kind: str, key: str, caption: str, number: int | None, part: str,
             stem: str | None = None) -> str:
        if key in self._items:
            raise ValueError(f"{kind.lower()} {key!r} is declared twice in chapter "
                             f"{self.chapter}")
        first, end = self.ranges.get(kind, (1, None))
        if number is None:
            used = [i.number for i in self._items.values() if i.kind == kind]
            number = max(used, default=first - 1) + 1
        if number < first or (end is not None and number >= end):
            last = f"{self.chapter}.{end - 1}" if end is not None else "on"
            raise ValueError(f"{kind} {self.chapter}.{number} ({key!r}) is outside this "
                             f"page's numbers, {kind} {self.chapter}.{first} to {last} "
                             "(the chapter registry's first_figure/first_table)")
        label = (kind, int(number), part)
        for other in self._items.values():
            if (other.kind, other.number, other.part) == label:
                raise ValueError(f"{kind} {self.chapter}.{number}{part} is used by both "
                                 f"{other.key!r} and {key!r}")
        self._items[key] = _Item(kind, key, caption, int(number), part, stem)
        return self.label(key)

    @classmethod
    def for_chapter(cls, chapter_id: str, fig_dir: str | None = None,
                    registry: str | Path | None = None) -> Numbering:
        """The numbering of chapter ``chapter_id`` as the chapter registry gives it
        (:mod:`robomill.registry`): labels prefixed by its chapter number (page 3.1:
        ``Figure 3.12``), and on a page of a chapter printed across pages (6.1-6.3) only the
        figure and table numbers of that page (:func:`robomill.registry.figure_range`).
        ``registry``: another chapter table than the package's."""
        from robomill.registry import chapter, figure_range

        return cls(chapter(chapter_id, registry).figure_prefix, fig_dir=fig_dir, ranges={
            "Figure": figure_range(chapter_id, "figure", registry),
            "Table": figure_range(chapter_id, "table", registry)})

    def figure(self, key: str, caption: str, number: int | None = None, part: str = "",
               stem: str | None = None) -> str:
        """Declare a figure; returns its label (``"Figure 2.9"``). ``stem`` overrides the
        file name :meth:`file` gives (for files named before this numbering)."""
        return self._add("Figure", key, caption, number, part, stem)

    def table(self, key: str, caption: str, number: int | None = None, part: str = "") -> str:
        """Declare a table; returns its label (``"Table 2.1"``)."""
        return self._add("Table", key, caption, number, part)

    def _item(self, key: str) -> _Item:
        try:
            return self._items[key]
        except KeyError:
            raise KeyError(f"no figure or table {key!r} declared in chapter {self.chapter}; "
                           f"declared: {', '.join(self._items) or 'none'}") from None

    def label(self, key: str) -> str:
        """``"Figure 2.9"`` for a declared key (not counted as a reference)."""
        return self._item(key).label.format(chapter=self.chapter)

    def ref(self, key: str) -> str:
        """The label, for use in prose; marks the figure or table as referred to."""
        item = self._item(key)
        item.referred = True
        return self.label(key)

    def file(self, key: str) -> str:
        """Figure file name without suffix, ``fig<chapter>_<number>_<key>`` (dots in the
        chapter become underscores: chapter ``"3"`` and number 12 give ``fig3_12_<key>``)."""
        item = self._item(key)
        if item.stem:
            return item.stem
        return f"fig{self.chapter.replace('.', '_')}_{item.number}_{item.key}"

    def caption_text(self, key: str) -> str:
        """``"Figure 2.9 — Measured and detrended profile."`` (marks the item as shown)."""
        item = self._item(key)
        item.shown = True
        text = item.caption.rstrip()
        if text and text[-1] not in ".?!":
            text += "."
        return f"{self.label(key)} — {text}"

    def caption(self, key: str):
        """The caption as an IPython Markdown object (bold label), to ``display`` under the
        figure or above the table."""
        from IPython.display import Markdown

        text = self.caption_text(key)
        label = self.label(key)
        return Markdown(f'<p class="caption"><b>{label}</b>{text[len(label):]}</p>')

    def show(self, fig, key: str) -> None:
        """Save ``fig`` as ``<fig_dir>/<file(key)>.png``
        (:func:`robomill.plotting.save_figure`), show that file inline (not drawn a second
        time) and put its caption under it."""
        import matplotlib.pyplot as plt
        from IPython.display import display

        from robomill.plotting import save_figure, saved_image

        if self.fig_dir is None:
            raise ValueError(f"chapter {self.chapter}: Numbering(fig_dir=...) is needed to save "
                             f"figure {key!r}")
        path = save_figure(fig, self.fig_dir, self.file(key))
        display(saved_image(path, fig.dpi, alt=self.caption_text(key)))
        plt.close(fig)
        display(self.caption(key))

    def labels(self) -> list[str]:
        """Every declared label, in declaration order."""
        return [self.label(k) for k in self._items]

    def check(self) -> None:
        """Raise ``ValueError`` naming every declared figure or table that was never shown
        (:meth:`caption`) or never referred to (:meth:`ref`); call it in the last cell."""
        problems = [f"{self.label(i.key)} ({i.key!r}) never " +
                    " and never ".join(w for w, bad in (("shown", not i.shown),
                                                        ("referred to", not i.referred)) if bad)
                    for i in self._items.values() if not (i.shown and i.referred)]
        if problems:
            raise ValueError(f"chapter {self.chapter}: " + "; ".join(problems))
