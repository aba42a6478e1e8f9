"""``nmm.plot``: a model as cut, or a frame of a run, as a matplotlib Figure.

The data come from the library (``Model.blocks()``; ``Result.frame(k)``, read by its VTK
reader) and the labels and units from the ones ``nmm plot`` uses; only the drawing is
matplotlib's. matplotlib is imported when a picture is drawn, not with ``nmm``.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Optional, Union

from . import _nmm

# the colours of `nmm plot` (crates/nmm/src/picture.rs)
_JOINTS = [(31, 119, 180), (255, 127, 14), (44, 160, 44), (148, 103, 189), (140, 86, 75),
           (227, 119, 194), (188, 189, 34), (23, 190, 207), (0, 0, 0)]
_FILLS = [(174, 199, 232), (255, 187, 120), (152, 223, 138), (197, 176, 213),
          (196, 156, 148), (219, 219, 141)]
_GREY = (150, 150, 150)
_STATES = [("contact open", _GREY), ("contact stick", (44, 160, 44)), ("contact slide", (214, 39, 40))]


def _rgb(c, alpha=1.0):
    return (c[0] / 255, c[1] / 255, c[2] / 255, alpha)


def _pyplot():
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ImportError(
            "nmm.plot needs matplotlib: pip install matplotlib (or pip install 'nmm[plot]')"
        ) from e
    return plt


def plot(
    what: Any,
    out: Union[str, os.PathLike, None] = None,
    frame: Optional[int] = None,
    field: str = "u",
    *,
    time: Optional[float] = None,
    ax: Any = None,
    contacts: bool = True,
    names: bool = True,
    cmap: str = "viridis",
    vmin: Optional[float] = None,
    vmax: Optional[float] = None,
    figsize: Optional[tuple] = None,
    dpi: int = 150,
    title: Optional[str] = None,
):
    """Draw a model as cut or a frame of a run; returns the matplotlib Figure.

    ``what``: an :class:`nmm.Model` (its blocks as cut: fixed blocks grey, the others in
    pastel colours, joint faces coloured by joint set or joint, names at the centroids),
    an :class:`nmm.Result` or :class:`nmm.Frame` (the deformed manifold elements coloured by
    ``field`` with a colour bar and its unit, block outlines, the step's contacts grey open,
    green stick, red slide; step and time in the title), or a path: a model file or a run
    folder. ``frame``: the frame of a run (from 0, negative from the end; default the last),
    or ``time``: the frame nearest to it (s). ``field``: ``u`` (|u|), ``ux``, ``uy``,
    ``sxx``, ``syy`` or ``sxy``, as ``nmm plot --field``. ``vmin``/``vmax``: the colour
    range in m or Pa (default the frame's). ``ax``: draw into these axes (else a new
    figure). ``out``: also save the figure there (any format matplotlib writes, ``dpi``);
    the figure is then closed in pyplot (still usable, not shown by ``plt.show()``).
    """
    from . import Model, Result
    from ._frames import Frame, Frames

    plt = _pyplot()
    if isinstance(what, (str, os.PathLike)):
        path = Path(what)
        what = Frames(path) if path.is_dir() else Model.load(os.fspath(path))
    if ax is None:
        fig, ax = plt.subplots(figsize=figsize or (10, 6))
    else:
        fig = ax.figure
    if isinstance(what, Model):
        if frame is not None or time is not None:
            raise ValueError("frame and time pick a frame of a run: give a Result, not a Model")
        _draw_model(ax, what, names, title)
    else:
        if isinstance(what, Result):
            what = what.frames
        if isinstance(what, Frames):
            if frame is not None and time is not None:
                raise ValueError("give frame or time, not both")
            what = what.nearest(time) if time is not None else what[-1 if frame is None else frame]
        elif not isinstance(what, Frame):
            raise TypeError(
                f"nmm.plot: expected an nmm.Model, nmm.Result, nmm.Frame or a path, got {type(what).__name__}"
            )
        elif frame is not None or time is not None:
            raise ValueError("frame and time pick a frame of a run: a Frame is one already")
        _draw_frame(fig, ax, what, field, contacts, cmap, (vmin, vmax), title)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    if out is not None:
        fig.savefig(os.fspath(out), dpi=dpi, bbox_inches="tight")
        plt.close(fig)
    return fig


def _centroid(p):
    import numpy as np

    x, y = p[:, 0], p[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    c = x * yn - xn * y
    a = c.sum()
    if abs(a) < 1e-300:
        return p.mean(axis=0)
    return np.array([((x + xn) * c).sum(), ((y + yn) * c).sum()]) / (3 * a)


def _draw_model(ax, model, names: bool, title: Optional[str]):
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.lines import Line2D

    df = model.blocks()
    fills, free = [], 0
    for fixed in df["fixed"]:
        if fixed:
            fills.append(_rgb(_GREY, 0.5))
        else:
            fills.append(_rgb(_FILLS[free % len(_FILLS)], 0.8))
            free += 1
    ax.add_collection(
        PolyCollection(list(df["polygon"]), facecolors=fills, edgecolors="black", linewidths=0.8)
    )
    segments, colours, used = [], [], {}
    for poly, joints in zip(df["polygon"], df["joints"]):
        n = len(poly)
        for k, j in enumerate(joints):
            if j >= 0:
                segments.append([poly[k], poly[(k + 1) % n]])
                colours.append(_rgb(_JOINTS[j % len(_JOINTS)]))
                used[int(j)] = True
    handles = []
    if segments:
        ax.add_collection(LineCollection(segments, colors=colours, linewidths=1.6))
        joint_names = df.attrs.get("joints", [])
        for j in sorted(used):
            label = f"joint {joint_names[j]}" if j < len(joint_names) else f"joint {j}"
            handles.append(Line2D([], [], color=_rgb(_JOINTS[j % len(_JOINTS)]), lw=2, label=label))
    if df["fixed"].any():
        handles.append(Line2D([], [], color=_rgb(_GREY), lw=6, label="fixed block"))
    if names:
        size = 6 if len(df) > 60 else 9
        for name, poly in zip(df["name"], df["polygon"]):
            x, y = _centroid(poly)
            ax.text(x, y, name, ha="center", va="center", fontsize=size)
    if handles:
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    ax.autoscale_view()
    ax.set_title(title if title is not None else f"{model.source}: {len(df)} blocks as cut")


def _draw_frame(fig, ax, fr, field: str, contacts: bool, cmap: str, limits, title):
    import numpy as np
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.lines import Line2D

    values = fr.field(field)
    finite = values[np.isfinite(values)]
    lo = limits[0] if limits[0] is not None else (finite.min() if finite.size else 0.0)
    hi = limits[1] if limits[1] is not None else (finite.max() if finite.size else 1.0)
    label, factor, unit = _nmm.field_unit(field, max(abs(lo), abs(hi)))
    if hi <= lo:  # a constant field: the middle of the colour map, as `nmm plot`
        pad = abs(lo) * 0.1 or factor
        lo, hi = lo - pad, hi + pad
    cells = PolyCollection(fr.polygons, cmap=cmap, edgecolors="face", linewidths=0.2)
    cells.set_array(values / factor)
    cells.set_clim(lo / factor, hi / factor)
    ax.add_collection(cells)
    rings = [np.vstack([p, p[:1]]) for loops in fr.blocks["outlines"] for p in loops if len(p)]
    ax.add_collection(LineCollection(rings, colors="black", linewidths=0.7))
    handles = []
    if contacts and len(fr.contacts):
        states = fr.contacts["state"].clip(0, 2).to_numpy()
        size = min(9.0, max(1.0, 3000.0 / len(states)))  # smaller markers where there are many
        for k, (name, colour) in enumerate(_STATES):
            on = states == k
            if on.any():
                ax.scatter(fr.contacts["x"][on], fr.contacts["y"][on], s=size,
                           color=_rgb(colour), zorder=3, linewidths=0)
                handles.append(Line2D([], [], marker="o", ls="", color=_rgb(colour), label=name))
    if handles:
        ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3,
                  fontsize=8)
    fig.colorbar(cells, ax=ax, label=f"{label} ({unit})")
    ax.autoscale_view()
    step = f"step {fr.step}, " if fr.step is not None else ""
    ax.set_title(title if title is not None else f"{fr.out} — {step}t = {fr.time} s — {label}")
