"""The book as a printed document (issue 30 part 4): title page with the study's description,
a contents list whose page numbers are the pages where the chapters start, one PDF bookmark
per chapter, and parameter tables without Python literals. The PDF tests print three small
chapters with headless Chromium and read the result back with poppler (pdftotext/pdfinfo),
independently of how the book computed its numbers."""

from __future__ import annotations

import re
import shutil
import subprocess
import zlib

import pytest
from conftest import missing_system_package

from robomill.pipeline import book_print
from robomill.pipeline.chapters import parameter_rows

DESCRIPTION = "6 cuts: 3 spindle speeds × 2 directions; constant: 3 flutes"


def _chapter(path, title, n_paragraphs):
    body = "".join(f"<p>Paragraph {k} of {title}. " + "Text " * 60 + "</p>"
                   for k in range(n_paragraphs))
    path.write_text(f"<!DOCTYPE html><html><head><meta charset='utf-8'></head><body>"
                    f"<h1>{title}</h1><h2>{title} section</h2>{body}</body></html>")
    return path


def _outline_titles(pdf_bytes: bytes) -> list[str]:
    """Titles of the PDF's outline items, read from the raw objects (compressed object
    streams inflated): every ``/Title (…)`` that belongs to an item with a ``/Parent``."""
    chunks = [pdf_bytes]
    for m in re.finditer(rb"stream\r?\n(.*?)endstream", pdf_bytes, re.S):
        try:
            chunks.append(zlib.decompress(m[1]))
        except zlib.error:
            continue
    titles = []
    for chunk in chunks:
        for m in re.finditer(rb"<<[^<>]*?/Title\s*\((.*?)\)[^<>]*?>>", chunk, re.S):
            if b"/Parent" in m[0]:
                titles.append(m[1].decode("latin-1"))
    return titles


@pytest.fixture(scope="module")
def printed(tmp_path_factory):
    if not book_print.find_chromium():
        missing_system_package("chromium not installed (Debian package chromium)")
    if not (shutil.which("pdftotext") and shutil.which("pdfinfo")):
        missing_system_package("pdftotext/pdfinfo not installed (Debian package poppler-utils)")
    d = tmp_path_factory.mktemp("book")
    pages = [_chapter(d / "ch0_plan.html", "Chapter Zero", 2),
             _chapter(d / "ch1_long.html", "Chapter One", 40),
             _chapter(d / "ch2_short.html", "Chapter Two", 3)]
    found = book_print.print_book(pages, d / "book_print.html", d / "book.pdf",
                                  description=DESCRIPTION)
    return d / "book.pdf", found


def _page_texts(pdf):
    n = int(re.search(r"Pages:\s+(\d+)", subprocess.run(
        ["pdfinfo", str(pdf)], capture_output=True, text=True, check=True).stdout)[1])
    return [subprocess.run(["pdftotext", "-f", str(k), "-l", str(k), "-layout", str(pdf), "-"],
                           capture_output=True, text=True, check=True).stdout
            for k in range(1, n + 1)]


@pytest.mark.browser
def test_title_page_holds_the_design_description(printed):
    pdf, _ = printed
    first = " ".join(_page_texts(pdf)[0].split())
    assert " ".join(DESCRIPTION.split()) in first


@pytest.mark.browser
def test_contents_page_numbers_are_where_the_chapters_start(printed):
    pdf, found = printed
    texts = _page_texts(pdf)
    contents = next(t for t in texts if "Contents" in t)
    for title in ("Chapter Zero", "Chapter One", "Chapter Two"):
        # the page where the chapter's heading is printed (the contents page excluded)
        start = next(k for k, t in enumerate(texts, 1)
                     if t is not contents and re.search(rf"^\s*{title}\s*$", t, re.M))
        listed = re.search(rf"{title}[ .]*?(\d+)\s*$", contents, re.M)
        assert listed, (title, contents)
        assert int(listed[1]) == start, (title, listed[1], start)
    # the long chapter spans several pages, so the third one starts later than the second + 1
    assert found["ch2_short"] > found["ch1_long"] + 1


@pytest.mark.browser
def test_one_bookmark_per_chapter(printed):
    pdf, _ = printed
    titles = _outline_titles(pdf.read_bytes())
    for title in ("Chapter Zero", "Chapter One", "Chapter Two"):
        assert titles.count(title) == 1, titles


def test_nested_parameters_are_key_value_rows_not_literals():
    rows = parameter_rows("experiment", {"spindle_rpm": 28000, "sets": [
        {"set": 1, "depth_mm": 0.5}, {"set": 2, "depth_mm": 1.0}], "dirs": ["px", "py"]},
        "dict")
    keys = [r[0] for r in rows]
    assert keys == ["experiment.spindle_rpm", "experiment.sets[0].set",
                    "experiment.sets[0].depth_mm", "experiment.sets[1].set",
                    "experiment.sets[1].depth_mm", "experiment.dirs"]
    assert dict((r[0], r[1]) for r in rows)["experiment.dirs"] == "px, py"
    assert not any("{" in r[1] or "[" in r[1] for r in rows)
    assert parameter_rows("empty", {}, "dict") == [("empty", "(empty)", "dict")]


def _sections_chapter(path, n_sections=40):
    """A chapter of ``n_sections`` headed sections of uneven length, so that headings fall
    at every height of a page; plus a table of 16 wide columns."""
    body = []
    for k in range(n_sections):
        words = 25 + (k * 37) % 110
        body.append(f"<h2>Section {k} heading</h2><p>" + f"Body{k} " * words + "</p>")
    head = "".join(f"<th>col{c}</th>" for c in range(16))
    rows = "".join("<tr>" + "".join(f"<td>{r}{c:02d}.45678</td>" for c in range(16))
                   + "</tr>" for r in range(1, 4))
    body.append(f"<div style='overflow-x:auto'><table><tr>{head}</tr>{rows}</table></div>")
    path.write_text("<!DOCTYPE html><html><head><meta charset='utf-8'></head><body>"
                    f"<h1>Chapter Three</h1>{''.join(body)}</body></html>")
    return path


def _print_sections(d, css=None, monkeypatch=None):
    if css is not None:
        monkeypatch.setattr(book_print, "_PRINT_CSS", css)
    page = book_print.print_document([_sections_chapter(d / "ch3_sections.html")],
                                     d / "book_print.html")
    book_print.print_pdf(page, d / "book.pdf")
    return _page_texts(d / "book.pdf")


def _headings_at_foot(texts):
    """Pages whose last line of text (the page number left out) is a section heading."""
    feet = []
    for k, t in enumerate(texts, 1):
        lines = [ln.strip() for ln in t.splitlines() if ln.strip()]
        if lines and lines[-1].isdigit():
            lines = lines[:-1]
        if lines and re.fullmatch(r"Section \d+ heading", lines[-1]):
            feet.append((k, lines[-1]))
    return feet


@pytest.mark.browser
def test_no_heading_alone_at_the_foot_of_a_page_and_wide_tables_print_whole(
        tmp_path, monkeypatch):
    """Printed, no page ends with a heading (it goes to the next page with its text), and
    every number of a 16-column table inside a scrolling box is on paper, on a landscape
    page (a portrait page clipped it from the eighth column on). The same chapter printed
    without the book's heading rule does leave a heading at a page foot: the check can
    fail."""
    if not book_print.find_chromium():
        missing_system_package("chromium not installed (Debian package chromium)")
    if not (shutil.which("pdftotext") and shutil.which("pdfinfo")):
        missing_system_package("pdftotext/pdfinfo not installed (Debian package poppler-utils)")
    (tmp_path / "book").mkdir()
    texts = _print_sections(tmp_path / "book")
    assert len(texts) > 4
    assert _headings_at_foot(texts) == []
    words = set(" ".join(texts).split())
    for r in range(1, 4):
        for c in range(16):
            assert f"{r}{c:02d}.45678" in words, (r, c)
    table_page = next(k for k, t in enumerate(texts, 1) if "115.45678" in t)
    size = subprocess.run(["pdfinfo", "-f", str(table_page), "-l", str(table_page),
                           str(tmp_path / "book" / "book.pdf")], capture_output=True,
                          text=True, check=True).stdout
    w, h = map(float, re.search(rf"Page\s+{table_page} size:\s+([\d.]+) x ([\d.]+)", size).groups())
    assert w > h  # landscape
    assert book_print.table_columns(book_print._TABLE.search(
        (tmp_path / "book" / "book_print.html").read_text())[0]) == 16
    # control: without keeping headings with what follows, some page ends with one
    loose = re.sub(r"\s*h1,h2,h3,h4,h5,h6\{[^}]*\}\n.*?break-after:avoid-page\}\n", "\n",
                   book_print._PRINT_CSS, flags=re.S)
    assert loose != book_print._PRINT_CSS
    (tmp_path / "loose").mkdir()
    assert _headings_at_foot(_print_sections(tmp_path / "loose", loose, monkeypatch))


def _captioned_tables_chapter(path, n_cells=8):
    """A chapter of notebook cells as nbconvert renders them, each longer than a page: three
    tables of 14 rows, each under its caption (``<p class="caption">``, a display output of
    its own before the table's), with prose of uneven length between them, so that captions
    fall at every height of a page."""
    cells = []
    for k in range(n_cells):
        outputs = []
        for j in range(3):
            words = 20 + (k * 53 + j * 31) % 140
            rows = "".join(f"<tr><td>r{r}</td><td>{k}.{j}.{r}</td></tr>" for r in range(14))
            outputs += [
                f"<div class='jp-OutputArea-child'><p>{'Prose ' * words}</p></div>",
                f"<div class='jp-OutputArea-child'><p class='caption'><b>Table 9.{3 * k + j}"
                f"</b> — caption {k}-{j}.</p></div>",
                f"<div class='jp-OutputArea-child'><table>{rows}</table></div>"]
        cells.append(f"<div class='jp-Cell'><div class='jp-OutputArea'>{''.join(outputs)}"
                     "</div></div>")
        # a section whose first output is the caption of a table too wide for a portrait
        # page (printed on a landscape page of its own, caption and heading with it)
        head = "".join(f"<th>c{c}</th>" for c in range(16))
        rows = "".join("<tr>" + "".join(f"<td>w{k}r{r}c{c}</td>" for c in range(16))
                       + "</tr>" for r in range(4))
        cells.append(
            "<div class='jp-Cell jp-MarkdownCell'><div class='jp-RenderedMarkdown'>"
            f"<h2>Wide section {k}</h2></div></div>"
            "<div class='jp-Cell'><div class='jp-OutputArea'>"
            f"<div class='jp-OutputArea-child'><p class='caption'><b>Table 9.{50 + k}</b> — "
            f"wide caption {k}.</p></div><div class='jp-OutputArea-child'><table><tr>{head}"
            f"</tr>{rows}</table></div></div></div>")
    path.write_text("<!DOCTYPE html><html><head><meta charset='utf-8'></head><body>"
                    f"<h1>Chapter Nine</h1>{''.join(cells)}</body></html>")
    return path


def _captions_at_foot(texts):
    """Pages whose last line of text (the page number left out) is a table's caption, a
    narrow or a wide table's (which of them fall at a page foot without the caption rules
    depends on the browser's layout: with Chromium 156 only wide tables' captions do in this
    chapter)."""
    feet = []
    for k, t in enumerate(texts, 1):
        lines = [ln.strip() for ln in t.splitlines() if ln.strip()]
        if lines and lines[-1].isdigit():
            lines = lines[:-1]
        if lines and re.match(r"Table 9\.\d+ — (wide )?caption", lines[-1]):
            feet.append((k, lines[-1]))
    return feet


@pytest.mark.browser
def test_a_table_caption_is_printed_on_the_page_of_its_table(tmp_path, monkeypatch):
    """Printed, no page ends with a table's caption (it goes to the next page with its
    table), even in a cell longer than a page, which the print style cannot keep whole; a
    table printed on a landscape page takes its caption and its section's heading with it.
    The same chapter printed without the caption rules leaves a caption at a page foot and
    a wide table's caption on the page before it."""
    if not book_print.find_chromium():
        missing_system_package("chromium not installed (Debian package chromium)")
    if not (shutil.which("pdftotext") and shutil.which("pdfinfo")):
        missing_system_package("pdftotext/pdfinfo not installed (Debian package poppler-utils)")

    def printed(folder, css=None):
        folder.mkdir()
        if css is not None:
            monkeypatch.setattr(book_print, "_PRINT_CSS", css)
        page = book_print.print_document(
            [_captioned_tables_chapter(folder / "ch9_tables.html")], folder / "book_print.html")
        book_print.print_pdf(page, folder / "book.pdf")
        return _page_texts(folder / "book.pdf")

    texts = printed(tmp_path / "book")
    assert len(texts) > 6
    assert sum(t.count("— caption") for t in texts) == 24  # every caption printed once
    assert _captions_at_foot(texts) == []
    for k in range(8):  # a wide table's page holds its heading and caption
        page = next(t for t in texts if f"w{k}r0c15" in t)
        assert f"wide caption {k}." in page and f"Wide section {k}" in page, k
    head, media = book_print._PRINT_CSS.split("@media print{", 1)
    rules = re.findall(r"[^{}]+\{[^{}]*\}", media)
    loose = head + "@media print{" + "".join(r for r in rules if "caption" not in r) + "\n}\n"
    assert loose != book_print._PRINT_CSS and "caption" not in loose
    texts = printed(tmp_path / "loose", loose)
    assert _captions_at_foot(texts)
    assert any(f"wide caption {k}." not in next(t for t in texts if f"w{k}r0c15" in t)
               for k in range(8))
