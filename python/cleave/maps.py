"""Fracture-mode maps from a sweep folder: which way a specimen cracks over two swept keys.

A map reads a sweep's `summary_mean.csv` (with `--seeds`) or `summary.csv`, one point per
combination of two swept keys (plain keys or ratio columns such as
`bond.tbn/fracture.cleavage_strength`), and draws the transgranular area fraction as filled
contours, with the line where half of the crack area is transgranular, and beside it the
strength:

    import cleave.maps
    m = cleave.maps.fracture_map("results/map_brazilian",
                                 x="bond.tbn/fracture.cleavage_strength", y="bond.kbn",
                                 path="map.svg")
    m["half"]  # the points (x, y) where the fraction crosses 1/2, along x at each y

Axes whose values are all positive and span more than a decade are drawn, and interpolated,
in log scale.
"""

import csv
import math
import os

FRACTION = "cracks_transgranular_area_fraction"


def read_summary(sweep):
    """The rows of a sweep folder's summary_mean.csv (else summary.csv) as dicts of strings,
    and which file they came from."""
    for name in ("summary_mean.csv", "summary.csv"):
        path = os.path.join(sweep, name)
        if os.path.exists(path):
            with open(path, newline="") as f:
                rows = [r for r in csv.DictReader(line for line in f if not line.startswith("#"))]
            return rows, name
    raise FileNotFoundError(f"{sweep}: no summary_mean.csv or summary.csv (not a sweep folder?)")


def _column(rows, name, source):
    """Column `name` as floats (NaN where empty); a mean file's NAME_mean stands for NAME."""
    keys = rows[0].keys() if rows else []
    for key in (name, name + "_mean"):
        if key in keys:
            out = []
            for r in rows:
                try:
                    out.append(float(r[key]))
                except (TypeError, ValueError):
                    out.append(math.nan)
            return out
    raise KeyError(f"{source}: no column {name!r} (columns: {', '.join(keys)}); "
                   f"a run.toml fact is added to a sweep's summary with --column FACT")


def _logscale(values):
    v = [x for x in values if math.isfinite(x)]
    return bool(v) and min(v) > 0 and max(v) / min(v) > 10


def half_line(xs, ys, fs, level=0.5, log_x=False):
    """Where f crosses `level` along x at each distinct y: a list of (x, y), x interpolated
    linearly in x (in log x when log_x) between the two points that bracket the level; the
    first crossing from the smallest x. A y at which f never crosses gives no point."""
    out = []
    for y in sorted(set(ys)):
        pts = sorted((x, f) for x, yy, f in zip(xs, ys, fs) if yy == y and math.isfinite(f))
        for (x0, f0), (x1, f1) in zip(pts, pts[1:]):
            if (f0 - level) * (f1 - level) <= 0 and f0 != f1:
                t = (level - f0) / (f1 - f0)
                if log_x:
                    x = 10 ** (math.log10(x0) + t * (math.log10(x1) - math.log10(x0)))
                else:
                    x = x0 + t * (x1 - x0)
                out.append((x, y))
                break
    return out


def fracture_map(sweep, x, y, fraction=FRACTION, strength="peak_load_N", path=None,
                 title=None):
    """Draws the fracture-mode map of a sweep folder over keys x and y: left, the
    transgranular area fraction (filled contours, the 1/2 line in black, the points run);
    right, `strength` (None: no second panel). Saves to `path` (the extension says the format)
    when given. Returns a dict: the columns read (`x`, `y`, `fraction`, `strength`), `half`
    (half_line's points) and the figure."""
    rows, source = read_summary(sweep)
    if not rows:
        raise ValueError(f"{sweep}/{source}: no rows")
    xs, ys = _column(rows, x, source), _column(rows, y, source)
    fs = _column(rows, fraction, source)
    ss = _column(rows, strength, source) if strength else None
    log_x, log_y = _logscale(xs), _logscale(ys)

    import matplotlib

    if os.environ.get("MPLBACKEND") is None:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.tri as mtri

    panels = 2 if ss is not None else 1
    fig, axes = plt.subplots(1, panels, figsize=(5.5 * panels, 4.5), squeeze=False)
    tx = [math.log10(v) if log_x else v for v in xs]
    ty = [math.log10(v) if log_y else v for v in ys]

    def draw(ax, values, label, levels, cmap):
        good = [i for i, v in enumerate(values) if math.isfinite(v)]
        px, py, pv = [tx[i] for i in good], [ty[i] for i in good], [values[i] for i in good]
        if len(set(px)) >= 2 and len(set(py)) >= 2 and len(good) >= 3:
            tri = mtri.Triangulation(px, py)
            filled = ax.tricontourf(tri, pv, levels=levels, cmap=cmap)
            fig.colorbar(filled, ax=ax, label=label)
            return tri, pv
        ax.scatter(px, py, c=pv, cmap=cmap)
        return None, pv

    ax = axes[0][0]
    tri, pv = draw(ax, fs, "transgranular area fraction", [i / 10 for i in range(11)], "coolwarm")
    if tri is not None and min(pv) < 0.5 < max(pv):
        ax.tricontour(tri, pv, levels=[0.5], colors="k", linewidths=2)
    ax.plot(tx, ty, "k.", markersize=3)
    ax.set_title("transgranular share of the crack area")
    if ss is not None:
        ax2 = axes[0][1]
        finite = [v for v in ss if math.isfinite(v)]
        label = strength
        if finite and _logscale(finite):  # strengths over decades: their logarithm
            ss_drawn = [math.log10(v) if v > 0 else math.nan for v in ss]
            finite = [v for v in ss_drawn if math.isfinite(v)]
            label = f"log10 {strength}"
        else:
            ss_drawn = ss
        if finite and max(finite) > min(finite):
            lo, hi = min(finite), max(finite)
            draw(ax2, ss_drawn, label, [lo + (hi - lo) * i / 10 for i in range(11)], "viridis")
        else:
            draw(ax2, ss_drawn, label, None, "viridis")
        ax2.plot(tx, ty, "k.", markersize=3)
        ax2.set_title(label)
    for a in axes[0]:
        a.set_xlabel(f"log10 {x}" if log_x else x)
        a.set_ylabel(f"log10 {y}" if log_y else y)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=150)
    return {
        "x": xs,
        "y": ys,
        "fraction": fs,
        "strength": ss,
        "half": half_line(xs, ys, fs, log_x=log_x),
        "figure": fig,
    }
