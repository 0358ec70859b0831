"""The caster drawn to scale: side view (wheel, fork, trail, sill) and top view (swept circle, footrest limit).

Two renderers of one geometry (:func:`caster_geometry`):

- :func:`draw_caster` draws on matplotlib Axes (two Axes in, the same Axes out);
- :func:`caster_svg` returns a small hand-built SVG string (no matplotlib: for reprs and the report's
  first screen, where it costs nothing to draw).

Geometry (all lengths [m], SI in, inches on the labels):

- the swivel (stem) axis is vertical at x = 0; the wheel centre trails it by T at x = −T, height d/2
  (the paper's trail, Fig. 1: the horizontal distance from the stem axis to the wheel's ground contact);
- the caster rolls towards +x; the door sill, of height h, stands where the wheel touches its edge:
  x_sill = −T + sqrt((d/2)² − (d/2 − h)²);
- top view: the wheel sweeps a circle of radius R_s = T + d/2 about the stem axis (docs/model.md);
  the footrest limit R_max, when the problem has one, is the dashed circle;
- the tyre is drawn as two treads separated by the groove B (the tread separation of Eq. 7), each
  :data:`TREAD` wide (illustrative: the model does not use the tread width).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from html import escape
from designer.display import shown
from designer.units import INCH, written_size

TREAD = 0.25 * INCH
"""Width of each tread in the drawing [m] (illustrative only)."""
STEM = 1.5 * INCH
"""Height of the stem above the fork crown in the drawing [m] (illustrative only)."""


@dataclass(frozen=True)
class CasterGeometry:
    """Points of the drawing [m] (stem axis at x = 0, ground at y = 0, travel towards +x)."""

    trail: float
    diameter: float
    groove: float
    sill_height: float
    swept_radius: float
    swept_radius_max: float | None
    axle: tuple[float, float]
    sill_x: float
    crown_y: float
    stem_top: float
    tyre_width: float


def caster_geometry(
    trail: float, diameter: float, groove: float, sill_height: float, swept_radius_max: float | None = None
) -> CasterGeometry:
    """The drawing's geometry for trail T [m], diameter d [m], groove B [m], sill h [m] and R_max [m] or None."""
    for name, value in (("trail", trail), ("diameter", diameter), ("groove", groove), ("sill_height", sill_height)):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
            raise ValueError(f"{name} = {value!r}: must be a finite length >= 0 [m]")
    if diameter <= 0:
        raise ValueError(f"diameter = {diameter!r}: must be positive [m]")
    r = diameter / 2
    h = min(sill_height, r)
    sill_x = -trail + math.sqrt(max(r * r - (r - h) ** 2, 0.0))
    crown_y = diameter + 0.3 * INCH
    return CasterGeometry(
        trail=trail,
        diameter=diameter,
        groove=groove,
        sill_height=sill_height,
        swept_radius=trail + r,
        swept_radius_max=swept_radius_max,
        axle=(-trail, r),
        sill_x=sill_x,
        crown_y=crown_y,
        stem_top=crown_y + STEM,
        tyre_width=groove + 2 * TREAD,
    )


def draw_caster(
    ax_side,
    ax_top,
    trail: float,
    diameter: float,
    groove: float,
    sill_height: float,
    swept_radius_max: float | None = None,
    title: str | None = None,
):
    """Draw the caster to scale on two matplotlib Axes; returns ``(ax_side, ax_top)``.

    Parameters
    ----------
    ax_side, ax_top : matplotlib Axes for the side view and the top view (either may be None)
    trail : T [m]; diameter : d [m]; groove : B [m] (tread separation); sill_height : h [m]
    swept_radius_max : footrest limit R_max [m] on T + d/2, or None
    title : optional title of the side view
    """
    from matplotlib.patches import Circle, Rectangle  # matplotlib: heavy, loaded only when drawing

    g = caster_geometry(trail, diameter, groove, sill_height, swept_radius_max)
    k = 1 / INCH  # draw in inches
    ax, ay = g.axle
    if ax_side is not None:
        s = ax_side
        s.axhline(0, color="0.3", lw=1)
        s.add_patch(Rectangle((g.sill_x * k, 0), 1.2 * g.diameter * k, g.sill_height * k, color="0.75", lw=0))
        s.add_patch(Circle((ax * k, ay * k), g.diameter / 2 * k, fill=False, lw=2.2, color="#1f4e79"))
        s.add_patch(Circle((ax * k, ay * k), 0.08 * g.diameter * k, color="#1f4e79"))
        s.plot([0, 0, ax * k, ax * k], [g.stem_top * k, g.crown_y * k, g.crown_y * k, ay * k], color="0.2", lw=3)
        s.plot([0, 0], [-0.3, g.stem_top * k + 0.2], color="#c0392b", ls="-.", lw=1)
        s.annotate("", (ax * k, -0.18), (0, -0.18), arrowprops=dict(arrowstyle="<->", lw=1))
        s.text(ax * k / 2, -0.35, f"trail T = {shown(g.trail, 'trail', 'in')}", ha="center", va="top", fontsize=8)
        d_text = f"d = {shown(g.diameter, 'diameter', 'in')}"
        s.text(ax * k, 0.27 * g.diameter * k, d_text, ha="center", va="top", fontsize=8)
        right, sill = (g.sill_x + 0.7 * g.diameter) * k, f"sill h = {shown(g.sill_height, 'threshold_height', 'in')}"
        s.text(right - 0.05, g.sill_height * k + 0.05, sill, fontsize=8, va="bottom", ha="right")
        s.text(0.1, g.stem_top * k, "swivel axis", color="#c0392b", fontsize=8, va="top")
        s.set_aspect("equal")
        s.set_xlim((ax - g.diameter * 0.65) * k, right)
        s.set_ylim(-0.8, g.stem_top * k + 0.4)
        s.set_xlabel("side view [in] (rolls towards the right)")
        if title:
            s.set_title(title, fontsize=10)
    if ax_top is not None:
        t = ax_top
        t.add_patch(Circle((0, 0), g.swept_radius * k, fill=False, color="#1f4e79", lw=1.5))
        if g.swept_radius_max is not None:
            t.add_patch(Circle((0, 0), g.swept_radius_max * k, fill=False, color="#c0392b", lw=1.2, ls="--"))
        for y0 in (-g.tyre_width / 2, g.groove / 2):
            t.add_patch(Rectangle(((ax - g.diameter / 2) * k, y0 * k), g.diameter * k, TREAD * k, color="#1f4e79"))
        t.plot([0, ax * k], [0, 0], color="0.2", lw=2)
        t.plot([0], [0], "o", color="#c0392b")
        text = f"swept radius R_s = T + d/2 = {shown(g.swept_radius, 'swept_radius', 'in')}"
        if g.swept_radius_max is not None:
            text += f"\nfootrest limit R_max = {shown(g.swept_radius_max, 'swept_radius_max', 'in')} (dashed)"
        t.text(0, -(max(g.swept_radius, g.swept_radius_max or 0) * k + 0.25), text, ha="center", va="top", fontsize=8)
        lim = max(g.swept_radius, g.swept_radius_max or 0) * k * 1.1
        t.set_aspect("equal")
        t.set_xlim(-lim, lim)
        t.set_ylim(-lim - 1.2, lim)
        t.set_xlabel(f"top view [in] (groove B = {shown(g.groove, 'groove', 'in')})")
    return ax_side, ax_top


def plot_caster(
    trail: float,
    diameter: float,
    groove: float,
    sill_height: float,
    swept_radius_max: float | None = None,
    title: str | None = None,
    ax=None,
):
    """The caster to scale, side and top views (:func:`draw_caster`); returns ``(ax_side, ax_top)``.

    ``ax``: None (a new figure with both views), one Axes (the side view only; ``ax_top`` is None) or a pair
    of Axes.  Lengths [m] as :func:`draw_caster`.  Used by :meth:`Recommendation.draw`.
    """
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(1, 2, figsize=(9, 4.2), width_ratios=(1.25, 1), layout="constrained")
    side, top = (ax, None) if not isinstance(ax, (tuple, list)) and getattr(ax, "ndim", 0) == 0 else tuple(ax)
    return draw_caster(side, top, trail, diameter, groove, sill_height, swept_radius_max, title=title)


# long: the drawing, one SVG element after another
def caster_svg(  # noqa: C901 - one branch per optional part of the drawing (limit, groove, units)
    trail: float,
    diameter: float,
    groove: float,
    sill_height: float,
    swept_radius_max: float | None = None,
    scale: float | None = None,
    label: str | None = None,
    units: str | None = None,
) -> str:
    """The caster to scale as an SVG string: side view left, top view right, each with its caption under it.

    ``scale`` is pixels per inch, the same in both views so the drawing is to scale (default: the top view
    about 320 px wide, 18–32 px/in).  ``units``: None labels sizes in decimal inches (``6.000 in``); ``"in"``
    to the nearest 1/16 (``2 1/2 in``), ``"mm"`` in millimetres to 0.1, as the report's ``[report] units``.
    The top view labels the two treads (one tyre when B = 0) and draws the footrest limit R_max as a wide red
    dashed ring under the swept circle, so it shows even where it equals the swept radius.  Text is escaped.
    """
    g = caster_geometry(trail, diameter, groove, sill_height, swept_radius_max)

    def size(value: float) -> str:
        return shown(value, dimension="length", units="in") if units is None else written_size(value, units)

    if scale is None:
        reach_in = max(g.swept_radius, g.swept_radius_max or 0.0) / INCH
        scale = min(32.0, max(18.0, 320.0 / (2.16 * reach_in)))
    s = scale / INCH  # px per metre
    pad = 0.6 * INCH
    ax, ay = g.axle
    # side view box in metres: x from axle − 0.65 d to sill + 0.7 d; y from −0.8 in to stem top + pad
    x0 = ax - 0.65 * g.diameter
    x1 = max(g.sill_x + 0.7 * g.diameter, x0 + 320 / s)  # room for the labels: at least 320 px wide
    y0, y1 = -0.8 * INCH, g.stem_top + pad
    side_w, side_h = (x1 - x0) * s, (y1 - y0) * s
    reach = max(g.swept_radius, g.swept_radius_max or 0.0) * 1.08
    top_w = max(2 * reach * s, 300.0)  # at least as wide as its caption
    top_h = 2 * reach * s
    gap = 28
    width = side_w + gap + top_w
    top_lines = [f"top view: swept radius R_s = T + d/2 = {size(g.swept_radius)} (blue)"]
    if g.swept_radius_max is not None:
        at = " (at the limit)" if abs(g.swept_radius_max - g.swept_radius) < 1e-9 else ""
        top_lines.append(f"footrest limit R_max = {size(g.swept_radius_max)} (red dashes){at}")
    height = max(side_h + 22, top_h + 8 + 14 * len(top_lines))

    def sx(x):  # side view: metres -> px
        return (x - x0) * s

    def sy(y):
        return (y1 - y) * s

    ox, oy = side_w + gap + top_w / 2, top_h / 2  # top view origin (stem axis)

    def tx(x):
        return ox + x * s

    def ty(y):
        return oy - y * s

    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" class="caster-drawing" width="{width:.0f}" '
        f'height="{height:.0f}" viewBox="0 0 {width:.1f} {height:.1f}" font-family="sans-serif" font-size="11">',
        '<defs><marker id="caster-arrow" viewBox="0 0 10 10" refX="5" refY="5" markerWidth="6" markerHeight="6" '
        'orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z"/></marker></defs>',
        f"<title>{escape(label or 'caster drawn to scale')}</title>",
    ]
    # side view
    out.append(_el("line", x1="0", y1=sy(0), x2=side_w, y2=sy(0), extra=' stroke="#555" stroke-width="1"'))
    sill = dict(x=sx(g.sill_x), y=sy(g.sill_height), width=(x1 - g.sill_x) * s, height=g.sill_height * s)
    out.append(_el("rect", **sill, extra=' fill="#bbb"'))
    wheel = ' fill="none" stroke="#1f4e79" stroke-width="3"'
    out.append(_el("circle", cx=sx(ax), cy=sy(ay), r=g.diameter / 2 * s, extra=wheel))
    out.append(_el("circle", cx=sx(ax), cy=sy(ay), r=0.08 * g.diameter * s, extra=' fill="#1f4e79"'))
    fork = " ".join(f"{sx(a):.1f},{sy(b):.1f}" for a, b in ((0, g.stem_top), (0, g.crown_y), (ax, g.crown_y), (ax, ay)))
    out.append(f'<polyline points="{fork}" fill="none" stroke="#333" stroke-width="4"/>')  # stem, crown, leg
    axis = ' stroke="#c0392b" stroke-dasharray="6,3,2,3"'
    out.append(_el("line", x1=sx(0), y1=sy(y1 - pad / 2), x2=sx(0), y2=sy(-0.2 * INCH), extra=axis))
    ya = sy(-0.25 * INCH)
    arrows = ' stroke="#000" marker-start="url(#caster-arrow)" marker-end="url(#caster-arrow)"'
    out.append(_el("line", x1=sx(ax), y1=ya, x2=sx(0), y2=ya, extra=arrows))
    middle = ' text-anchor="middle"'
    # the trail below the arrow at any scale; the diameter right of the hub, clear of the fork leg
    out.append(_label(sx(ax / 2), max(ya + 14, sy(-0.7 * INCH)), f"trail T = {size(g.trail)}", middle))
    out.append(_label(sx(ax) + 0.1 * g.diameter * s + 4, sy(ay) + 4, f"d = {size(g.diameter)}"))
    out.append(_label(side_w - 2, sy(g.sill_height) - 4, f"sill h = {size(g.sill_height)}", ' text-anchor="end"'))
    out.append(_label(sx(0) + 4, sy(g.stem_top) + 4, "swivel axis", ' fill="#c0392b"'))
    out.append(_label(side_w / 2, side_h + 16, "side view, rolling to the right", middle, "caption"))
    # top view: the swept disc, then the footrest limit wide and dashed, then the swept circle's thin line over
    # it: the limit shows even where it equals the swept radius
    r_s = g.swept_radius * s
    out.append(_el("circle", cx=ox, cy=oy, r=r_s, extra=' fill="#eef4fb" stroke="none"'))
    if g.swept_radius_max is not None:
        dashes = ' fill="none" stroke="#c0392b" stroke-opacity="0.75" stroke-width="6" stroke-dasharray="9,6"'
        out.append(_el("circle", "footrest-limit", cx=ox, cy=oy, r=g.swept_radius_max * s, extra=dashes))
    out.append(_el("circle", "swept", cx=ox, cy=oy, r=r_s, extra=' fill="none" stroke="#1f4e79" stroke-width="1.5"'))
    for yy in (g.tyre_width / 2, -g.groove / 2):
        tread = dict(x=tx(ax - g.diameter / 2), y=ty(yy), width=g.diameter * s, height=TREAD * s)
        out.append(_el("rect", "tread", **tread, extra=' fill="#1f4e79"'))
    out.append(_el("line", x1=tx(0), y1=ty(0), x2=tx(ax), y2=ty(0), extra=' stroke="#333" stroke-width="2"'))
    out.append(_el("circle", cx=tx(0), cy=ty(0), extra=' r="3" fill="#c0392b"'))
    if g.groove > 1e-9:
        tread_labels = ((g.tyre_width / 2, -4, "tread"), (-g.tyre_width / 2, 12, "tread"))
        out.append(_label(tx(ax + g.diameter / 2) + 4, ty(0) + 4, f"groove B = {size(g.groove)}"))
    else:
        tread_labels = ((g.tyre_width / 2, -4, "one tread (no groove)"),)
    out += [_label(tx(ax), ty(yy) + dy, text, middle) for yy, dy, text in tread_labels]
    out += [_label(ox, top_h + 8 + 14 * i, line, middle, "caption") for i, line in enumerate(top_lines)]
    out.append("</svg>")
    return "\n".join(out)


def _el(tag: str, cls: str = "", text: str | None = None, extra: str = "", **at) -> str:
    """An SVG element ``tag`` of class ``cls`` with the attributes ``at`` (numbers [px] to 0.1 px) and then
    ``extra`` (attribute text), holding ``text`` (escaped) if given."""
    attrs = (f' class="{cls}"' if cls else "") + "".join(
        f' {k}="{v if isinstance(v, str) else f"{v:.1f}"}"' for k, v in at.items()
    )
    return f"<{tag}{attrs}{extra}>{escape(text)}</{tag}>" if text is not None else f"<{tag}{attrs}{extra}/>"


def _label(x: float, y: float, text: str, attrs: str = "", cls: str = "") -> str:
    """An SVG ``<text>`` of ``text`` (escaped) at (x, y) [px]; ``attrs``: its further attributes, ``cls``: its class."""
    return _el("text", cls, text, attrs, x=x, y=y)


__all__ = ["CasterGeometry", "caster_geometry", "caster_svg", "draw_caster"]
