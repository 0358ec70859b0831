"""The report's figures, drawn on the SVG canvas of :mod:`designer.plots.svg` (matplotlib's object API).

Each ``figure_*`` function takes what it draws (arrays, plain records, the
problem's bounds) and returns a :class:`designer.plots.svg.Figure` (``to_svg()`` gives the SVG text);
:mod:`designer.report.figures` picks those arguments out of a report's data.  No matplotlib: a figure
costs milliseconds, so the main job draws all six (benchmarks/results.md).
The front and its design variables are drawn by the same functions as
:meth:`Front.plot` and :meth:`Front.plot_variables`
(:mod:`designer.plots.fronts`).  They compute nothing: every curve is an array of
:mod:`designer.studies.curves` (the report data's ``curves``), computed by the model.  Lengths
are plotted in millimetres with inches on a secondary axis; only valid
(successful) front points are drawn.

Figures (name: what it redraws)
-------------------------------
front          the Pareto front F_turn vs P, knee and weighted optimum marked
variables      the design variables T, d, B, c_f along the front
trail          V_c vs trail for the Table 1 wheels (the paper's Fig. 14)
inertia        V_c vs I_w at 2 in trail with the measured points (Fig. 15)
threshold      P/L vs diameter, exact Eq. 4A and approximate Eq. 5A (Fig. 2A)
groove_damper  groove against damper: turning effort needed to reach V_req
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from designer.display import axis, number, rescale, shown, unit
from designer.data.paper import INCH, TABLE1_STABLE_UP_TO, TABLE1_TRAIL, WALKING_SPEED
from designer.output import PLOT, SOFTWARE, write_file
from designer.plots.fronts import COLOR_BY, dress, draw_fronts, plot_front, plot_variables, variable_axis
from designer.plots.svg import Figure

FIGURES = ("front", "variables", "trail", "inertia", "threshold", "groove_damper")
"""Figure names in report order; ``figure_<name>`` draws each."""

MECHANISM_STYLE = {
    "groove alone": ("#1f77b4", "-", "o"),
    "damper alone": ("#d62728", "--", "s"),
    "optimum mix": ("#2ca02c", ":", "D"),
}
MM = unit("length", "mm").factor
"""Lengths are plotted in millimetres."""
BOXED = dict(bbox=dict(facecolor="white", alpha=0.8, lw=0))
"""A note's white box."""
WHEEL_COLOURS = ("#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02", "#a6761d")


def _inch_x(ax, name: str):
    """The inch axis on top of a design variable ``name`` plotted in millimetres."""
    sec = ax.secondary_xaxis("top", functions=(rescale("mm", "in"), rescale("in", "mm")))
    sec.set_xlabel(variable_axis(name, "in"))
    return sec


def _stable(ax, x: float, y: float, colour: str, rise: float, lw: float, s: float, zorder: float = 1) -> None:
    """A wheel that did not shimmy up to speed ``y`` [m/s] (the treadmill's limit): a bar at it with an arrow
    ``rise`` [m/s] up, at ``x``."""
    ax.annotate("", (x, y + rise), (x, y), arrowprops=dict(arrowstyle="->", color=colour, lw=lw))
    ax.scatter([x], [y], marker="_", s=s, color=colour, zorder=zorder)


def _walking(ax, x: float, dy: float) -> None:
    """The walking speed, a dotted line labelled at ``x`` [data units], ``dy`` [m/s] above it."""
    ax.axhline(WALKING_SPEED, color="0.4", ls=":", lw=1)
    ax.text(x, WALKING_SPEED + dy, "walking speed 1 m/s", fontsize=8, color="0.3")


MARGINS = dict(left=0.65, right=0.15, bottom=0.5, top=0.35)
"""A figure's default margins [in] around its axes (:func:`_new`)."""


def _new(width: float = 7.5, height: float = 4.8, wspace: float = 0.2, hspace: float = 0.2, **margins) -> Figure:
    """A figure of ``width`` x ``height`` inches with fixed ``margins`` [in] around the axes (``left``, ``right``,
    ``bottom``, ``top``; the others as :data:`MARGINS`).

    Fixed margins (the SVG canvas measures no text): each figure gives the margins its labels need (a
    title, an inch axis on top, a right-hand axis or colour bar).
    """
    m = MARGINS | margins
    fig = Figure(figsize=(width, height))
    fig.subplots_adjust(m["left"] / width, 1 - m["right"] / width, m["bottom"] / height, 1 - m["top"] / height)
    fig.subplots_adjust(wspace=wspace, hspace=hspace)
    return fig


CREATOR = ("svg", "pdf", "ps", "eps")
"""Figure formats whose metadata take a Creator (matplotlib): the tool's name goes there."""


def save_figure(fig, path, dpi: int = 110, option: str = "--plot") -> None:
    """Save a figure to ``path`` (format from its suffix) and close it; the file is replaced atomically
    (:func:`designer.output.write_file`), and a place that cannot be written is an OutputError naming ``option``."""
    import matplotlib.pyplot as plt

    # the metadata name this tool (not matplotlib's version: a redrawn figure has the same bytes), so that the
    # next --plot recognises the file as its own figure (designer.output.PLOT) and replaces nothing else
    suffix = Path(path).suffix[1:].lower()
    metadata = {"Software": SOFTWARE} if suffix == "png" else {"Creator": SOFTWARE} if suffix in CREATOR else None
    try:
        buf = io.BytesIO()
        fig.savefig(buf, format=suffix or None, dpi=dpi, metadata=metadata)
        write_file(path, buf.getvalue(), option, example="plot.png", kind=PLOT)
    finally:
        plt.close(fig)


def png_bytes(fig, dpi: int = 110) -> bytes:
    """A matplotlib figure as PNG bytes (Agg renderer; the robust and calibration reports)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, metadata={"Software": None})  # no matplotlib version in the bytes
    return buf.getvalue()


# --------------------------------------------------------------------------- front


def figure_front(
    front: dict,
    title: str,
    tighter: dict | None = None,
    curves=(),
    marks=(),
    ends=(),
    note: str | None = None,
    hover=None,
) -> Figure:
    """Pareto front: turning effort F_turn [N] against threshold force P [N] (the report's front figure).

    The front is drawn by :func:`designer.plots.fronts.plot_front` (points coloured by design family, as
    :meth:`Front.plot`), the other fronts and the marked designs by
    :func:`designer.plots.fronts.draw_fronts`.

    Parameters
    ----------
    front : ``{"turning_effort": [N], "threshold_force": [N], "family": [str]}``, one entry per point
    title : the axes title
    tighter : optional curve ``{"turning_effort": [N], "threshold_force": [N], "label": str}`` drawn in grey
        (the front for the tighter target, check 8c)
    curves, marks : further fronts and marked designs (:func:`~designer.plots.fronts.draw_fronts` records)
    ends : up to two records ``{"turning_effort", "threshold_force" [N], "trail", "diameter", "groove" [m]}``
        labelled with their sizes in inches (the two ends of the front)
    note : text shown under a single-point front (why it is a single point)
    hover : optional tooltip text per front point (its numbers); the marked designs show their labels
    """
    fig = _new(7.5, 5.0)
    ax = fig.add_subplot()
    if tighter is not None:
        style = dict(color="0.65", lw=1.5, ls="--", marker=".", ms=4)
        ax.plot(tighter["threshold_force"], tighter["turning_effort"], label=tighter["label"], **style)
    f = np.asarray(front["turning_effort"], float)
    p = np.asarray(front["threshold_force"], float)
    plot_front(f, p, front["family"], ax=ax, legend=False)
    if len(f):
        draw_fronts(ax, curves, marks, legend=False)
        _label_ends(ax, ends)
        if len(f) == 1:
            ax.set_xlim(p[0] * 0.9, p[0] * 1.1)
            ax.set_ylim(f[0] * 0.8, f[0] * 1.2)
            note = "single-point front: " + (note or "")
            ax.text(0.5, 0.08, note, transform=ax.transAxes, ha="center", fontsize=8.5, wrap=True, color="0.2")
        else:
            t = np.asarray(tighter["turning_effort"], float) if tighter is not None else f
            lo, hi = min(f.min(), t.min()), max(f.max(), t.max())
            pad = 0.12 * (hi - lo if hi > lo else 1.0)
            ax.set_ylim(lo - 3 * pad, hi + 2.2 * pad)
    if hover is not None:
        ax.hover(p, f, hover)
        named = [m for m in marks if m["label"]]  # a mark drawn on another's spot shares its label
        ax.hover(*([m[k] for m in named] for k in ("threshold_force", "turning_effort", "label")))
    ax.legend(fontsize=7.5, loc="upper right", framealpha=0.9)
    ax.set_title(title, fontsize=10)
    return fig


def _label_ends(ax, ends) -> None:
    """Label the front's ends with their sizes [in], on the empty ideal side (below-left), with a line to each."""
    places = (
        dict(xytext=(-25, -30), textcoords="offset points", ha="right", va="top"),
        dict(xytext=(0.03, 0.05), textcoords="axes fraction", ha="left", va="bottom"),
    )
    line, sizes = dict(arrowstyle="-", color="0.5", lw=0.8), (("d", "diameter"), ("T", "trail"), ("B", "groove"))
    for end, place in zip(ends, places):
        text = "\n".join(f"{s} = {shown(end[k], k, 'in', digits=2)}" for s, k in sizes)
        at = (end["threshold_force"], end["turning_effort"])
        ax.annotate(text, at, fontsize=8, color="0.25", arrowprops=line, **place)


# --------------------------------------------------------------------------- variables


def figure_variables(threshold_force, designs, families, bounds, gaps=(), hover=None) -> Figure:
    """The design variables T, d, B [mm, in] and c_f [N·m/rad] along the front, against P [N].

    Drawn by :func:`designer.plots.fronts.plot_variables` (as :meth:`Front.plot_variables`); arguments as
    there.  Dashed vertical lines mark family switches (``gaps``); ``hover``: optional tooltip per point.
    """
    fig = Figure(figsize=(8.5, 6.2))
    fig.subplots_adjust(left=0.09, right=0.91, bottom=0.15, top=0.93, wspace=0.45, hspace=0.1)
    axes = fig.subplots(2, 2, sharex=True)
    plot_variables(threshold_force, designs, families, bounds, gaps, axes=axes)
    if hover is not None:
        x = np.asarray(threshold_force, float).reshape(-1)
        d = np.asarray(designs, float).reshape(-1, 4)
        for ax, (_, k, scale) in zip(axes.ravel(), COLOR_BY.values()):
            ax.hover(x, d[:, k] * scale, hover)
    return fig


# --------------------------------------------------------------------------- paper figures


def figure_trail(required_speed: float, curves: dict) -> Figure:
    """V_c [m/s] vs trail T [mm, in] for the Table 1 wheels (Eq. 7, B = 0, bare fork c_f = 1.3): Fig. 14.

    ``required_speed``: the problem's V_req [m/s], drawn as a dashed line; ``curves``: the wheels' curves
    (:func:`designer.studies.curves.trail_curves`).

    Measured critical speeds at 2 in trail (wheels C–G) are points in the
    colour of their curve; wheels A and B, stable to 3.8 m/s on the
    treadmill, are arrows at 3.8 m/s.
    """
    fig = _new(7.5, 5.0, top=0.75)  # title and the inch axis on top
    ax = fig.add_subplot()
    trail = np.asarray(curves["trail"], float)
    stable_offset = iter((-1.0, 1.0, 0.0))  # side by side: A and B were both stable at 2 in
    for w, colour in zip(curves["wheels"], WHEEL_COLOURS):
        key, name, measured = w["key"], w["name"], w["measured"]
        ax.plot(trail * MM, w["speeds"], color=colour, lw=1.4, label=f"{key} {name}, I_w {w['inertia'] * 1e3:.2f}e-3")
        if measured is not None:
            ax.scatter([TABLE1_TRAIL * MM], [measured], color=colour, edgecolor="black", s=40, zorder=4)
            says = f"wheel {key} {name}: measured V_c {measured:.2f} m/s at T = 2 in; Eq. 7 {w['eq7']:.2f} m/s"
            ax.hover([TABLE1_TRAIL * MM], [measured], [says])
        else:
            _stable(ax, TABLE1_TRAIL * MM + next(stable_offset), TABLE1_STABLE_UP_TO, colour, 0.5, 1.8, 60, zorder=4)
    ax.scatter([], [], color="white", edgecolor="black", s=40, label="measured at 2 in (Table 1)")
    note = "A, B: stable to 3.8 m/s\n(treadmill limit)"
    ax.annotate(note, (TABLE1_TRAIL * MM, TABLE1_STABLE_UP_TO), textcoords="offset points", xytext=(8, -22), fontsize=8)
    _walking(ax, trail[0] * MM + 1, 0.08)
    req = required_speed
    ax.axhline(req, color="black", ls="--", lw=1)
    # at the right end: the legend fills the upper left, and at the left a fast target's label went under it
    ax.text(trail[-1] * MM - 1, req + 0.08, f"this problem's V_req = {req:.2f} m/s", fontsize=8, ha="right", **BOXED)
    ax.set_xlim(trail[0] * MM, trail[-1] * MM)
    ax.set_ylim(0, 7)
    _inch_x(ax, "trail")
    title = "V_c vs trail, Table 1 wheels, Eq. 7 (B = 0, c_f = 1.3 N·m/rad) (cf. paper Fig. 14)"
    legend = dict(fontsize=7.5, loc="upper left", title="Table 1 wheel, I_w [kg·m²]", title_fontsize=8)
    dress(ax, variable_axis("trail"), axis("critical_speed"), title, legend)
    return fig


def figure_inertia(curves: dict) -> Figure:
    """V_c [m/s] vs wheel inertia I_w [kg·m²] at 2 in trail (Eq. 7, B = 0, c_f = 1.3) with Table 1's measurements:
    Fig. 15; ``curves``: :func:`designer.studies.curves.inertia_curve`."""
    fig = _new(7.5, 5.0)
    ax = fig.add_subplot()
    inertia = np.asarray(curves["inertia"], float)
    ax.plot(inertia * 1e3, curves["speeds"], color="#1f77b4", lw=1.6, label="Eq. 7, T = 2 in, B = 0, c_f = 1.3 N·m/rad")
    wheels = curves["wheels"]
    measured = [w for w in wheels if w["measured"] is not None]
    mx, my = [w["inertia"] * 1e3 for w in measured], [w["measured"] for w in measured]
    ax.scatter(mx, my, color="#d62728", edgecolor="black", s=45, zorder=4, label="measured critical speed (Table 1)")
    at = [(w["inertia"] * 1e3, TABLE1_STABLE_UP_TO if w["measured"] is None else w["measured"]) for w in wheels]
    for w, (x, y) in zip(wheels, at):
        if w["measured"] is None:
            _stable(ax, x, y, "#d62728", 0.6, 1.5, 120)
        ax.annotate(w["key"], (x, y), textcoords="offset points", xytext=(6, 4), fontsize=9, weight="bold")
    stable = "A, B: no shimmy up to 3.8 m/s (treadmill limit)"
    ax.plot([], [], color="#d62728", marker="uarrow", ls="none", ms=10, label=stable)
    says = [
        f"wheel {w['key']} {w['name']}: I_w {w['inertia'] * 1e3:.2f}e-3 kg·m², "
        + (f"measured V_c {w['measured']:.2f} m/s" if w["measured"] is not None else "no shimmy up to 3.8 m/s")
        + f"; Eq. 7 {w['eq7']:.2f} m/s"
        for w in wheels
    ]
    ax.hover(*zip(*at), says)
    _walking(ax, 2.2, -0.22)
    ax.set_xlim(0, 3.8)
    ax.set_ylim(0, 7)
    xlabel = "wheel moment of inertia about a diameter I_w [10⁻³ kg·m²]"
    title = "V_c vs wheel inertia at 2 in trail (cf. paper Fig. 15; letters: Table 1)"
    dress(ax, xlabel, axis("critical_speed"), title, dict(fontsize=8, loc="upper right"))
    return fig


def figure_threshold(sill_height: float, load: float, diameter_bounds, curves: dict) -> Figure:
    """P/L [-] vs wheel diameter d [mm, in]: exact Eq. 4A and approximate Eq. 5A, Fig. 2A.

    Drawn for the sill height h = ``sill_height`` [m] (and the paper's ½ in when h differs); the right axis
    gives P [N] for the caster ``load`` L [N]; ``diameter_bounds`` (an object with ``low``, ``high`` [m] and
    ``fixed``) are shaded and the front's diameters marked; ``curves``:
    :func:`designer.studies.curves.threshold_curves`.
    """
    h = sill_height
    fig = _new(7.5, 5.0, top=0.75, right=0.75)  # title, inch axis on top, force axis on the right
    ax = fig.add_subplot()
    d = np.asarray(curves["diameter"], float)
    d_lo, d_hi = d[0], d[-1]
    exact = f"exact, Eq. 4A (h = {shown(h, 'threshold_height', 'in')})"
    ax.plot(d * MM, curves["exact"], color="#1f77b4", lw=1.8, label=exact)
    ax.plot(d * MM, curves["approximate"], color="#1f77b4", lw=1.2, ls="--", label="approximate, Eq. 5A: 2 sqrt(h/d)")
    if curves["paper_diameter"] is not None:
        paper = np.asarray(curves["paper_diameter"], float) * MM
        ax.plot(paper, curves["paper_exact"], color="0.5", lw=1.2, label="exact, paper's h = 0.5 in (Fig. 2A)")
    b = diameter_bounds
    if b.fixed:
        ax.axvline(b.low * MM, color="#ff7f0e", lw=1.2, label=f"fixed diameter {shown(b.low, 'diameter', 'in')}")
    else:
        ax.axvspan(b.low * MM, b.high * MM, color="#ff7f0e", alpha=0.12, label="diameter bounds of the problem")
    if len(curves["front_diameters"]):
        dd, ratio = np.asarray(curves["front_diameters"], float), np.asarray(curves["front_ratio"], float)
        ax.scatter(dd * MM, ratio, color="black", s=12, zorder=4, label="front designs")
        sizes = [f"d = {shown(x, 'diameter', 'in')} ({shown(x, 'diameter', 'mm', digits=1)})" for x in dd]
        ax.hover(dd * MM, ratio, [f"{d}: P/L = {r:.4f}, P = {r * load:.2f} N" for d, r in zip(sizes, ratio)])
    ax.set_xlim(d_lo * MM, d_hi * MM)
    ax.set_ylim(0, min(3.0, float(curves["exact"][0]) * 1.05))
    _inch_x(ax, "diameter")
    sec = ax.secondary_yaxis("right", functions=(lambda r: r * load, lambda p: p / load))
    sec.set_ylabel(f"{axis('threshold_force')} at L = {load:.0f} N")
    title = "Force per unit load to climb a sill vs diameter (cf. paper Fig. 2A)"
    dress(ax, variable_axis("diameter"), axis("threshold_force_ratio"), title, dict(fontsize=8, loc="upper right"))
    return fig


# --------------------------------------------------------------------------- groove vs damper


def figure_groove_damper(
    name: str,
    required_speed: float,
    bounds: dict,
    tradeoff,
    design=None,
    plane: dict | None = None,
    robust: bool = False,
    catalog: bool = False,
) -> Figure:
    """Groove against damper for the problem's conditions.

    Left: the least turning effort F_turn [N] that reaches V_req at each
    diameter by the groove alone, the damper alone and the optimum mix
    (exact NLP, trail free: the ``tradeoff`` rows of
    :func:`designer.studies.front._tradeoff.groove_damper_tradeoff`).  Right: at the weighted optimum's T and d
    (``design``), the (B, c_f) plane with turning-effort contours [N] and iso-V_c lines [m/s] (``plane``, of
    :func:`designer.studies.curves.groove_damper_plane`); the bold line is V_c = V_req, the star the optimum.

    Parameters
    ----------
    name : the problem's name (title)
    required_speed : V_req [m/s]
    bounds : {"groove": Bound, "damping": Bound, ...} [SI] (objects with ``low``, ``high``, ``fixed``)
    tradeoff : rows with ``diameter`` [m], ``wheel``, ``effort`` {mechanism: F_turn [N] or None}, ``designs``
    design, plane : the weighted optimum and its plane, or None ("no feasible design")
    robust : the conditions carry a risk law (the legend says the bold line is the nominal Eq. 7)
    catalog : the diameters are catalog wheels (grouped bars instead of lines)
    """
    # suptitle, titles, inch axes on top; colour bar; the plane's legend under it (inside, it covered iso-V_c labels)
    fig = _new(11.5, 6.3, top=0.95, right=0.1, bottom=1.8, wspace=0.17)
    left, right = fig.subplots(1, 2, width_ratios=(1, 1.1))
    rows, bars = tradeoff, catalog or len(tradeoff) == 1
    xlabel = _tradeoff_bars(left, catalog, rows) if bars else _tradeoff_lines(left, bounds, rows)
    if any(r.effort.get(m) is None for r in rows for m in MECHANISM_STYLE):
        label = "× cannot reach V_req" if bars else "cannot reach V_req (plotted at 0)"
        left.scatter([], [], color="0.3", marker="x", label=label)
    fixed = [name for name in ("groove", "damping") if bounds[name].fixed]
    if fixed:
        note = f"{' and '.join(fixed)} fixed by the problem"
        left.text(0.02, 0.97, note, transform=left.transAxes, fontsize=8, color="0.3", va="top")
    title = f"Least turning effort reaching V_req = {required_speed:.2f} m/s"
    legend = dict(fontsize=8, loc="upper left", bbox_to_anchor=(0, 0.93))
    dress(left, xlabel, f"least {axis('turning_effort')}", title, legend)
    _groove_damper_plane(right, bounds, required_speed, design, plane, robust)
    fig.suptitle(f"{name}: groove against damper (trail free on the left, fixed on the right)", fontsize=10)
    return fig


def _tradeoff_lines(left, bounds, rows) -> str:
    """Least F_turn vs diameter, one line per mechanism (continuous diameter); returns the x label."""
    xs = np.array([r.diameter for r in rows]) * MM
    for mechanism, (colour, ls, marker) in MECHANISM_STYLE.items():
        y = np.array([r.effort.get(mechanism) if r.effort.get(mechanism) is not None else np.nan for r in rows])
        ok = np.isfinite(y)
        left.plot(xs[ok], y[ok], color=colour, ls=ls, marker=marker, ms=4, lw=1.5, label=mechanism)
        left.hover(
            xs[ok], y[ok], [_says(mechanism, r.diameter, r.effort[mechanism]) for r, good in zip(rows, ok) if good]
        )
        if np.any(~ok):
            left.scatter(xs[~ok], np.zeros((~ok).sum()), color=colour, marker="x", s=40, clip_on=False, zorder=4)
    bare = [
        r.diameter * MM
        for r in rows
        if r.designs.get("optimum mix") is not None and is_bare_fork(bounds, r.designs["optimum mix"])
    ]
    if bare and len(rows) > 1:
        step = (xs[-1] - xs[0]) / (len(xs) - 1) / 2
        left.axvspan(min(bare) - step, max(bare) + step, color="0.85", alpha=0.5, lw=0)
        note = "trail alone suffices:\nno groove, no damper"
        left.text(0.5 * (min(bare) + max(bare)), 0.5, note, ha="center", fontsize=8, color="0.3")
    _inch_x(left, "diameter")
    left.set_ylim(bottom=0)
    return variable_axis("diameter")


def _says(mechanism: str, diameter: float, effort: float) -> str:
    """What a point of the groove/damper trade-off says on hover: its diameter (inches, mm) and least F_turn."""
    sizes = f"{shown(diameter, 'diameter', 'in')} ({shown(diameter, 'diameter', 'mm')})"
    return f"{mechanism}: d = {sizes}, least F_turn {shown(effort, 'turning_effort')}"


def _tradeoff_bars(left, catalog, rows) -> str:
    """Grouped bars per wheel (catalog) or for the one fixed diameter; returns the x label."""
    x = np.arange(len(rows))
    width = 0.26
    top = max([v for r in rows for v in r.effort.values() if v is not None] or [1.0])
    for k, (mechanism, (colour, _, _)) in enumerate(MECHANISM_STYLE.items()):
        y = [r.effort.get(mechanism) for r in rows]
        pos = x + (k - 1) * width
        left.bar(
            [p for p, v in zip(pos, y) if v is not None], [v for v in y if v is not None], width * 0.95, color=colour
        )
        left.legend_patch(mechanism, colour)  # legend entry even without bars
        for p, v in zip(pos, y):
            if v is None:
                left.text(p, 0.02 * top, "×", ha="center", va="bottom", color=colour, fontsize=13, weight="bold")
            else:
                value = number(v, "turning_effort")
                left.text(p, v + 0.01 * top, value, ha="center", va="bottom", fontsize=6.5, rotation=90)
    labels = [
        (f"{r.wheel}\n" if r.wheel else "")
        + f"{shown(r.diameter, 'diameter', 'in')}\n{shown(r.diameter, 'diameter', 'mm')}"
        for r in rows
    ]
    left.set_xticks(x, labels, fontsize=8)
    left.set_ylim(0, top * 1.35)
    if len(rows) == 1:
        left.set_xlim(-1, 1)
    return "Table 1 wheel, diameter d [in, mm]" if catalog else "wheel diameter d (fixed) [in, mm]"


def _groove_damper_plane(ax, bounds, req, design, plane, robust: bool) -> None:
    if design is None or plane is None:
        ax.text(0.5, 0.5, "no feasible design", transform=ax.transAxes, ha="center")
        return
    gb, cb = bounds["groove"], bounds["damping"]
    G, C = plane["groove"], plane["damping"]
    g_hi, c_lo, c_hi = G.max(), C.min(), C.max()
    f, v = plane["turning_effort"], plane["critical_speed"]
    filled = ax.contourf(G * MM, C, f, levels=14, cmap="Greens", alpha=0.85)
    cbar = ax.figure.colorbar(filled, ax=ax, pad=0.02)
    cbar.set_label(axis("turning_effort"))
    lines = ax.contour(G * MM, C, v, levels=8, colors="0.25", linewidths=0.8)
    ax.clabel(lines, fmt="%.1f m/s", fontsize=7)
    if v.min() < req < v.max():
        ax.contour(G * MM, C, v, levels=[req], colors="black", linewidths=2.2)
    elif v.min() >= req:
        note = "V_c > V_req everywhere in this plane:\nstable without groove or damper"
        ax.text(0.5, 0.12, note, transform=ax.transAxes, ha="center", fontsize=8.5, **BOXED)
    label = f"V_c = V_req = {req:.2f} m/s (stable above/right)"
    label += "\nnominal Eq. 7; the robust optimum keeps a margin" if robust else ""
    ax.plot([], [], color="black", lw=2.2, label=label)
    ax.plot([], [], color="0.25", lw=0.8, label="iso-V_c lines [m/s]")
    width, height = max((gb.high - gb.low) * MM, 1e-9), max(cb.high - cb.low, 1e-9)
    ax.rectangle(gb.low * MM, cb.low, width, height, edgecolor="#bb5500", ls=":", lw=1.2)
    ax.plot([], [], color="#bb5500", ls=":", label="bounds")
    at = [design.groove * MM], [design.damping]
    style = dict(marker="*", s=260, facecolor="gold", edgecolor="black", zorder=5, clip_on=False)
    ax.scatter(*at, label="weighted optimum", **style)
    ax.hover(*at, [f"weighted optimum: B = {shown(design.groove, 'groove', 'in')}, c_f = {design.damping:.3f} N·m/rad"])
    ax.set_xlim(0, g_hi * MM)
    ax.set_ylim(c_lo, c_hi)
    _inch_x(ax, "groove")
    legend = dict(fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, -0.14), framealpha=0.9)
    title = f"At the optimum's T = {shown(design.trail, 'trail', 'in', digits=2)}, d = {shown(design.diameter, 'diameter', 'in', digits=2)}"
    if cb.fixed or gb.fixed:
        title += " (beyond the problem's fixed values, for context)"
    size = 10 if not (cb.fixed or gb.fixed) else 9
    dress(ax, variable_axis("groove"), variable_axis("damping"), title, legend, size, grid=False)


def is_bare_fork(bounds, design) -> bool:
    """No groove and no added damper beyond the lower bounds (``bounds``: the problem's, by variable name)."""
    return design.groove <= bounds["groove"].low + 1e-6 * INCH and design.damping <= bounds["damping"].low * (1 + 1e-6)


__all__ = ["FIGURES", "png_bytes", "save_figure"] + [f"figure_{n}" for n in FIGURES]
