"""What a printed page of a PDF holds: its figures' scale and type sizes, and how full it is.

Typst places each figure (a PDF of its own) as a form XObject.  Reading the page's
content stream with its graphics state (``q``/``Q``/``cm``) gives the matrix each
figure is drawn with; reading the figure's own stream inside that matrix gives the size
of every piece of its text as printed, sub- and superscripts included (each is a text
run of its own size).  No renderer is needed: pypdf parses the streams.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import pypdf
from pypdf.generic import ContentStream

IDENTITY = (1.0, 0.0, 0.0, 1.0, 0.0, 0.0)
MM_PER_PT = 25.4 / 72.0


def _times(m, n):
    """The matrix product m x n of two PDF matrices (a, b, c, d, e, f)."""
    a, b, c, d, e, f = m
    A, B, C, D, E, F = n
    return (
        a * A + b * C,
        a * B + b * D,
        c * A + d * C,
        c * B + d * D,
        e * A + f * C + E,
        e * B + f * D + F,
    )


def _scale(m):
    """The linear scale of a matrix (the square root of its determinant's size)."""
    return math.sqrt(abs(m[0] * m[3] - m[1] * m[2]))


def _numbers(operands):
    return tuple(float(x) for x in operands)


@dataclass
class PlacedFigure:
    """One figure on a page: the scale it is printed at and the sizes of its text (pt)."""

    page: int
    scale: float
    bottom_pt: float
    top_pt: float
    text_sizes_pt: list = field(default_factory=list)
    texts: list = field(default_factory=list)


def _walk(stream, resources, ctm, reader, visit_text, visit_form):
    """Interpret one content stream: text runs and form XObjects with their matrices."""
    content = ContentStream(stream, reader)
    xobjects = (resources or {}).get("/XObject") or {}
    stack, size, tm, line = [], 0.0, IDENTITY, IDENTITY
    leading = 0.0
    for operands, op in content.operations:
        if op == b"q":
            stack.append(ctm)
        elif op == b"Q":
            ctm = stack.pop()
        elif op == b"cm":
            ctm = _times(_numbers(operands), ctm)
        elif op == b"BT":
            tm = line = IDENTITY
        elif op == b"Tf":
            size = float(operands[1])
        elif op == b"TL":
            leading = float(operands[0])
        elif op == b"Tm":
            tm = line = _numbers(operands)
        elif op in (b"Td", b"TD"):
            tx, ty = _numbers(operands)
            if op == b"TD":
                leading = -ty
            tm = line = _times((1, 0, 0, 1, tx, ty), line)
        elif op == b"T*":
            tm = line = _times((1, 0, 0, 1, 0, -leading), line)
        elif op in (b"Tj", b"TJ", b"'", b'"'):
            matrix = _times(tm, ctm)
            visit_text(size * _scale(matrix), matrix[5], operands)
        elif op == b"Do":
            child = xobjects[operands[0]].get_object()
            if child.get("/Subtype") == "/Form":
                matrix = _times(_numbers(child.get("/Matrix", IDENTITY)), ctm)
                visit_form(child, matrix)


def _text_of(operands):
    parts = []
    for operand in operands:
        if isinstance(operand, list):
            parts.extend(str(x) for x in operand if isinstance(x, str))
        elif isinstance(operand, str):
            parts.append(operand)
    return "".join(parts)


def placed_figures(path):
    """Every figure drawn on the pages of a PDF, with its scale and its text sizes.

    Parameters
    ----------
    path : str or os.PathLike
        The article's PDF.

    Returns
    -------
    list of PlacedFigure
        In page order; ``scale`` is 1 where the figure is printed at its own size.
    """
    reader = pypdf.PdfReader(path)
    figures = []
    for number, page in enumerate(reader.pages, start=1):

        def on_form(form, matrix, number=number):
            x0, y0, x1, y1 = (float(v) for v in form["/BBox"])
            corners = [(x, y) for x in (x0, x1) for y in (y0, y1)]
            ys = [matrix[1] * x + matrix[3] * y + matrix[5] for x, y in corners]
            figure = PlacedFigure(number, _scale(matrix), min(ys), max(ys))

            def in_figure(size_pt, _y, operands):
                text = _text_of(operands)
                if text.strip() or not text:
                    figure.text_sizes_pt.append(size_pt)
                    figure.texts.append(text)

            def nested(child, child_matrix):
                _walk(child, child.get("/Resources"), child_matrix, reader, in_figure, nested)

            _walk(form, form.get("/Resources"), matrix, reader, in_figure, nested)
            figures.append(figure)

        _walk(
            page.get_contents(), page.get("/Resources"), IDENTITY, reader, lambda *a: None, on_form
        )
    return figures


def page_fill(path, margin_mm=22.0, blank_mm=6.0):
    """How full each page is: the share of its text block's height not left blank.

    A stretch of the text block (the page less ``margin_mm`` at top and bottom) with
    no text and no figure that is taller than ``blank_mm`` counts as empty; the gaps
    between lines, paragraphs and headings are smaller.

    Returns
    -------
    list of float
        One fraction per page, in page order.
    """
    reader = pypdf.PdfReader(path)
    fills = []
    for page in reader.pages:
        height = float(page.mediabox.height)
        spans = []

        def on_text(size_pt, y, operands, spans=spans):
            if _text_of(operands).strip() or size_pt > 0:
                spans.append((y - 0.3 * size_pt, y + 0.9 * size_pt))

        def on_form(form, matrix, spans=spans):
            x0, y0, x1, y1 = (float(v) for v in form["/BBox"])
            ys = [matrix[1] * x + matrix[3] * y + matrix[5] for x in (x0, x1) for y in (y0, y1)]
            spans.append((min(ys), max(ys)))

        _walk(page.get_contents(), page.get("/Resources"), IDENTITY, reader, on_text, on_form)
        low, high = margin_mm / MM_PER_PT, height - margin_mm / MM_PER_PT
        # y runs upward in PDF; walk down the text block and sum the tall blank stretches
        covered = sorted((max(a, low), min(b, high)) for a, b in spans if b > low and a < high)
        empty, reached = 0.0, low
        for a, b in covered:
            if a - reached > blank_mm / MM_PER_PT:
                empty += a - reached
            reached = max(reached, b)
        if high - reached > blank_mm / MM_PER_PT:
            empty += high - reached
        fills.append(1.0 - empty / (high - low))
    return fills


def headings(path):
    """Where each heading of a PDF's outline (Typst writes one per heading) starts.

    Returns
    -------
    dict
        Heading text (with its number, ``"8. Software"``) -> ``(page, top_pt)``: the page
        (from 1) and the height of the heading's top above the page's foot (points).
    """
    reader = pypdf.PdfReader(path)
    found = {}

    def walk(items):
        for item in items:
            if isinstance(item, list):
                walk(item)
            else:
                found[str(item.title)] = (
                    reader.get_destination_page_number(item) + 1,
                    float(item.get("/Top", 0.0)),
                )

    walk(reader.outline)
    return found


def placed_after(figure, heading):
    """Whether a figure (:class:`PlacedFigure`) prints after a heading's start ``(page,
    top_pt)``: on a later page, or on the same page below it."""
    page, top_pt = heading
    return figure.page > page or (figure.page == page and figure.top_pt <= top_pt)
