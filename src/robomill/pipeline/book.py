"""The thesis book: every rendered chapter in one self-contained folder.

``build_book`` copies the chapter pages and figures into ``results/thesis/``, adds a
navigation bar (index, previous, next) to each chapter, and writes ``index.html``: a title page
with the experiment, a table of contents, the numbered figures of each chapter ("Figure 2.3",
from the figure file names ``fig2_3_<slug>.png``), the scorecard when there is one, and the
run's provenance. Every link is relative, so the folder can be copied anywhere.

The print-ready ``book.pdf`` (title page, numbered contents, bookmarks) is made by
:mod:`robomill.pipeline.book_print`, whose functions stay importable from here.
"""

from __future__ import annotations

import html
import re
import shutil
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from robomill.pipeline.book_print import (  # noqa: F401  (public names, kept importable here)
    CHROMIUM_NAMES,
    book_part,
    chapter_key,
    chapter_title,
    find_chromium,
    print_book,
    print_document,
    print_pdf,
)
from robomill.pipeline.design_tables import describe_design

_FIG = re.compile(r"^fig(?P<ch>\d+)_(?P<num>\d+)(?:_(?P<slug>.*))?$")


@dataclass
class ChapterPage:
    name: str  # e.g. ch2
    title: str
    html_path: Path
    figures: list[tuple[str, str, Path]]  # (label "Figure 2.3", caption, png path)


def figure_label(png: Path) -> tuple[str, str]:
    """("Figure N.M", caption from the slug) for ``figN_M_slug.png``."""
    m = _FIG.match(png.stem)
    if not m:
        return png.stem, ""
    caption = (m["slug"] or "").replace("_", " ")
    return f"Figure {int(m['ch'])}.{int(m['num'])}", caption


def collect_chapters(chapter_html: Sequence[str | Path], figures_root: str | Path
                     ) -> list[ChapterPage]:
    """Chapter pages in order, each with its figures from ``figures_root/chN[/part]``."""
    pages = []
    for p in sorted(map(Path, chapter_html), key=lambda p: chapter_key(p.stem)):
        name = p.stem
        m = re.match(r"ch(\d+)(?:_(\d+))?_(.+)", name)
        if m and m[2]:
            fig_dir = Path(figures_root) / f"ch{m[1]}" / m[3]
        else:
            fig_dir = Path(figures_root) / name.split("_")[0]
        figs = []
        for png in sorted(fig_dir.glob("*.png"), key=lambda q: _figure_key(q.stem)):
            label, caption = figure_label(png)
            figs.append((label, caption, png))
        pages.append(ChapterPage(name, chapter_title(p.read_text(errors="replace"), name), p,
                                 figs))
    return pages


def _figure_key(stem: str) -> tuple:
    m = _FIG.match(stem)
    return (int(m["ch"]), int(m["num"]), stem) if m else (999, 999, stem)


_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;max-width:1100px;
margin:2em auto;padding:0 1em;color:#222;line-height:1.45}
h1{border-bottom:2px solid #345;padding-bottom:.3em}
table{border-collapse:collapse;margin:1em 0;font-size:.9em}
td,th{border:1px solid #ccc;padding:.25em .6em;text-align:left}
th{background:#eef}
.figs{display:flex;flex-wrap:wrap;gap:12px}
.figs figure{width:250px;margin:0}
.figs img{width:250px;border:1px solid #ddd}
figcaption{font-size:.8em}
.pass{color:#161}.miss{color:#a11}
"""
_NAV_CSS = """
nav.robomill{position:sticky;top:0;background:#f4f6fa;border-bottom:1px solid #ccd;
padding:.4em 1em;font-family:system-ui,sans-serif;z-index:1000}
nav.robomill a{margin-right:1.2em}
"""


def _nav(prev: ChapterPage | None, nxt: ChapterPage | None) -> str:
    parts = ['<nav class="robomill"><a href="../index.html">Contents</a>']
    if prev:
        parts.append(f'<a href="{prev.name}.html">← {html.escape(prev.title)}</a>')
    if nxt:
        parts.append(f'<a href="{nxt.name}.html">{html.escape(nxt.title)} →</a>')
    parts.append("</nav>")
    return "".join(parts)


def _span(values: pd.Series, fmt: str) -> str:
    lo, hi = float(values.min()), float(values.max())
    return format(lo, fmt) if lo == hi else f"{format(lo, fmt)}–{format(hi, fmt)}"


def experiment_line(cuts: pd.DataFrame) -> str:
    """The title page's line on the experiment, from ``results/ingest/cuts.csv``: the cuts,
    the sets where the design has them, and the range of spindle speed, feed and depth (one
    value where all cuts share it), e.g. ``45 cuts in 3 sets; spindle 28000 rpm; feed
    1–10 mm/s; depth 0.25–1 mm``."""
    sets = cuts["set"].dropna().nunique() if "set" in cuts else 0
    parts = [f"{len(cuts)} cuts" + (f" in {sets} sets" if sets > 1 else "")]
    if "spindle_hz" in cuts and cuts["spindle_hz"].notna().any():
        parts.append(f"spindle {_span(60 * cuts['spindle_hz'].dropna(), '.0f')} rpm")
    for col, name, unit in (("feed_mm_s", "feed", "mm/s"), ("depth_mm", "depth", "mm")):
        if col in cuts and cuts[col].notna().any():
            parts.append(f"{name} {_span(cuts[col].dropna(), 'g')} {unit}")
    return "; ".join(parts)


def build_book(
    chapter_html: Sequence[str | Path],
    figures_root: str | Path,
    out_dir: str | Path,
    *,
    provenance: Mapping[str, str],
    cuts_csv: str | Path | None = None,
    scorecard_csv: str | Path | None = None,
    benchmarks_csv: str | Path | None = None,
    skipped: Mapping[str, str] | None = None,
    pdf_name: str | None = None,
) -> Path:
    """Write the book into ``out_dir`` and return the path of ``index.html``.

    ``skipped`` maps the label of every chapter left out of the run (``"3.3"``) to the reason
    (``"no impact files in manifest.yaml"``): a partial raw folder builds what it has data
    for, and the book says what is missing and why. ``pdf_name`` (``"book.pdf"``), when given,
    is linked from the contents as the print-ready book (written beside the index by
    :func:`print_pdf`).
    """
    out = Path(out_dir)
    if out.exists():
        for sub in ("chapters", "figures"):
            shutil.rmtree(out / sub, ignore_errors=True)
    (out / "chapters").mkdir(parents=True, exist_ok=True)
    pages = collect_chapters(chapter_html, figures_root)
    for i, page in enumerate(pages):
        text = page.html_path.read_text(errors="replace")
        nav = _nav(pages[i - 1] if i > 0 else None, pages[i + 1] if i + 1 < len(pages) else None)
        header = f"<style>{_NAV_CSS}</style>{nav}"
        text = re.sub(r"(<body[^>]*>)", lambda m, h=header: m[1] + h, text, count=1)
        (out / "chapters" / f"{page.name}.html").write_text(text)
        for _, _, png in page.figures:
            dst = out / "figures" / page.name / png.name
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(png, dst)

    body = ["<h1>Robotic milling quality — the study, reproduced</h1>",
            "<p>Calibration, surface spectra, cutting forces, path straightness against "
            "gear-mesh frequencies, modal identification, chatter and stiffness of this run's "
            "robot cell, computed by the robomill pipeline from this run's data, then the "
            "reference studies of the source papers.</p>"]
    if cuts_csv and Path(cuts_csv).exists() and len(cuts := pd.read_csv(cuts_csv)):
        body.append(f"<p><b>The experiment:</b> {experiment_line(cuts)}.</p>")
        body.append(f"<p><b>The design:</b> {html.escape(describe_design(cuts))}.</p>")
    body.append("<h2>Contents</h2>")
    part = None
    for page in pages:
        if book_part(page.name) != part:
            body.append("</ol>" if part is not None else "")
            part = book_part(page.name)
            body.append(f"<h3>{html.escape(part)}</h3><ol>")
        body.append(f'<li><a href="chapters/{page.name}.html">{html.escape(page.title)}</a> '
                    f"({len(page.figures)} figures)</li>")
    body.append("</ol>" if part is not None else "")
    body.append("<h3>Tables and print</h3><ol>")
    extra = []
    if pdf_name:
        extra.append(f'<li><a href="{html.escape(pdf_name)}">The whole book, print-ready '
                     "(PDF)</a></li>")
    if scorecard_csv and Path(scorecard_csv).exists():
        if Path(scorecard_csv).resolve() != (out / "scorecard.csv").resolve():
            shutil.copyfile(scorecard_csv, out / "scorecard.csv")
        card = pd.read_csv(scorecard_csv)
        if len(card):
            extra.append('<li><a href="scorecard.html">Reproduction scorecard</a></li>')
        else:  # not the thesis' design: nothing to compare with its numbers
            extra.append("<li>Reproduction scorecard: none (this study is not the thesis' "
                         "design)</li>")
        _write_table_page(out / "scorecard.html", "Reproduction scorecard", card,
                          verdict_col="verdict")
    if benchmarks_csv and Path(benchmarks_csv).exists():
        extra.append('<li><a href="benchmarks.html">Benchmarks</a></li>')
        _write_table_page(out / "benchmarks.html", "Benchmarks", pd.read_csv(benchmarks_csv))
    body.extend(extra)
    body.append("</ol>")
    if skipped:
        body.append("<h2>Not built from this data</h2><ul>")
        for label, why in skipped.items():
            body.append(f"<li>chapter {html.escape(str(label))}: {html.escape(str(why))}</li>")
        body.append("</ul>")
    for page in pages:
        if not page.figures:
            continue
        body.append(f'<h3><a href="chapters/{page.name}.html">{html.escape(page.title)}</a>'
                    '</h3><div class="figs">')
        for label, caption, png in page.figures:
            rel = f"figures/{page.name}/{png.name}"
            body.append(f'<figure><a href="{rel}"><img src="{rel}" alt="{label}"></a>'
                        f"<figcaption><b>{label}</b> {html.escape(caption)}</figcaption>"
                        "</figure>")
        body.append("</div>")
    body.append("<h2>Provenance of this run</h2><table>")
    for k, v in provenance.items():
        body.append(f"<tr><th>{html.escape(k)}</th><td>{html.escape(str(v))}</td></tr>")
    body.append("</table>")
    index = out / "index.html"
    index.write_text(_page("robomill — the study", "\n".join(body)))
    return index


def add_benchmarks_page(out_dir: str | Path, benchmarks_csv: str | Path) -> Path:
    """Write ``benchmarks.html`` into an existing book from ``make bench``'s summary.csv and
    link it from the contents (``make bench`` runs after the book was built)."""
    out = Path(out_dir)
    page = out / "benchmarks.html"
    _write_table_page(page, "Benchmarks", pd.read_csv(benchmarks_csv))
    index = out / "index.html"
    if index.exists():
        text = index.read_text()
        if 'href="benchmarks.html"' not in text:
            text = text.replace("</ol>", '<li><a href="benchmarks.html">Benchmarks</a></li></ol>',
                                1)
            index.write_text(text)
    return page


def _page(title: str, body: str) -> str:
    return (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}"
            f"</title><style>{_CSS}{_NAV_CSS}</style></head><body>{body}</body></html>")


def _write_table_page(path: Path, title: str, df: pd.DataFrame,
                      verdict_col: str | None = None) -> None:
    table = df.to_html(index=False, escape=True, na_rep="")
    if verdict_col:
        table = table.replace("<td>pass</td>", '<td class="pass">pass</td>').replace(
            "<td>miss</td>", '<td class="miss">miss</td>')
    path.write_text(_page(title, f'<nav class="robomill"><a href="index.html">Contents</a>'
                                 f"</nav><h1>{html.escape(title)}</h1>{table}"))
