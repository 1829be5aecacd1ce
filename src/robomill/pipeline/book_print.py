"""The book as a printed document: one page holding every chapter, printed to ``book.pdf``.

:func:`print_document` joins the chapters into one page (``book_print.html``): a title page
with the study's one-line description (:func:`robomill.pipeline.design_tables.describe_design`),
a contents list in two parts, the study's chapters and the reference studies (the source
papers' reproductions that use no data of the study; the chapter registry's ``part``,
:func:`book_part`), whose entries
link to the chapters and carry their page numbers, then each chapter on a new page, the
reference studies behind a part title page. The print style keeps a heading with what follows it
(``break-after: avoid``), a table's caption with its table (the caption above it) and a figure
with its caption (below it), does not split figures, tables or table rows, wraps table cells
instead of clipping them behind a scroll bar, prints a table of more than
:data:`WIDE_TABLE_COLUMNS` columns on a landscape page (:func:`landscape_wide_tables`), folds
the code away and numbers the pages.

:func:`print_book` prints that page with headless Chromium twice: CSS ``target-counter()`` is
not supported by Chromium, so the first print gives the page on which each chapter starts
(read from the PDF's named destinations with poppler's ``pdfinfo -dests``: every contents
entry links to its chapter, and Chromium writes one destination per linked anchor), and the
second prints the contents with those numbers. Chromium's document outline
(``--generate-pdf-document-outline``) gives one PDF bookmark per chapter (its ``<h1>``), with
its sections below it.
"""

from __future__ import annotations

import html
import os
import re
import shutil
import subprocess
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path

from robomill.registry import PARTS, book_order, by_notebook

#: executable names tried, in order, by :func:`find_chromium` (``$ROBOMILL_CHROMIUM`` first)
CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")

#: prints of the book at most, until the contents' page numbers agree with the pages
MAX_PRINTS = 3

#: a table with more columns than this is printed on a landscape page of its own
#: (:func:`landscape_wide_tables`): 8 pt numbers of 8–10 characters, ~60 px a column, fill
#: the 182 mm (≈ 690 px) of a portrait A4 line at about 11 columns
WIDE_TABLE_COLUMNS = 10

_TABLE = re.compile(r"<table\b.*?</table>", re.S | re.I)
_ROW = re.compile(r"<tr\b.*?</tr>", re.S | re.I)
_CELL = re.compile(r"<t[hd]\b", re.I)

_TITLE = re.compile(r"<h1[^>]*>(?P<t>.*?)</h1>", re.S)
_TAG = re.compile(r"<[^>]+>")
_BODY = re.compile(r"<body[^>]*>(?P<b>.*)</body>", re.S)
_HEAD = re.compile(r"<head[^>]*>(?P<h>.*?)</head>", re.S)
_SCRIPT_SRC = re.compile(r"<script[^>]*\bsrc=[\"']https?:[^>]*>\s*</script>", re.S)

_PRINT_CSS = """
@page{size:A4;margin:16mm 14mm 18mm 14mm;
 @bottom-center{content:counter(page);font:9pt system-ui,sans-serif;color:#555}}
@page front{@bottom-center{content:none}}
@page wide{size:A4 landscape}
section.front{page:front}
section.title{text-align:center;padding-top:28vh;font-family:system-ui,sans-serif}
section.title .book-title{font-size:2.2em;font-weight:bold;margin-bottom:.8em}
section.title .description{font-size:1.15em;margin:0 8% 1.5em}
section.title .by{color:#555}
section.contents{break-before:page;font-family:system-ui,sans-serif}
section.contents .contents-title{font-size:1.6em;font-weight:bold;margin:0 0 1em}
ol.contents{list-style:none;padding:0;margin:0;font-size:11pt}
ol.contents li{display:flex;align-items:baseline;margin:.35em 0}
ol.contents li a{color:#222;text-decoration:none}
ol.contents li .leader{flex:1;border-bottom:1px dotted #888;margin:0 .4em}
ol.contents li .page{min-width:2em;text-align:right}
.contents .part-title{font-weight:bold;font-size:12pt;margin:1em 0 .3em}
section.part{break-before:page;font-family:system-ui,sans-serif;padding-top:30vh}
section.part .part-title{font-size:2em;font-weight:bold}
@media print{
 nav.robomill,details.robomill-code{display:none!important}
 section.chapter{break-before:page}
 div.wide-table{page:wide}
 .jp-OutputArea-child:has(p.caption):has(+.jp-OutputArea-child div.wide-table){page:wide}
 .jp-Cell:has(.jp-RenderedMarkdown>:is(h1,h2,h3,h4,h5,h6):last-child):has(
  +.jp-Cell .jp-OutputArea-child:first-child p.caption):has(
  +.jp-Cell .jp-OutputArea-child:first-child+.jp-OutputArea-child div.wide-table){page:wide}
 div.wide-table table{max-width:none!important}
 div.wide-table td,div.wide-table th{overflow-wrap:normal}
 h1,h2,h3,h4,h5,h6{break-after:avoid-page;break-inside:avoid-page}
 .jp-Cell:has(.jp-RenderedMarkdown>:is(h1,h2,h3,h4,h5,h6):last-child){break-after:avoid-page}
 .jp-Cell{break-inside:avoid-page}
 p.caption{break-inside:avoid-page;break-after:avoid-page}
 .jp-OutputArea-child:has(p.caption){break-after:avoid-page}
 .jp-OutputArea-child:is(:has(img),:has(.jp-RenderedImage))+.jp-OutputArea-child:has(p.caption){
  break-before:avoid-page}
 figure,img,tr,pre,.jp-RenderedImage{break-inside:avoid-page}
 img{max-width:100%!important;height:auto}
 .jp-OutputArea-output,.jp-RenderedHTMLCommon,.jp-RenderedHTML,div{overflow:visible!important}
 table{table-layout:auto!important;width:auto!important;max-width:100%!important;
  font-size:8pt!important}
 td,th{white-space:normal!important;overflow-wrap:anywhere;word-break:normal;
  max-width:none!important;padding:.2em .35em!important}
 pre{white-space:pre-wrap!important;overflow-wrap:anywhere}
 a.anchor-link{display:none!important}
}
"""


def chapter_title(html_text: str, fallback: str) -> str:
    """Text of the first ``<h1>`` of a rendered chapter (anchor links removed)."""
    m = _TITLE.search(html_text)
    if not m:
        return fallback
    text = html.unescape(_TAG.sub("", m["t"])).replace("¶", "").strip()
    return text or fallback


#: the book's two parts (the chapter registry's ``part``: ``study``, ``reference``)
STUDY_PART = PARTS["study"]
REFERENCE_PART = PARTS["reference"]


def chapter_key(stem: str, registry: str | Path | None = None) -> tuple:
    """Book order of a chapter page (file stem ``ch3_forces``): the study's chapters, then
    the reference studies, each in the chapter registry's order
    (:func:`robomill.registry.book_order`; ``registry``: another chapter table than the
    package's); pages that are no chapter last."""
    return book_order(stem, registry)


def book_part(stem: str, registry: str | Path | None = None) -> str:
    """The part of the book a chapter page belongs to (:data:`STUDY_PART` or
    :data:`REFERENCE_PART`: the registry row's ``part``; ``registry`` as in
    :func:`chapter_key`)."""
    row = by_notebook(registry).get(stem)
    return PARTS[row.part] if row is not None else STUDY_PART


def print_document(chapter_html: Sequence[str | Path], out_html: str | Path, *,
                   title: str = "Robotic milling quality — the study, reproduced",
                   description: str | None = None,
                   pages: Mapping[str, int] | None = None,
                   registry: str | Path | None = None) -> Path:
    """Every chapter in one page for printing: a title page (``title`` and the study's
    one-line ``description``), a contents list (each entry links to its chapter and shows
    ``pages[chapter name]`` when given), then each chapter's body on a new page in book
    order. Scripts fetched from the network (MathJax, require.js) are left out so the page
    prints offline. ``registry``: another chapter table than the package's."""
    paths = sorted(map(Path, chapter_html), key=lambda p: chapter_key(p.stem, registry))
    if not paths:
        raise ValueError("print_document: no chapter pages given")
    texts = [p.read_text(errors="replace") for p in paths]
    head = _HEAD.search(texts[0])
    head_html = _SCRIPT_SRC.sub("", head["h"]) if head else "<meta charset='utf-8'>"
    titles = [chapter_title(t, p.stem) for t, p in zip(texts, paths, strict=True)]
    parts = ['<section class="front title">',
             f'<div class="book-title">{html.escape(title)}</div>']
    if description:
        parts.append(f'<p class="description">{html.escape(description)}</p>')
    parts.append('<p class="by">computed by the robomill pipeline from this run\'s data</p>'
                 '</section><section class="front contents">'
                 '<div class="contents-title">Contents</div>')
    part = None
    for path, name in zip(paths, titles, strict=True):
        if book_part(path.stem, registry) != part:
            parts.append("</ol>" if part is not None else "")
            part = book_part(path.stem, registry)
            parts.append(f'<div class="part-title">{html.escape(part)}</div>'
                         '<ol class="contents">')
        page = (pages or {}).get(path.stem)
        parts.append(f'<li><a href="#{path.stem}">{html.escape(name)}</a>'
                     f'<span class="leader"></span><span class="page">'
                     f'{page if page is not None else "&nbsp;"}</span></li>')
    parts.append("</ol></section>")
    part = STUDY_PART
    for text, path in zip(texts, paths, strict=True):
        # the reference studies open with a part title page
        if book_part(path.stem, registry) != part:
            part = book_part(path.stem, registry)
            parts.append(f'<section class="part"><h1 class="part-title">{html.escape(part)}'
                         "</h1><p>Reproductions of the source papers that use no data of this "
                         "study.</p></section>")
        m = _BODY.search(text)
        body = m["b"] if m else text
        body = re.sub(r'<nav class="robomill">.*?</nav>', "", body, flags=re.S)
        body = landscape_wide_tables(body)
        parts.append(f'<section class="chapter" id="{path.stem}">{body}</section>')
    out = Path(out_html)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(f"<!DOCTYPE html><html><head>{head_html}<title>{html.escape(title)}</title>"
                   f"<style>{_PRINT_CSS}</style></head><body>{''.join(parts)}</body></html>")
    return out


def table_columns(table_html: str) -> int:
    """Columns of an HTML table: the most cells (``<th>``/``<td>``) in one of its rows."""
    return max((len(_CELL.findall(r)) for r in _ROW.findall(table_html)), default=0)


def landscape_wide_tables(body: str, max_columns: int = WIDE_TABLE_COLUMNS) -> str:
    """``body`` with every table of more than ``max_columns`` columns wrapped in
    ``<div class="wide-table">``, which the print style puts on a landscape A4 page (CSS
    named page ``wide``): printed whole, not clipped at the portrait page's edge."""
    return _TABLE.sub(lambda m: (f'<div class="wide-table">{m[0]}</div>'
                                 if table_columns(m[0]) > max_columns else m[0]), body)


def find_chromium() -> str | None:
    """The headless browser used to print the book, or None when none is installed."""
    named = os.environ.get("ROBOMILL_CHROMIUM")
    if named:
        return shutil.which(named) or (named if os.access(named, os.X_OK) else None)
    for name in CHROMIUM_NAMES:
        found = shutil.which(name)
        if found:
            return found
    return None


def print_pdf(page: str | Path, out_pdf: str | Path, *, chromium: str | None = None,
              timeout_s: float = 600) -> Path:
    """Print ``page`` to ``out_pdf`` with headless Chromium (``--print-to-pdf``, no browser
    header or footer, a document outline from the headings). Raises ``RuntimeError`` naming
    what to install when no browser is found, or with the browser's output when it wrote no
    PDF."""
    chromium = chromium or find_chromium()
    if not chromium:
        raise RuntimeError("cannot print the book to PDF: no Chromium found (tried "
                           f"{', '.join(CHROMIUM_NAMES)} and $ROBOMILL_CHROMIUM); install the "
                           "Debian package `chromium` (apt-get install chromium)")
    out = Path(out_pdf).resolve()
    out.parent.mkdir(parents=True, exist_ok=True)
    partial = out.with_name(out.name + ".partial")
    partial.unlink(missing_ok=True)
    with tempfile.TemporaryDirectory(prefix="robomill-chromium-") as profile:
        cmd = [chromium, "--headless", "--no-sandbox", "--disable-gpu",
               "--disable-dev-shm-usage", "--no-first-run", "--disable-background-networking",
               "--disable-component-update", "--disable-sync", f"--user-data-dir={profile}",
               "--no-pdf-header-footer", "--run-all-compositor-stages-before-draw",
               "--generate-pdf-document-outline",
               f"--print-to-pdf={partial}", Path(page).resolve().as_uri()]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout_s)
    if not partial.exists() or partial.stat().st_size == 0:
        raise RuntimeError(f"{chromium} wrote no PDF for {page} (exit {proc.returncode}):\n"
                           f"{proc.stderr[-2000:]}")
    partial.replace(out)
    return out


_DEST = re.compile(r"^\s*(?P<page>\d+)\s+\[.*?\]\s+\"(?P<name>[^\"]*)\"", re.M)


def destination_pages(pdf: str | Path) -> dict[str, int]:
    """``{anchor: page}`` of the PDF's named destinations (poppler's ``pdfinfo -dests``)."""
    exe = shutil.which("pdfinfo")
    if not exe:
        raise RuntimeError("cannot number the book's contents: pdfinfo not found; install the "
                           "Debian package `poppler-utils` (apt-get install poppler-utils)")
    out = subprocess.run([exe, "-dests", str(pdf)], capture_output=True, text=True,
                         check=True).stdout
    return {m["name"]: int(m["page"]) for m in _DEST.finditer(out)}


def print_book(chapter_html: Sequence[str | Path], out_html: str | Path,
               out_pdf: str | Path, *, description: str | None = None,
               chromium: str | None = None) -> dict[str, int]:
    """Print the book to ``out_pdf`` with a contents list that gives each chapter's first
    page, and return those pages ``{chapter name: page}``.

    The book is printed until the pages its contents state are the pages where the chapters
    start (twice, unless stating them moves a chapter), at most :data:`MAX_PRINTS` times.
    """
    names = [Path(p).stem for p in chapter_html]
    pages: dict[str, int] | None = None
    for _ in range(MAX_PRINTS):
        page = print_document(chapter_html, out_html, description=description, pages=pages)
        print_pdf(page, out_pdf, chromium=chromium)
        dests = destination_pages(out_pdf)
        found = {n: dests[n] for n in names if n in dests}
        if len(found) < len(names):
            missing = ", ".join(n for n in names if n not in found)
            raise RuntimeError(f"{out_pdf}: no PDF destination for chapter(s) {missing}")
        if found == pages:
            return pages
        pages = found
    raise RuntimeError(f"{out_pdf}: contents page numbers did not settle after {MAX_PRINTS} "
                       "prints")
