"""Small HTML pieces for the notebook reprs (``_repr_html_``): a table with units and an inline SVG curve.

Ground layer: plain strings in, a string out; no solver, no matplotlib, no designer import.  Every text is
escaped.  Used by :class:`~designer.problem.Problem`, :class:`~designer.studies.front._pareto.Front`,
:class:`~designer.studies.optimum._optimise.Solution` and :class:`~designer.studies.recommend._recommend.Recommendation`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from html import escape
from typing import Any

STYLE = (
    "border-collapse:collapse;font-size:12px;font-family:sans-serif;margin:2px 0",
    "text-align:left;padding:1px 8px 1px 0;font-weight:normal;color:#555;white-space:nowrap",
    "text-align:right;padding:1px 4px;font-variant-numeric:tabular-nums;white-space:nowrap",
    "text-align:left;padding:1px 0 1px 4px;color:#555;white-space:nowrap",
)
"""Inline styles (table, label cell, value cell, unit cell): the repr must render without a stylesheet."""


def html_table(title: str, rows: Iterable[tuple[Any, Any, Any]], caption: str = "", extra: str = "") -> str:
    """A compact HTML table: a bold title, rows of (label, value, unit), an optional caption and extra HTML.

    ``value`` is shown as given (format numbers before); ``extra`` (e.g. an SVG) is placed beside the table
    unescaped, so pass only strings built by this package.
    """
    table, th, td, unit = STYLE
    body = "".join(
        f'<tr><th style="{th}">{escape(str(label))}</th><td style="{td}">{escape(str(value))}</td>'
        f'<td style="{unit}">{escape(str(u))}</td></tr>'
        for label, value, u in rows
    )
    cap = (
        f'<div style="font-size:11px;color:#555;font-family:sans-serif;max-width:420px">{escape(caption)}</div>'
        if caption
        else ""
    )
    inner = (
        f'<div><div style="font-weight:bold;font-family:sans-serif;font-size:13px">{escape(title)}</div>'
        f'<table style="{table}">{body}</table>{cap}</div>'
    )
    if extra:
        return (
            f'<div style="display:flex;gap:16px;align-items:flex-start">'
            f'<div style="flex:none">{inner}</div><div style="flex:none">{extra}</div></div>'
        )
    return f"<div>{inner}</div>"


def _tick_labels(
    x0: float, x1: float, y0: float, y1: float, width: int, height: int, left: int, right: int, top: int, bottom: int
) -> list[str]:
    """The four end values of a small SVG plot's axes, at the corners of the plot box."""
    return [
        f'<text x="{left}" y="{height - bottom + 12}">{x0:.3g}</text>',
        f'<text x="{width - right}" y="{height - bottom + 12}" text-anchor="end">{x1:.3g}</text>',
        f'<text x="{left - 3}" y="{height - bottom}" text-anchor="end">{y0:.3g}</text>',
        f'<text x="{left - 3}" y="{top + 9}" text-anchor="end">{y1:.3g}</text>',
    ]


def _axis_labels(
    xlabel: str, ylabel: str, width: int, height: int, left: int, right: int, top: int, bottom: int, xlabel_gap: int
) -> list[str]:
    """The x label under the box, the y label turned along the left edge, and the closing tag."""
    return [
        f'<text x="{(left + width - right) / 2:.0f}" y="{height - xlabel_gap}" text-anchor="middle">'
        f"{escape(xlabel)}</text>",
        f'<text transform="translate(11,{(top + height - bottom) / 2:.0f}) rotate(-90)" '
        f'text-anchor="middle">{escape(ylabel)}</text>',
        "</svg>",
    ]


def svg_curve(x: Any, y: Any, xlabel: str, ylabel: str, marks: Any = (), width: int = 240, height: int = 170) -> str:
    """A small line plot as an SVG string: the points (x, y) joined in order, axis labels with units.

    ``marks``: (x, y, label) points drawn as dots (e.g. the knee).  Non-finite points are dropped.
    """
    pts = [(float(a), float(b)) for a, b in zip(x, y) if math.isfinite(a) and math.isfinite(b)]
    left, right, top, bottom = 42, 8, 8, 32
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
        f'viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="10">',
        f"<title>{escape(ylabel)} against {escape(xlabel)}</title>",
        f'<rect x="{left}" y="{top}" width="{width - left - right}" height="{height - top - bottom}" '
        f'fill="none" stroke="#999"/>',
    ]
    if pts:
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        x0, x1 = min(xs), max(xs)
        y0, y1 = min(ys), max(ys)
        x0, x1 = (x0 - 0.5, x1 + 0.5) if x1 == x0 else (x0, x1)
        y0, y1 = (y0 - 0.5, y1 + 0.5) if y1 == y0 else (y0, y1)

        def px(a):
            return left + 4 + (a - x0) / (x1 - x0) * (width - left - right - 8)

        def py(b):
            return height - bottom - 4 - (b - y0) / (y1 - y0) * (height - top - bottom - 8)

        line = " ".join(f"{px(a):.1f},{py(b):.1f}" for a, b in pts)
        out.append(f'<polyline points="{line}" fill="none" stroke="#1f77b4" stroke-width="1.5"/>')
        for a, b in pts:
            out.append(f'<circle cx="{px(a):.1f}" cy="{py(b):.1f}" r="1.6" fill="#1f77b4"/>')
        for a, b, label in marks:
            out.append(
                f'<circle cx="{px(a):.1f}" cy="{py(b):.1f}" r="3.5" fill="#d62728">'
                f"<title>{escape(label)}</title></circle>"
            )
        out += _tick_labels(x0, x1, y0, y1, width, height, left, right, top, bottom)
    out += _axis_labels(xlabel, ylabel, width, height, left, right, top, bottom, xlabel_gap=4)
    return "".join(out)


def svg_sparkline(
    x: Any,
    y: Any,
    xlabel: str,
    ylabel: str,
    band: float | None = None,
    width: int = 260,
    height: int = 120,
    max_points: int = 400,
) -> str:
    """A small line (no dots) as an SVG string, e.g. θ(t): a zero line, optional ±``band`` dashed lines.

    Long series are thinned to about ``max_points`` vertices (every k-th point, the last kept) so the repr
    stays small; non-finite points are dropped.
    """
    pts = [(float(a), float(b)) for a, b in zip(x, y) if math.isfinite(a) and math.isfinite(b)]
    step = max(1, math.ceil(len(pts) / max_points))
    pts = pts[::step] + (pts[-1:] if pts and (len(pts) - 1) % step else [])
    left, right, top, bottom = 38, 6, 6, 28
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
        f'viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="10">',
        f"<title>{escape(ylabel)} against {escape(xlabel)}</title>",
    ]
    if pts:
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        x0, x1 = min(xs), max(xs)
        reach = max([abs(v) for v in ys] + ([abs(band)] if band is not None and math.isfinite(band) else []))
        y0, y1 = (-reach, reach) if reach > 0 else (-1.0, 1.0)
        x1 = x1 if x1 > x0 else x0 + 1.0

        def px(a: float) -> float:
            return left + (a - x0) / (x1 - x0) * (width - left - right)

        def py(b: float) -> float:
            return height - bottom - (b - y0) / (y1 - y0) * (height - top - bottom)

        out.append(f'<line x1="{left}" y1="{py(0):.1f}" x2="{width - right}" y2="{py(0):.1f}" stroke="#999"/>')
        if band is not None and math.isfinite(band):
            for b in (band, -band):
                out.append(
                    f'<line x1="{left}" y1="{py(b):.1f}" x2="{width - right}" y2="{py(b):.1f}" '
                    f'stroke="#d62728" stroke-dasharray="4 3"/>'
                )
        line = " ".join(f"{px(a):.1f},{py(b):.1f}" for a, b in pts)
        out.append(f'<polyline points="{line}" fill="none" stroke="#1f77b4" stroke-width="1.2"/>')
        out += _tick_labels(x0, x1, y0, y1, width, height, left, right, top, bottom)
    out += _axis_labels(xlabel, ylabel, width, height, left, right, top, bottom, xlabel_gap=3)
    return "".join(out)


def require_pandas(what: str) -> Any:
    """The pandas module, or an ImportError naming ``what`` needs it and how to install it (optional extra)."""
    try:
        import pandas  # optional dependency: only the to_pandas methods need it
    except ImportError:
        raise ImportError(f"{what} needs pandas: pip install 'caster-designer[notebook]'") from None
    return pandas


def dataframe(what: str, records: list[dict[str, Any]], columns: list[str], units: dict[str, str], **attrs: Any) -> Any:
    """A pandas DataFrame of ``records`` in ``columns`` order; ``df.attrs["units"]`` = ``units`` plus ``attrs``.

    ``what`` names the caller in the message when pandas is missing (:func:`require_pandas`).
    """
    pd = require_pandas(what)
    df = pd.DataFrame.from_records(records, columns=columns)
    df.attrs.update(attrs)
    df.attrs["units"] = dict(units)
    return df


__all__ = ["dataframe", "html_table", "require_pandas", "svg_curve", "svg_sparkline"]
