"""A small SVG canvas with the part of matplotlib's Axes API the report's figures use.

The report draws its six figures here instead of matplotlib: a figure is a few hundred SVG elements written
as text, about a millisecond each, where a matplotlib figure costs about 0.4–0.85 s of CPU (its import, the
Agg renderer and the PNG encoder; benchmarks/results.md).  The page inlines the SVG (vector, searchable, a
point's numbers on hover through :meth:`Axes.hover`), report.md links the same files.

:class:`Figure` and :class:`Axes` accept the calls of matplotlib's object API that the figure functions make
(``plot``, ``scatter``, ``axhline``, ``axvspan``, ``text``, ``annotate``, ``legend``, ``secondary_xaxis``,
``bar``, ``contourf``/``contour``/``clabel``, ``colorbar`` …), with the same meaning of their arguments, so
:func:`designer.plots.fronts.plot_front` and :func:`~designer.plots.fronts.plot_variables` draw the report's
front on this canvas and a notebook's on matplotlib's.  Only linear axes; sizes as matplotlib's: figure
inches, font points, marker sizes in points (``ms``) or points² (``s``); :data:`DPI` pixels per inch.
Contours come from contourpy (matplotlib's own contouring library, a small compiled module).  The small
charts of the records' notebook reprs (:func:`svg_curve`, :func:`svg_sparkline`) are written here too.
"""

from __future__ import annotations

import math
from collections import namedtuple
from html import escape
from typing import Any

import numpy as np
from contourpy import FillType, LineType, contour_generator

DPI = 110.0
"""Pixels per figure inch (the PNGs the report had were 110 dpi)."""
PT = DPI / 72.0
"""Pixels per point."""
FONT = "DejaVu Sans, Verdana, Arial, Helvetica, sans-serif"
BASE_FONT = 10.0
"""Default font size [pt] (matplotlib's)."""

_NAMED = {"black": "#000000", "white": "#ffffff", "gold": "#ffd700", "red": "#ff0000", "blue": "#0000ff"}
_NAMED.update({"green": "#008000", "grey": "#808080", "gray": "#808080", "k": "#000000", "w": "#ffffff"})
_NAMED.update({"tab:blue": "#1f77b4", "tab:orange": "#ff7f0e", "tab:green": "#2ca02c", "tab:red": "#d62728"})
_NAMED.update({"tab:purple": "#9467bd", "tab:gray": "#7f7f7f"})
"""matplotlib's colour names the figures use, as SVG colours."""
_DASH = {"-": None, "solid": None, "--": (3.7, 1.6), "dashed": (3.7, 1.6), ":": (1, 1.65), "dotted": (1, 1.65)}
_DASH.update({"-.": (6.4, 1.6, 1, 1.6), "dashdot": (6.4, 1.6, 1, 1.6)})
"""Dash patterns in units of the line width (matplotlib's defaults)."""
_GREENS = ("#f7fcf5", "#e5f5e0", "#c7e9c0", "#a1d99b", "#74c476", "#41ab5d", "#238b45", "#006d2c", "#00441b")
"""The "Greens" sequential colour ramp, light to dark (ColorBrewer)."""
_CMAPS = {"Greens": _GREENS, "viridis": ("#440154", "#3b528b", "#21918c", "#5ec962", "#fde725")}

# Advance widths of DejaVu Sans [em] (the page's font): used to size legends and boxes, not to place glyphs.
_WIDTH = dict(zip("0123456789", [0.636] * 10))
_WIDTH.update(
    zip(
        "abcdefghijklmnopqrstuvwxyz",
        [0.613, 0.635, 0.55, 0.635, 0.615, 0.352, 0.635, 0.634, 0.278, 0.278, 0.579, 0.278, 0.974]
        + [0.634, 0.612, 0.635, 0.635, 0.411, 0.521, 0.392, 0.634, 0.592, 0.818, 0.592, 0.592, 0.525],
    )
)
_WIDTH.update(
    zip(
        "ABCDEFGHIJKLMNOPQRSTUVWXYZ",
        [0.684, 0.686, 0.698, 0.77, 0.632, 0.575, 0.775, 0.752, 0.295, 0.295, 0.656, 0.557, 0.863]
        + [0.748, 0.787, 0.603, 0.787, 0.695, 0.635, 0.611, 0.732, 0.684, 0.989, 0.685, 0.611, 0.685],
    )
)
_WIDTH.update({" ": 0.318, ".": 0.318, ",": 0.318, ":": 0.337, ";": 0.337, "(": 0.39, ")": 0.39, "[": 0.39})
_WIDTH.update({"]": 0.39, "-": 0.361, "_": 0.5, "=": 0.838, "/": 0.337, "+": 0.838, "%": 0.95, "·": 0.318})
_WIDTH.update({"'": 0.275, "×": 0.838, "²": 0.4, "³": 0.4, "⁻": 0.4, "≥": 0.838, "≤": 0.838, "–": 0.5})


def text_width(text: str, size: float) -> float:
    """Estimated width [px] of ``text`` at ``size`` [pt] in DejaVu Sans."""
    return sum(_WIDTH.get(ch, 0.62) for ch in text) * size * PT


def colour(value, default: str = "#000000") -> str:
    """An SVG colour from a matplotlib colour: hex, a name, ``"tab:…"``, a grey level string ``"0.65"``."""
    if value is None:
        return default
    text = str(value)
    if text.startswith("#") or text == "none" or text in _NAMED:
        return _NAMED.get(text, text)
    try:
        rgb = value[:3] if isinstance(value, (tuple, list)) else [float(text)] * 3
    except ValueError:
        return text
    return "#" + "".join(f"{int(round(255 * float(v))):02x}" for v in rgb)


def _f(x: float) -> str:
    """A coordinate [px] as short text."""
    return f"{x:.1f}".rstrip("0").rstrip(".") if abs(x) < 1e6 else "0"


def nice_ticks(lo: float, hi: float, bins: int = 7) -> list[float]:
    """Round tick values inside [lo, hi]: the smallest step of 1, 2, 2.5, 5 × 10^k that needs at most ``bins``
    intervals from a multiple of the step below ``lo`` to one above ``hi`` (as matplotlib's MaxNLocator)."""
    if not (math.isfinite(lo) and math.isfinite(hi)) or hi <= lo:
        return [lo] if math.isfinite(lo) else []
    bins = max(int(bins), 1)
    mag = 10 ** math.floor(math.log10((hi - lo) / bins))
    for m in (1, 2, 2.5, 5, 10, 20, 25, 50, 100):
        step = m * mag
        if math.ceil(hi / step - 1e-9) - math.floor(lo / step + 1e-9) <= bins:
            break
    first = math.ceil(lo / step - 1e-9) * step
    n = int(math.floor((hi - first) / step + 1e-9)) + 1
    return [round(first + i * step, 12) for i in range(max(n, 0))]


def _bins(length: float, vertical: bool = False) -> int:
    """Tick intervals for an axis ``length`` [px] long: one per three font sizes across, two up, at most 9
    (matplotlib's ``get_tick_space``)."""
    return max(1, min(9, int(length / ((2 if vertical else 3) * BASE_FONT * PT))))


def _tick_labels(ticks: list[float]) -> list[str]:
    """Labels with as many decimals as the step needs."""
    if len(ticks) < 2:
        return [f"{t:g}" for t in ticks]
    step = min(abs(b - a) for a, b in zip(ticks, ticks[1:]))
    decimals = 0
    while decimals < 6 and abs(round(step, decimals) - step) > 1e-9 * max(1.0, abs(step)):
        decimals += 1
    return [f"{0.0 if abs(t) < 1e-12 * step else t:.{decimals}f}" for t in ticks]


def _levels(lo: float, hi: float, n: int) -> np.ndarray:
    """Round contour levels covering [lo, hi] with at most about ``n`` steps (as matplotlib's MaxNLocator)."""
    raw = (hi - lo) / max(n, 1)
    mag = 10 ** math.floor(math.log10(raw)) if raw > 0 else 1.0
    step = next(m * mag for m in (1, 2, 2.5, 5, 10) if m * mag >= raw * 0.999)
    first = math.floor(lo / step) * step
    last = math.ceil(hi / step) * step
    return np.arange(first, last + step / 2, step)


def _ramp(name: str, t: float) -> str:
    """Colour at t in [0, 1] of the named ramp (linear in RGB between its anchors)."""
    anchors = _CMAPS[name]
    t = min(max(t, 0.0), 1.0) * (len(anchors) - 1)
    k = min(int(t), len(anchors) - 2)
    a, b = anchors[k], anchors[k + 1]
    mix = [int(a[i : i + 2], 16) * (1 - (t - k)) + int(b[i : i + 2], 16) * (t - k) for i in (1, 3, 5)]
    return "#" + "".join(f"{int(round(v)):02x}" for v in mix)


class _Axis:
    """A secondary axis (``secondary_xaxis``/``secondary_yaxis``): ticks of f(x) placed through f⁻¹."""

    def __init__(self, where: str, functions):
        self.where, (self.forward, self.inverse) = where, functions
        self.label = ""

    def set_xlabel(self, text: str) -> None:
        """The axis label (also ``set_ylabel``, ``set_label`` for a colour bar)."""
        self.label = text

    set_ylabel = set_label = set_xlabel


_Mappable = namedtuple("_Mappable", "levels colours alpha")
"""What ``contourf`` returns: its levels and colours, for ``colorbar``."""
_Lines = namedtuple("_Lines", "paths colour width")
"""What ``contour`` returns: (level, [polyline arrays]) pairs, for ``clabel``."""


class _Handle:
    """A legend handle: how the entry's key is drawn."""

    def __init__(self, label: str, kind: str, **style):
        self.label, self.kind, self.style = label, kind, style

    def get_label(self) -> str:
        """The legend text."""
        return self.label


class Axes:
    """One plotting area; see the module docstring for the calls it takes."""

    transAxes = "axes"  # matplotlib's ax.transAxes: coordinates as fractions of the axes

    def __init__(self, figure: "Figure", box: tuple[float, float, float, float]):
        self.figure = figure
        self.box = list(box)  # x, y, width, height [px], y downwards
        self.items: list[tuple[float, int, str, tuple]] = []  # (zorder, order, kind, args)
        self.handles: list[_Handle] = []
        self.xlabel = self.ylabel = self.title = ""
        self.title_size = BASE_FONT * 1.2
        self.xlim: list = [None, None]
        self.ylim: list = [None, None]
        self.data_x: list[float] = []
        self.data_y: list[float] = []
        self.show_grid = False
        self.secondary: list[_Axis] = []
        self.xticks: tuple | None = None
        self.legend_args: dict | None = None
        self.sharex: Axes | None = None
        self.hide_xticklabels = False

    # -- state -------------------------------------------------------------------------------------
    def _add(self, kind: str, zorder: float, *args) -> None:
        self.items.append((zorder, len(self.items), kind, args))

    def _extent(self, xs=(), ys=()) -> None:
        self.data_x.extend(float(v) for v in np.ravel(xs) if np.isfinite(v))
        self.data_y.extend(float(v) for v in np.ravel(ys) if np.isfinite(v))

    def set_xlabel(self, text: str) -> None:
        """The x axis label (with its unit)."""
        self.xlabel = text

    def set_ylabel(self, text: str) -> None:
        """The y axis label (with its unit)."""
        self.ylabel = text

    def set_title(self, text: str, fontsize: float = BASE_FONT * 1.2) -> None:
        """The title above the axes (and above an axis on top); ``fontsize`` [pt]."""
        self.title, self.title_size = text, fontsize

    def grid(self, visible: bool = True, alpha: float = 0.3, **_) -> None:
        """Light grid lines at the ticks."""
        self.show_grid = bool(visible)

    def set_xlim(self, left=None, right=None) -> None:
        """x limits [data units] (shared by the axes of ``subplots(sharex=True)``); None keeps the automatic one."""
        _set_limits(self.sharex.xlim if self.sharex is not None else self.xlim, left, right)

    def set_ylim(self, bottom=None, top=None) -> None:
        """y limits [data units]; None keeps the automatic one (data range ± 5 %)."""
        _set_limits(self.ylim, bottom, top)

    def set_xticks(self, ticks, labels=None, fontsize: float = BASE_FONT * 0.9) -> None:
        """Ticks at ``ticks`` [data units] with ``labels`` (multi-line text allowed), ``fontsize`` [pt]."""
        self.xticks = (list(map(float, ticks)), list(labels) if labels is not None else None, fontsize)

    def secondary_xaxis(self, where: str, functions, _sides=("top", "bottom")) -> _Axis:
        """A second x axis (``"top"``) in other units: ``functions`` = (forward, inverse) from these units; also
        ``secondary_yaxis`` (``"right"``)."""
        axis = _Axis(where if where == _sides[0] else _sides[1], functions)
        self.secondary.append(axis)
        return axis

    def secondary_yaxis(self, where: str, functions) -> _Axis:
        """A second y axis (``"right"``) in other units (:meth:`secondary_xaxis`)."""
        return self.secondary_xaxis(where, functions, ("right", "left"))

    # -- artists -----------------------------------------------------------------------------------
    def _handle(self, label: str | None, kind: str, **style) -> _Handle:
        """The artist's legend handle, listed in the legend when labelled (not "_…", as matplotlib)."""
        handle = _Handle(label or "", kind, **style)
        if label and not label.startswith("_"):
            self.handles.append(handle)
        return handle

    def plot(
        self,
        x,
        y,
        fmt: str | None = None,
        *,
        color=None,
        lw: float = 1.5,
        ls: str = "-",
        marker=None,
        ms: float = 6.0,
        label: str | None = None,
        zorder: float = 2,
        drawstyle: str = "default",
        **_,
    ):
        """A polyline (with markers); ``fmt`` as matplotlib's short strings ("o", "--", ":")."""
        if fmt:
            marker = fmt if fmt in ("o", ".", "s", "^", "D", "x") else marker
            ls = fmt if fmt in _DASH else ("none" if marker == fmt else ls)
        x = np.asarray(x, float).reshape(-1)
        y = np.asarray(y, float).reshape(-1) if np.ndim(y) else np.full(len(x), float(y))
        col = colour(color, "#1f77b4")
        if len(x):
            self._extent(x, y)
            self._add("line", zorder, x, y, col, lw, ls, marker or None, ms, drawstyle)
        return [self._handle(label, "line", color=col, lw=lw, ls=ls, marker=marker or None, ms=ms)]

    def scatter(
        self,
        x,
        y,
        s=36.0,
        c=None,
        *,
        color=None,
        marker: str = "o",
        facecolor=None,
        edgecolor=None,
        lw: float = 1.0,
        label: str | None = None,
        zorder: float = 1,
        clip_on: bool = True,
        **_,
    ):
        """Markers of area ``s`` [pt²]; ``c``/``color`` one colour or one per point."""
        x = np.asarray(x, float).reshape(-1)
        y = np.asarray(y, float).reshape(-1)
        fill = facecolor if facecolor is not None else (c if c is not None else color)
        many = isinstance(fill, (list, np.ndarray))  # one colour per point
        fills = [colour(v) for v in fill] if many else [colour(fill, "#1f77b4")] * len(x)
        edge = colour(edgecolor) if edgecolor is not None else None
        size = math.sqrt(float(s))
        if len(x):
            self._extent(x, y)
            self._add("markers", zorder, x, y, fills, edge, lw, marker, size, clip_on)
        key_fill = fills[0] if fills else "#888" if many else colour(fill, "#1f77b4")
        return self._handle(label, "marker", fill=key_fill, edge=edge, lw=lw, marker=marker, ms=size)

    def axhline(self, y: float, color=None, ls: str = "-", lw: float = 1.5, label=None, zorder=2, _kind="h", **_):
        """A horizontal line across the axes at ``y`` [data units]; ``lw`` [pt] (``axvline``: vertical at x)."""
        col = colour(color, "#1f77b4")
        if np.isfinite(y):
            self._extent(**{"ys" if _kind == "h" else "xs": [y]})
            self._add("hline", zorder, _kind, float(y), col, lw, ls)
        return self._handle(label, "line", color=col, lw=lw, ls=ls, marker=None, ms=0)

    def axvline(self, x: float, color=None, ls: str = "-", lw: float = 1.5, label=None, zorder=2, **_):
        """A vertical line across the axes at ``x`` [data units] (:meth:`axhline`)."""
        return self.axhline(x, color, ls, lw, label, zorder, "v")

    def axvspan(self, x0: float, x1: float, color=None, alpha: float = 1.0, label: str | None = None, **_):
        """A shaded band from ``x0`` to ``x1`` [data units] across the axes' height."""
        col = colour(color, "#1f77b4")
        self._extent([x0, x1], ())
        self._add("vspan", 1, float(x0), float(x1), col, alpha)
        return self._handle(label, "patch", fill=col, alpha=alpha)

    def rectangle(self, x: float, y: float, width: float, height: float, *, edgecolor=None, ls="-", lw=1.0) -> None:
        """An unfilled rectangle in data coordinates (matplotlib: ``add_patch(Rectangle(..., fill=False))``)."""
        self._add("rect", 1, x, y, width, height, colour(edgecolor), ls, lw)

    def bar(self, x, height, width: float = 0.8, color=None, label: str | None = None, **_):
        """Bars centred at ``x`` of ``height`` and ``width`` [data units], from 0."""
        x = np.asarray(x, float).reshape(-1)
        h = np.asarray(height, float).reshape(-1)
        col = colour(color, "#1f77b4")
        if len(x):
            self._extent(np.concatenate([x - width / 2, x + width / 2]), np.concatenate([h, [0.0]]))
            self._add("bars", 1, x, h, width, col)
        return self._handle(label, "patch", fill=col, alpha=1.0)

    def legend_patch(self, label: str, color) -> _Handle:
        """A legend entry with a filled square key and no artist (matplotlib: an empty Rectangle patch)."""
        return self._handle(label, "patch", fill=colour(color), alpha=1.0)

    def text(
        self,
        x: float,
        y: float,
        s: str,
        transform=None,
        ha: str = "left",
        va: str = "baseline",
        fontsize: float = BASE_FONT,
        color=None,
        weight: str = "normal",
        rotation: float = 0.0,
        bbox=None,
        wrap: bool = False,
        **_,
    ):
        """Text at data coordinates, or axes fractions with ``transform=ax.transAxes``."""
        where = "axes" if transform == "axes" else "data"
        args = (where, float(x), float(y), str(s), ha, va, fontsize, colour(color), weight, rotation, bbox is not None)
        self._add("text", 3, *args, wrap)

    def annotate(
        self,
        text: str,
        xy,
        xytext=None,
        textcoords: str = "data",
        arrowprops=None,
        fontsize: float = BASE_FONT,
        color=None,
        ha: str = "left",
        va: str = "baseline",
        weight: str = "normal",
        **_,
    ):
        """Text at ``xytext`` (data, "offset points" from ``xy`` or "axes fraction"), with an optional line
        or arrow to ``xy`` (``arrowprops``: ``arrowstyle`` "-", "->" or "<->", ``color``, ``lw``)."""
        args = (str(text), tuple(map(float, xy)), xytext, textcoords, arrowprops, fontsize, colour(color), ha, va)
        self._add("annotate", 3, *args, weight)

    def hover(self, x, y, texts) -> None:
        """Invisible hover targets: each point's ``texts`` entry shows as its tooltip (an SVG ``<title>``)."""
        x = np.asarray(x, float).reshape(-1)
        y = np.asarray(y, float).reshape(-1)
        self._add("hover", 10, x, y, [str(t) for t in texts])

    def contourf(self, X, Y, Z, levels: int = 10, cmap: str = "Greens", alpha: float = 1.0, **_) -> _Mappable:
        """Filled bands between round levels of Z on the grid (X, Y) (contourpy)."""
        X, Y, Z = (np.asarray(a, float) for a in (X, Y, Z))
        lv = _levels(float(np.nanmin(Z)), float(np.nanmax(Z)), levels)
        gen = contour_generator(X, Y, Z, fill_type=FillType.OuterCode)
        cols = [_ramp(cmap, (k + 0.5) / (len(lv) - 1)) for k in range(len(lv) - 1)]
        bands = [(gen.filled(lo, hi), col) for lo, hi, col in zip(lv[:-1], lv[1:], cols)]
        self._extent([X.min(), X.max()], [Y.min(), Y.max()])
        self._add("bands", 0.9, bands, alpha)
        return _Mappable(lv, cols, alpha)

    def contour(self, X, Y, Z, levels=8, colors=None, linewidths: float = 1.0, **_) -> _Lines:
        """Lines of Z on the grid (X, Y) at ``levels`` (a count of round levels, or the values)."""
        X, Y, Z = (np.asarray(a, float) for a in (X, Y, Z))
        zlo, zhi = float(np.nanmin(Z)), float(np.nanmax(Z))
        lv = [v for v in _levels(zlo, zhi, levels) if zlo < v < zhi] if isinstance(levels, int) else list(levels)
        gen = contour_generator(X, Y, Z, line_type=LineType.Separate)
        paths = [(float(v), gen.lines(v)) for v in lv]
        lines = _Lines(paths, colour(colors), linewidths)
        self._add("contour", 2, lines)
        return lines

    def clabel(self, lines: _Lines, fmt: str = "%.1f", fontsize: float = BASE_FONT) -> None:
        """A label per contour level, on its longest piece, turned along the line."""
        self._add("clabel", 3, lines, fmt, fontsize)

    def legend(
        self,
        handles=None,
        loc: str = "upper right",
        fontsize: float = BASE_FONT,
        framealpha: float = 0.8,
        title: str | None = None,
        title_fontsize: float | None = None,
        bbox_to_anchor=None,
        ncol: int = 1,
        **_,
    ):
        """The legend of the labelled artists (or ``handles``) at ``loc`` ("upper right", "upper left", ...) or
        with its ``loc`` corner at ``bbox_to_anchor`` (axes fractions); ``fontsize`` [pt]."""
        self.legend_args = dict(handles=handles, loc=loc, fontsize=fontsize, framealpha=framealpha, ncol=ncol)
        self.legend_args |= dict(title=title, title_fontsize=title_fontsize or fontsize, anchor=bbox_to_anchor)

    # -- drawing -----------------------------------------------------------------------------------
    def _resolved_xlim(self) -> tuple[float, float]:
        owner = self.sharex or self
        lim = owner.xlim
        data = owner.data_x + [v for ax in owner.figure.axes if ax.sharex is owner for v in ax.data_x]
        return self._auto(lim, data)

    def _resolved_ylim(self) -> tuple[float, float]:
        return self._auto(self.ylim, self.data_y)

    @staticmethod
    def _auto(lim, data) -> tuple[float, float]:
        lo, hi = (min(data), max(data)) if data else (0.0, 1.0)
        if hi == lo:
            lo, hi = lo - (abs(lo) * 0.05 or 0.05), hi + (abs(hi) * 0.05 or 0.05)
        pad = 0.05 * (hi - lo)
        return (lim[0] if lim[0] is not None else lo - pad, lim[1] if lim[1] is not None else hi + pad)

    def _scales(self):
        x0, y0, w, h = self.box
        xl, xh = self._resolved_xlim()
        yl, yh = self._resolved_ylim()

        def sx(v):  # data -> px
            t = (np.asarray(v, float) - xl) / (xh - xl)
            return x0 + w * t

        def sy(v):
            return y0 + h * (1 - (np.asarray(v, float) - yl) / (yh - yl))

        return sx, sy, (xl, xh), (yl, yh)

    def render(self, out: list, uid: str) -> None:  # noqa: C901 - one branch per kind of artist
        """Append this axes' SVG elements to ``out``; ``uid`` makes its ids unique in the page."""
        x0, y0, w, h = self.box
        sx, sy, (xl, xh), (yl, yh) = self._scales()
        clip = f"{uid}-clip"
        out.append(f'<clipPath id="{clip}">{_rect(x0, y0, w, h)}</clipPath>')
        out.append(_rect(x0, y0, w, h, ' fill="#ffffff"'))
        xt = self.xticks[0] if self.xticks else nice_ticks(min(xl, xh), max(xl, xh), _bins(w))
        yt = nice_ticks(min(yl, yh), max(yl, yh), _bins(h, True))
        if self.show_grid:
            grid = [f"M{_f(float(sx(t)))} {_f(y0)}V{_f(y0 + h)}" for t in xt]
            grid += [f"M{_f(x0)} {_f(float(sy(t)))}H{_f(x0 + w)}" for t in yt]
            out.append(
                f'<path d="{"".join(grid)}" stroke="#b0b0b0" stroke-opacity="0.45" stroke-width="0.8" fill="none"/>'
            )
        unclipped = [i for i in self.items if i[2] == "markers" and not i[3][-1]]
        free = {i[1] for i in unclipped}
        out.append(f'<g clip-path="url(#{clip})">')
        for _z, _i, kind, args in sorted(
            i for i in self.items if i[2] not in ("text", "annotate", "hover", "clabel") and i[1] not in free
        ):
            getattr(self, f"_draw_{kind}")(out, sx, sy, *args)
        out.append("</g>")
        out.append(_rect(x0, y0, w, h, ' fill="none" stroke="#000" stroke-width="0.9"'))
        self._draw_ticks(out, sx, sy, xt, yt)
        for _z, _i, kind, args in sorted(unclipped + [i for i in self.items if i[2] in ("text", "annotate", "clabel")]):
            getattr(self, f"_draw_{kind}")(out, sx, sy, *args)
        if self.legend_args is not None:
            handles = self.legend_args["handles"]
            args = self.legend_args | {"handles": self.handles if handles is None else handles}
            draw_legend(out, box=tuple(self.box), **args)
        for _z, _i, _kind, args in (i for i in self.items if i[2] == "hover"):
            self._draw_hover(out, sx, sy, *args)

    def _draw_ticks(self, out, sx, sy, xt, yt) -> None:
        x0, y0, w, h = self.box
        size = BASE_FONT * PT
        labels = self.xticks[1] if self.xticks and self.xticks[1] is not None else _tick_labels(xt)
        fs = self.xticks[2] if self.xticks else BASE_FONT
        marks = ""
        for t, lab in zip(xt, labels):
            px = float(sx(t))
            marks += f"M{_f(px)} {_f(y0 + h)}v{_f(3.5 * PT)}"
            if not self.hide_xticklabels:
                out.append(_text(px, y0 + h + 3.5 * PT + fs * PT * 1.05, lab, fs, "middle"))
        ymarks, width = _vticks(out, x0, -1, [float(sy(t)) for t in yt], _tick_labels(yt))
        out.append(_marks(marks + ymarks))
        tick_h = 0.0
        if labels and not self.hide_xticklabels:
            tick_h = fs * PT * 1.2 * (max(str(x).count("\n") for x in labels) + 1)
        if self.xlabel:
            out.append(_text(x0 + w / 2, y0 + h + 3.5 * PT + tick_h + size * 1.15, self.xlabel, BASE_FONT, "middle"))
        if self.ylabel:
            px = x0 - 5.5 * PT - width - 0.7 * size  # turned text: glyphs from 0.8 size left to 0.25 right
            out.append(_text(px, y0 + h / 2, self.ylabel, BASE_FONT, "middle", rotate=-90))
        top = y0
        for axis in self.secondary:
            top = self._draw_secondary(out, sx, sy, axis, top)
        if self.title:
            out.append(_text(x0 + w / 2, top - 0.45 * self.title_size * PT, self.title, self.title_size, "middle"))

    def _draw_secondary(self, out, sx, sy, axis: _Axis, top: float) -> float:
        """Ticks and label of a secondary axis; returns the y [px] above which the title goes."""
        x0, y0, w, h = self.box
        size = BASE_FONT * PT
        vertical = axis.where in ("left", "right")
        lo, hi = self._resolved_ylim() if vertical else self._resolved_xlim()
        a, b = sorted((float(axis.forward(lo)), float(axis.forward(hi))))
        ticks = nice_ticks(a, b, _bins(h if vertical else w, vertical))
        labels = _tick_labels(ticks)
        if vertical:
            side, sign = (x0 + w, 1) if axis.where == "right" else (x0, -1)
            marks, width = _vticks(out, side, sign, [float(sy(float(axis.inverse(t)))) for t in ticks], labels)
            if axis.label:
                px = side + sign * (5.5 * PT + width) + (1.15 if sign > 0 else -0.7) * size
                out.append(_text(px, y0 + h / 2, axis.label, BASE_FONT, "middle", rotate=-90))
            if axis.where == "right":
                out.append(f'<path d="M{_f(side)} {_f(y0)}v{_f(h)}" stroke="#000" stroke-width="0.9"/>')
        else:
            marks = ""
            for t, lab in zip(ticks, labels):
                px = float(sx(float(axis.inverse(t))))
                marks += f"M{_f(px)} {_f(y0)}v{_f(-3.5 * PT)}"
                out.append(_text(px, y0 - 5.5 * PT, lab, BASE_FONT, "middle"))
            top = y0 - 5.5 * PT - size * 1.1
            if axis.label:
                out.append(_text(x0 + w / 2, top, axis.label, BASE_FONT, "middle"))
                top -= size * 1.2
        out.append(_marks(marks))
        return top

    def _draw_line(self, out, sx, sy, x, y, col, lw, ls, marker, ms, drawstyle) -> None:
        px, py = sx(x), sy(y)
        if ls not in ("none", "None", "", " ") and len(x) > 1:
            pts = list(zip(px, py))
            if drawstyle == "steps-post":  # across at each point's y to the next x, then up or down
                pts = pts[:1] + [p for k in range(1, len(px)) for p in ((px[k], py[k - 1]), (px[k], py[k]))]
            d = "M" + "L".join(f"{_f(a)} {_f(b)}" for a, b in pts if np.isfinite(a) and np.isfinite(b))
            out.append(f'<path d="{d}" fill="none"{_stroke(col, lw, ls)} stroke-linejoin="round"/>')
        if marker:
            size = ms if marker != "." else ms * 0.5
            for a, b in zip(px, py):
                out.append(_marker(marker, float(a), float(b), size * PT, col, col, 0.5 * PT))

    def _draw_markers(self, out, sx, sy, x, y, fills, edge, lw, marker, size, clip_on) -> None:
        for a, b, fill in zip(sx(x), sy(y), fills):
            out.append(_marker(marker, float(a), float(b), size * PT, fill, edge or fill, lw * PT))

    def _draw_hline(self, out, sx, sy, kind, v, col, lw, ls) -> None:
        """A line across the axes: horizontal at y = ``v`` (``kind`` "h") or vertical at x = ``v`` ("v")."""
        x0, y0, w, h = self.box
        d = (
            f"M{_f(x0)} {_f(float(sy(v)))}H{_f(x0 + w)}"
            if kind == "h"
            else f"M{_f(float(sx(v)))} {_f(y0)}V{_f(y0 + h)}"
        )
        out.append(f'<path d="{d}"{_stroke(col, lw, ls)}/>')

    def _draw_vspan(self, out, sx, sy, a, b, col, alpha) -> None:
        _, y0, _, h = self.box
        pa, pb = sorted((float(sx(a)), float(sx(b))))
        out.append(_rect(pa, y0, pb - pa, h, f' fill="{col}" fill-opacity="{alpha:g}"'))

    def _draw_rect(self, out, sx, sy, x, y, width, height, edge, ls, lw) -> None:
        xa, xb = sorted((float(sx(x)), float(sx(x + width))))
        ya, yb = sorted((float(sy(y)), float(sy(y + height))))
        out.append(_rect(xa, ya, xb - xa, yb - ya, f' fill="none"{_stroke(edge, lw, ls)}'))

    def _draw_bars(self, out, sx, sy, x, h, width, col) -> None:
        for a, v in zip(x, h):
            xa, xb = sorted((float(sx(a - width / 2)), float(sx(a + width / 2))))
            ya, yb = sorted((float(sy(0.0)), float(sy(v))))
            out.append(_rect(xa, ya, xb - xa, yb - ya, f' fill="{col}"'))

    def _draw_bands(self, out, sx, sy, bands, alpha) -> None:
        for (points, codes), col in bands:
            d = []
            for pts, cds in zip(points, codes):
                px, py = sx(pts[:, 0]), sy(pts[:, 1])
                for a, b, code in zip(px, py, cds):
                    d.append("Z" if code == 79 else ("M" if code == 1 else "L") + f"{_f(a)} {_f(b)}")
            if d:
                paint = f'fill="{col}" fill-opacity="{alpha:g}" stroke="{col}" stroke-opacity="{alpha:g}"'
                out.append(f'<path d="{"".join(d)}" {paint} stroke-width="0.3" fill-rule="evenodd"/>')

    def _draw_contour(self, out, sx, sy, lines: _Lines) -> None:
        for _level, pieces in lines.paths:
            for piece in pieces:
                d = "M" + "L".join(f"{_f(a)} {_f(b)}" for a, b in zip(sx(piece[:, 0]), sy(piece[:, 1])))
                out.append(f'<path d="{d}" fill="none" stroke="{lines.colour}" stroke-width="{_f(lines.width * PT)}"/>')

    def _draw_clabel(self, out, sx, sy, lines: _Lines, fmt: str, fontsize: float) -> None:
        x0, y0, w, h = self.box
        for level, pieces in lines.paths:
            if not pieces:
                continue
            piece = max(pieces, key=len)
            px, py = sx(piece[:, 0]), sy(piece[:, 1])
            inside = np.nonzero((px > x0 + 25) & (px < x0 + w - 25) & (py > y0 + 12) & (py < y0 + h - 12))[0]
            if len(inside) < 2:
                continue
            k = int(inside[len(inside) // 2])
            k0, k1 = max(k - 2, 0), min(k + 2, len(px) - 1)
            angle = math.degrees(math.atan2(py[k1] - py[k0], px[k1] - px[k0]))
            if angle > 90:
                angle -= 180
            elif angle < -90:
                angle += 180
            label = fmt % level
            out.append(
                f'<text x="{_f(px[k])}" y="{_f(py[k] + 0.35 * fontsize * PT)}" font-size="{_f(fontsize * PT)}" '
                f'text-anchor="middle" fill="{lines.colour}" stroke="#ffffff" stroke-opacity="0.6" stroke-width="5" stroke-linejoin="round" '
                f'paint-order="stroke" transform="rotate({angle:.1f} {_f(px[k])} {_f(py[k])})">{escape(label)}</text>'
            )

    def _point(self, sx, sy, where: str, x: float, y: float) -> tuple[float, float]:
        x0, y0, w, h = self.box
        if where == "axes":
            return x0 + x * w, y0 + (1 - y) * h
        return float(sx(x)), float(sy(y))

    def _draw_text(self, out, sx, sy, where, x, y, s, ha, va, fontsize, col, weight, rotation, boxed, wrap) -> None:
        px, py = self._point(sx, sy, where, x, y)
        lines = s.split("\n")
        if wrap:
            lines = [piece for line in lines for piece in _wrap(line, fontsize, self.box[2] * 0.9)]
        size = fontsize * PT
        n = len(lines)
        if rotation and n == 1:  # turned text (bar values): along the turned direction, centred across it
            anchor = {"bottom": "start", "top": "end"}.get(va, "middle")
            turn = f' transform="rotate({-rotation:g} {_f(px)} {_f(py)})"'
            out.append(
                f'<text x="{_f(px)}" y="{_f(py + 0.35 * size)}" font-size="{_f(size)}" text-anchor="{anchor}"{turn}>'
                f"{escape(lines[0])}</text>"
            )
            return
        first = _first_baseline(py, n, size, va)
        anchor = {"left": "start", "center": "middle", "right": "end"}[ha]
        if boxed:
            width = max(text_width(line, fontsize) for line in lines) + 0.6 * size
            left = {"start": px - 0.3 * size, "middle": px - width / 2, "end": px - width + 0.3 * size}[anchor]
            box = left, first - 0.95 * size, width, n * 1.2 * size + 0.3 * size
            out.append(_rect(*box, ' fill="#ffffff" fill-opacity="0.8"'))
        out.append(_text(px, first, "\n".join(lines), fontsize, anchor, col, weight))

    def _draw_annotate(
        self, out, sx, sy, text, xy, xytext, textcoords, arrowprops, fontsize, col, ha, va, weight
    ) -> None:
        ax_, ay_ = float(sx(xy[0])), float(sy(xy[1]))
        if xytext is None:
            tx, ty = ax_, ay_
        elif textcoords == "offset points":
            tx, ty = ax_ + xytext[0] * PT, ay_ - xytext[1] * PT
        elif textcoords == "axes fraction":
            tx, ty = self._point(sx, sy, "axes", *xytext)
        else:
            tx, ty = float(sx(xytext[0])), float(sy(xytext[1]))
        if arrowprops:
            acol = colour(arrowprops.get("color"), "#000000")
            lw = float(arrowprops.get("lw", 1.0)) * PT
            style = arrowprops.get("arrowstyle", "-")
            bx, by = tx, ty
            if text:  # from the edge of the text's box nearest the point, as matplotlib
                left, top, right, bottom = _text_box(tx, ty, text.split("\n"), fontsize, ha, va)
                bx, by = min(max(ax_, left - 2), right + 2), min(max(ay_, top - 2), bottom + 2)
            out.append(
                f'<path d="M{_f(bx)} {_f(by)}L{_f(ax_)} {_f(ay_)}" stroke="{acol}" stroke-width="{_f(lw)}" fill="none"/>'
            )
            if style in ("->", "<->"):
                out.append(_arrowhead(bx, by, ax_, ay_, acol, lw))
            if style == "<->":
                out.append(_arrowhead(ax_, ay_, bx, by, acol, lw))
        if text:
            self._draw_text(
                out, lambda v: v, lambda v: v, "px", tx, ty, text, ha, va, fontsize, col, weight, 0, False, False
            )

    def _draw_hover(self, out, sx, sy, x, y, texts) -> None:
        out.append('<g class="hover">')
        for a, b, t in zip(sx(x), sy(y), texts):
            if np.isfinite(a) and np.isfinite(b):
                out.append(  # invisible by its own attributes in a file opened alone; a page's CSS overrides them
                    f'<circle cx="{_f(a)}" cy="{_f(b)}" r="{_f(4 * PT)}" fill="#ffffff" fill-opacity="0">'
                    f"<title>{escape(t)}</title></circle>"
                )
        out.append("</g>")


def draw_legend(out, handles, box, loc, fontsize, framealpha=0.8, title=None, title_fontsize=None, anchor=None, ncol=1):
    """A legend box of the labelled ``handles`` placed at ``loc`` of ``box`` (x, y, w, h [px])."""
    entries = [hd for hd in handles if hd.get_label()]
    if not entries:
        return
    size = fontsize * PT
    row = 1.35 * size
    key = 2.0 * size
    pad = 0.5 * size
    lines_of = [hd.label.split("\n") for hd in entries]
    widths = [max(text_width(line, fontsize) for line in lines) for lines in lines_of]
    heights = [row * len(lines) for lines in lines_of]
    ncol = max(1, int(ncol))
    if ncol > 1:
        cell = [key + 0.6 * size + wd + 1.2 * size for wd in widths]
        width = sum(cell) + 2 * pad
        height = row + 2 * pad
    else:
        width = key + 0.6 * size + max(widths) + 2 * pad
        height = sum(heights) + 2 * pad
    title_h = 0.0
    if title:
        title_h = 1.4 * (title_fontsize or fontsize) * PT
        width = max(width, text_width(title, title_fontsize or fontsize) + 2 * pad)
        height += title_h
    x0, y0, w, h = box
    gap = 0.6 * size
    if anchor is not None:
        ax_, ay_ = x0 + anchor[0] * w, y0 + (1 - anchor[1]) * h
    else:
        ax_ = {"right": x0 + w - gap, "left": x0 + gap, "center": x0 + w / 2}[loc.split()[-1]]
        ay_ = {"upper": y0 + gap, "lower": y0 + h - gap, "center": y0 + h / 2}[loc.split()[0]]
    left = {"right": ax_ - width, "left": ax_, "center": ax_ - width / 2}[loc.split()[-1]]
    top = {"upper": ay_, "lower": ay_ - height, "center": ay_ - height / 2}[loc.split()[0]]
    frame = f' rx="3" fill="#ffffff" fill-opacity="{framealpha:g}" stroke="#cccccc" stroke-width="0.8"'
    out.append('<g class="legend">' + _rect(left, top, width, height, frame))
    if title:
        out.append(_text(left + width / 2, top + pad + 0.8 * title_h, title, title_fontsize or fontsize, "middle"))
    x, y = left + pad, top + pad + title_h
    for hd, lines, wd, ht in zip(entries, lines_of, widths, heights):
        cy = y + row / 2
        _legend_key(out, hd, x, cy, key, size)
        out.append(_text(x + key + 0.6 * size, cy + 0.35 * size, "\n".join(lines), fontsize, "start"))
        if ncol > 1:
            x += key + 0.6 * size + wd + 1.2 * size
        else:
            y += ht
    out.append("</g>")


def _legend_key(out, hd: _Handle, x: float, cy: float, key: float, size: float) -> None:
    st = hd.style
    if hd.kind == "line":
        if st.get("ls") not in ("none", "None", "", " "):
            out.append(f'<path d="M{_f(x)} {_f(cy)}h{_f(key)}"{_stroke(st["color"], st["lw"], st["ls"])}/>')
        if st.get("marker"):
            ms = st["ms"] if st["marker"] != "." else st["ms"] * 0.5
            out.append(_marker(st["marker"], x + key / 2, cy, ms * PT, st["color"], st["color"], 0.5 * PT))
    elif hd.kind == "marker":
        ms = min(st["ms"], 14.0)
        out.append(
            _marker(st["marker"], x + key / 2, cy, ms * PT, st["fill"], st.get("edge") or st["fill"], st["lw"] * PT)
        )
    else:
        fill = f' fill="{st["fill"]}" fill-opacity="{max(st.get("alpha", 1.0), 0.25):g}"'
        out.append(_rect(x, cy - 0.35 * size, key, 0.7 * size, fill))


def _set_limits(lim: list, low, high) -> None:
    """Set ``lim`` ([low, high]) to ``low``, ``high`` [data units] (or the pair ``low``); None keeps a limit."""
    low, high = low if isinstance(low, (tuple, list)) else (low, high)
    lim[:] = [float(v) if v is not None else old for v, old in zip((low, high), lim)]


def _vticks(out, x: float, sign: int, ys, labels) -> tuple[str, float]:
    """Tick labels along a vertical edge at ``x`` [px] (``sign`` 1: labels right of it, -1: left) at ``ys`` [px];
    returns the tick marks' path data and the widest label [px]."""
    for py, lab in zip(ys, labels):
        out.append(
            _text(x + sign * 5.5 * PT, py + 0.35 * (BASE_FONT * PT), lab, BASE_FONT, "start" if sign > 0 else "end")
        )
    marks = "".join(f"M{_f(x)} {_f(py)}h{_f(sign * 3.5 * PT)}" for py in ys)
    return marks, max((text_width(lab, BASE_FONT) for lab in labels), default=0)


def _marks(d: str) -> str:
    """Tick marks of path data ``d``."""
    return f'<path d="{d}" stroke="#000" stroke-width="0.8"/>'


def _rect(x: float, y: float, width: float, height: float, attrs: str = "") -> str:
    """A ``<rect>`` at (x, y) of ``width`` × ``height`` [px]; ``attrs``: its further attributes."""
    return f'<rect x="{_f(x)}" y="{_f(y)}" width="{_f(width)}" height="{_f(height)}"{attrs}/>'


def _stroke(col: str, lw: float, ls: str) -> str:
    """The stroke attributes of a line of colour ``col``, width ``lw`` [pt] and style ``ls`` (its dashes)."""
    pattern = _DASH.get(ls)
    scale = max(lw, 1.0) * PT
    dash = f' stroke-dasharray="{",".join(_f(p * scale) for p in pattern)}"' if pattern else ""
    return f' stroke="{col}" stroke-width="{_f(lw * PT)}"{dash}'


def _text(x, y, s, fontsize, anchor="start", col="#000000", weight="normal", rotate: float = 0.0) -> str:
    """A ``<text>`` element; each line of a multi-line ``s`` a ``<tspan>``, 1.2 font sizes apart."""
    lines = str(s).split("\n")
    extra = f' transform="rotate({rotate:g} {_f(x)} {_f(y)})"' if rotate else ""
    fill = "" if col in ("#000000", None) else f' fill="{col}"'
    bold = ' font-weight="bold"' if weight == "bold" else ""
    body = "".join(
        f'<tspan x="{_f(x)}" dy="{"0" if i == 0 else _f(1.2 * fontsize * PT)}">{escape(line)}</tspan>'
        for i, line in enumerate(lines)
    )
    body = escape(lines[0]) if len(lines) == 1 else body
    return f'<text x="{_f(x)}" y="{_f(y)}" font-size="{_f(fontsize * PT)}" text-anchor="{anchor}"{fill}{bold}{extra}>{body}</text>'


def _wrap(line: str, fontsize: float, width: float) -> list[str]:
    words, out, cur = line.split(" "), [], ""
    for word in words:
        trial = f"{cur} {word}".strip()
        if cur and text_width(trial, fontsize) > width:
            out.append(cur)
            cur = word
        else:
            cur = trial
    return out + [cur]


def _first_baseline(py: float, n: int, size: float, va: str) -> float:
    """Baseline [px] of the first of ``n`` lines of ``size`` [px] placed at ``py`` with vertical alignment ``va``."""
    if va == "top":
        return py + 0.8 * size
    if va == "center":
        return py - (n - 1) * 0.6 * size + 0.35 * size
    if va == "bottom":
        return py - (n - 1) * 1.2 * size - 0.25 * size
    return py - (n - 1) * 1.2 * size  # baseline: the last line's baseline at py


def _text_box(px: float, py: float, lines: list[str], fontsize: float, ha: str, va: str):
    """Estimated (left, top, right, bottom) [px] of text placed as :meth:`Axes.text` places it."""
    size = fontsize * PT
    first = _first_baseline(py, len(lines), size, va)
    width = max(text_width(line, fontsize) for line in lines)
    left = {"left": px, "center": px - width / 2, "right": px - width}[ha]
    return left, first - 0.8 * size, left + width, first + (len(lines) - 1) * 1.2 * size + 0.25 * size


def _arrowhead(x0, y0, x1, y1, col, lw) -> str:
    """A filled arrowhead at (x1, y1) pointing away from (x0, y0)."""
    length = math.hypot(x1 - x0, y1 - y0) or 1.0
    ux, uy = (x1 - x0) / length, (y1 - y0) / length
    size = 4 * PT + lw
    bx, by = x1 - ux * size, y1 - uy * size
    px, py = -uy * size * 0.45, ux * size * 0.45
    return f'<path d="M{_f(x1)} {_f(y1)}L{_f(bx + px)} {_f(by + py)}L{_f(bx - px)} {_f(by - py)}Z" fill="{col}"/>'


def _marker(kind: str, x: float, y: float, size: float, fill: str, edge: str, lw: float) -> str:
    """One marker of width ``size`` [px] centred at (x, y)."""
    r = size / 2
    stroke = f'fill="{fill}" stroke="{edge}" stroke-width="{_f(lw)}"'
    if kind in ("o", "."):
        return f'<circle cx="{_f(x)}" cy="{_f(y)}" r="{_f(r)}" {stroke}/>'
    if kind == "s":
        return _rect(x - r, y - r, size, size, " " + stroke)
    if kind == "_":
        return f'<path d="M{_f(x - r)} {_f(y)}h{_f(size)}" stroke="{fill}" stroke-width="{_f(max(lw, 1.5))}"/>'
    if kind == "x":
        return f'<path d="M{_f(x - r)} {_f(y - r)}l{_f(size)} {_f(size)}M{_f(x - r)} {_f(y + r)}l{_f(size)} {_f(-size)}" stroke="{fill}" stroke-width="{_f(max(lw, 1.5))}"/>'
    if kind == "uarrow":
        return (
            f'<path d="M{_f(x)} {_f(y + r)}V{_f(y - r * 0.4)}" stroke="{fill}" stroke-width="{_f(max(lw, 1.5))}"/>'
            f'<path d="M{_f(x)} {_f(y - r)}L{_f(x - r * 0.45)} {_f(y - r * 0.3)}H{_f(x + r * 0.45)}Z" fill="{fill}"/>'
        )
    shapes = {
        "D": [(0, -1), (0.7, 0), (0, 1), (-0.7, 0)],
        "^": [(0, -1), (0.87, 0.5), (-0.87, 0.5)],
        "*": [(math.sin(k * math.pi / 5) * r_, -math.cos(k * math.pi / 5) * r_) for k, r_ in enumerate([1, 0.4] * 5)],
        "X": [  # a plus sign of arms 1 long and 0.6 wide, turned by 45°
            (a * math.cos(t) - b * math.sin(t), a * math.sin(t) + b * math.cos(t))
            for t in (math.pi / 4,)
            for a, b in zip(
                (1, 0.3, 0.3, -0.3, -0.3, -1, -1, -0.3, -0.3, 0.3, 0.3, 1),
                (0.3, 0.3, 1, 1, 0.3, 0.3, -0.3, -0.3, -1, -1, -0.3, -0.3),
            )
        ],
    }
    pts = shapes.get(kind, shapes["D"])
    d = "M" + "L".join(f"{_f(x + px * r)} {_f(y + py * r)}" for px, py in pts) + "Z"
    return f'<path d="{d}" {stroke} stroke-linejoin="miter"/>'


class Figure:
    """A figure of ``figsize`` inches; its axes draw as one ``<svg>`` (:meth:`to_svg`)."""

    def __init__(self, figsize=(7.5, 5.0)):
        self.width, self.height = figsize[0] * DPI, figsize[1] * DPI
        self.axes: list[Axes] = []
        self.margins = dict(left=0.125, right=0.9, bottom=0.11, top=0.88, wspace=0.2, hspace=0.2)
        self.title = ""
        self.title_size = BASE_FONT * 1.2
        self.legend_args: dict | None = None
        self.bars: list = []

    def subplots_adjust(self, left=None, right=None, bottom=None, top=None, wspace=None, hspace=None) -> None:
        """Margins as fractions of the figure, gaps as fractions of the mean axes width/height (matplotlib's)."""
        for key, value in dict(left=left, right=right, bottom=bottom, top=top, wspace=wspace, hspace=hspace).items():
            if value is not None:
                self.margins[key] = value

    def add_subplot(self) -> Axes:
        """One axes filling the figure inside its margins."""
        return self.subplots()

    def subplots(self, nrows: int = 1, ncols: int = 1, sharex: bool = False, width_ratios=None):
        """A grid of axes (one Axes, a 1-d array or an nrows × ncols array, as matplotlib's)."""
        m = self.margins
        left, right = m["left"] * self.width, m["right"] * self.width
        top, bottom = (1 - m["top"]) * self.height, (1 - m["bottom"]) * self.height
        ratios = list(width_ratios or [1] * ncols)
        cell_w = (right - left) / (sum(ratios) + m["wspace"] * (ncols - 1) * sum(ratios) / ncols)
        gap_w = m["wspace"] * cell_w * sum(ratios) / ncols
        cell_h = (bottom - top) / (nrows + m["hspace"] * (nrows - 1))
        gap_h = m["hspace"] * cell_h
        axes = []
        for r in range(nrows):
            x = left
            for c in range(ncols):
                axes.append(Axes(self, (x, top + r * (cell_h + gap_h), cell_w * ratios[c], cell_h)))
                x += cell_w * ratios[c] + gap_w
        self.axes.extend(axes)
        if sharex:
            for ax in axes[1:]:
                ax.sharex = axes[0]
            for ax in axes[: (nrows - 1) * ncols]:
                ax.hide_xticklabels = True
        if nrows == 1 and ncols == 1:
            return axes[0]
        grid = np.empty(len(axes), dtype=object)
        grid[:] = axes
        return grid.reshape(nrows, ncols) if nrows > 1 and ncols > 1 else grid

    def suptitle(self, text: str, fontsize: float = BASE_FONT * 1.2) -> None:
        """The figure's title, centred at the top; ``fontsize`` [pt]."""
        self.title, self.title_size = text, fontsize

    def legend(self, handles, loc: str = "lower center", ncol: int = 1, fontsize: float = BASE_FONT, **_) -> None:
        """A figure legend of ``handles`` at ``loc`` (``"lower center"``), in ``ncol`` columns."""
        self.legend_args = dict(handles=handles, loc=loc, ncol=ncol, fontsize=fontsize, framealpha=1.0)

    def colorbar(self, mappable: _Mappable, ax: Axes, pad: float = 0.05, label: str = "", **_):
        """A vertical colour bar right of ``ax``, which gives up 15 % of its width for it."""
        x, y, w, h = ax.box
        ax.box[2] = w * 0.85
        bar = _Axis("right", (lambda v: v, lambda v: v))
        bar.label = label
        self.bars.append((mappable, (x + w * (0.85 + pad * 0.85), y, w * 0.05, h), bar))
        return bar

    def _draw_colorbar(self, out, mappable: _Mappable, box, label: str) -> None:
        x, y, w, h = box
        lv = mappable.levels
        lo, hi = float(lv[0]), float(lv[-1])
        for a, b, col in zip(lv[:-1], lv[1:], mappable.colours):
            ya, yb = y + h * (1 - (b - lo) / (hi - lo)), y + h * (1 - (a - lo) / (hi - lo))
            out.append(_rect(x, ya, w, yb - ya + 0.3, f' fill="{col}" fill-opacity="{mappable.alpha:g}"'))
        out.append(_rect(x, y, w, h, ' fill="none" stroke="#000" stroke-width="0.8"'))
        ticks = nice_ticks(lo, hi, _bins(h, True))
        marks, width = _vticks(out, x + w, 1, [y + h * (1 - (t - lo) / (hi - lo)) for t in ticks], _tick_labels(ticks))
        out.append(_marks(marks))
        if label:
            size = BASE_FONT * PT
            out.append(_text(x + w + 5.5 * PT + width + 1.15 * size, y + h / 2, label, BASE_FONT, "middle", rotate=-90))

    def to_svg(self, uid: str = "fig", title: str | None = None) -> str:
        """The figure as one ``<svg>`` element; ``uid`` prefixes its ids (several figures share one page)."""
        out = [
            f'<svg xmlns="http://www.w3.org/2000/svg" class="figure" width="{_f(self.width)}" height="{_f(self.height)}" '
            f'viewBox="0 0 {_f(self.width)} {_f(self.height)}" font-family="{FONT}" role="img">'
        ]
        if title:
            out.append(f"<title>{escape(title)}</title>")
        out.append(f'<rect width="{_f(self.width)}" height="{_f(self.height)}" fill="#ffffff"/>')
        for k, ax in enumerate(self.axes):
            ax.render(out, f"{uid}-{k}")
        for mappable, box, bar in self.bars:
            self._draw_colorbar(out, mappable, box, bar.label)
        if self.title:
            y = 0.3 * DPI * 0.55 + self.title_size * PT * 0.5
            out.append(_text(self.width / 2, y, self.title, self.title_size, "middle"))
        if self.legend_args is not None:
            draw_legend(out, box=(0, 0, self.width, self.height), **self.legend_args)
        out.append("</svg>")
        return "\n".join(out)


# --------------------------------------------------------------------------- the records' small charts


def _small_chart(xlabel, ylabel, width, height, box, xlabel_gap, body, ends=None, frame=False) -> str:
    """A small SVG plot: ``body`` (elements) in the plot ``box`` (left, right, top, bottom margins [px]), the four
    ``ends`` (x0, x1, y0, y1) of its axes at the box's corners, the x label under it, the y label turned along
    the left edge; ``frame`` draws the box."""
    left, right, top, bottom = box
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
        f'viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="10">',
        f"<title>{escape(ylabel)} against {escape(xlabel)}</title>",
    ]
    if frame:
        out.append(
            f'<rect x="{left}" y="{top}" width="{width - left - right}" height="{height - top - bottom}" '
            f'fill="none" stroke="#999"/>'
        )
    out += body
    if ends is not None:
        x0, x1, y0, y1 = ends
        out += [
            f'<text x="{left}" y="{height - bottom + 12}">{x0:.3g}</text>',
            f'<text x="{width - right}" y="{height - bottom + 12}" text-anchor="end">{x1:.3g}</text>',
            f'<text x="{left - 3}" y="{height - bottom}" text-anchor="end">{y0:.3g}</text>',
            f'<text x="{left - 3}" y="{top + 9}" text-anchor="end">{y1:.3g}</text>',
        ]
    out += [
        f'<text x="{(left + width - right) / 2:.0f}" y="{height - xlabel_gap}" text-anchor="middle">'
        f"{escape(xlabel)}</text>",
        f'<text transform="translate(11,{(top + height - bottom) / 2:.0f}) rotate(-90)" '
        f'text-anchor="middle">{escape(ylabel)}</text>',
        "</svg>",
    ]
    return "".join(out)


def _linear(lo: float, hi: float, start: float, end: float):
    """The linear map of [lo, hi] (data) onto [start, end] [px]."""
    return lambda v: start + (v - lo) / (hi - lo) * (end - start)


def svg_curve(x: Any, y: Any, xlabel: str, ylabel: str, marks: Any = (), width: int = 240, height: int = 170) -> str:
    """A small line plot as an SVG string: the points (x, y) joined in order, axis labels with units.

    ``marks``: (x, y, label) points drawn as dots (e.g. the knee).  Non-finite points are dropped.
    """
    pts = [(float(a), float(b)) for a, b in zip(x, y) if math.isfinite(a) and math.isfinite(b)]
    box = left, right, top, bottom = 42, 8, 8, 32
    if not pts:
        return _small_chart(xlabel, ylabel, width, height, box, 4, [], frame=True)
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    x0, x1 = min(xs), max(xs)
    y0, y1 = min(ys), max(ys)
    x0, x1 = (x0 - 0.5, x1 + 0.5) if x1 == x0 else (x0, x1)
    y0, y1 = (y0 - 0.5, y1 + 0.5) if y1 == y0 else (y0, y1)

    px, py = _linear(x0, x1, left + 4, width - right - 4), _linear(y0, y1, height - bottom - 4, top + 4)
    line = " ".join(f"{px(a):.1f},{py(b):.1f}" for a, b in pts)
    body = [f'<polyline points="{line}" fill="none" stroke="#1f77b4" stroke-width="1.5"/>']
    body += [f'<circle cx="{px(a):.1f}" cy="{py(b):.1f}" r="1.6" fill="#1f77b4"/>' for a, b in pts]
    body += [
        f'<circle cx="{px(a):.1f}" cy="{py(b):.1f}" r="3.5" fill="#d62728"><title>{escape(label)}</title></circle>'
        for a, b, label in marks
    ]
    return _small_chart(xlabel, ylabel, width, height, box, 4, body, (x0, x1, y0, y1), frame=True)


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
    box = left, right, top, bottom = 38, 6, 6, 28
    if not pts:
        return _small_chart(xlabel, ylabel, width, height, box, 3, [])
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    x0, x1 = min(xs), max(xs)
    banded = band is not None and math.isfinite(band)
    reach = max([abs(v) for v in ys] + ([abs(band)] if banded else []))
    y0, y1 = (-reach, reach) if reach > 0 else (-1.0, 1.0)
    x1 = x1 if x1 > x0 else x0 + 1.0

    px, py = _linear(x0, x1, left, width - right), _linear(y0, y1, height - bottom, top)
    body = [f'<line x1="{left}" y1="{py(0):.1f}" x2="{width - right}" y2="{py(0):.1f}" stroke="#999"/>']
    body += [
        f'<line x1="{left}" y1="{py(b):.1f}" x2="{width - right}" y2="{py(b):.1f}" '
        f'stroke="#d62728" stroke-dasharray="4 3"/>'
        for b in ((band, -band) if banded else ())
    ]
    line = " ".join(f"{px(a):.1f},{py(b):.1f}" for a, b in pts)
    body.append(f'<polyline points="{line}" fill="none" stroke="#1f77b4" stroke-width="1.2"/>')
    return _small_chart(xlabel, ylabel, width, height, box, 3, body, (x0, x1, y0, y1))


__all__ = ["Axes", "DPI", "Figure", "colour", "draw_legend", "nice_ticks", "svg_curve", "svg_sparkline", "text_width"]
