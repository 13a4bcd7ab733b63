"""Plots of a result folder with matplotlib (PNG, PDF, SVG: the file name says which).

Each function takes a Result (or a folder), draws on `ax` (a new figure if None) and saves
to `path` when given; it returns the axes.
"""

import math
import os


def _setup(ax):
    import matplotlib

    if ax is None:
        if os.environ.get("MPLBACKEND") is None:
            matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(6, 4.5))
    return ax


def _finish(ax, path):
    if path is not None:
        ax.figure.tight_layout()
        ax.figure.savefig(path, dpi=150)
    return ax


def _result(res):
    from .results import Result

    return res if isinstance(res, Result) else Result(res)


def load_displacement(res, ax=None, path=None):
    """Load P against load-point displacement, one line per loading stage (load_displacement.csv)."""
    res = _result(res)
    t = res.table("load_displacement")
    ax = _setup(ax)
    import numpy as np

    stages = t["stage"]
    load = t["load_N"].astype(float)
    disp = t["load_point_displacement_m"].astype(float)
    for name in dict.fromkeys(stages.tolist()):
        sel = (stages == name) & np.isfinite(load)
        if sel.sum() >= 2:
            ax.plot(disp[sel] * 1e3, load[sel], label=f"stage {name}")
    ax.set_xlabel("load-point displacement (mm)")
    ax.set_ylabel("load P (N)")
    ax.set_title(f"{res.scenario.get('name', os.path.basename(res.path))}: load-displacement")
    ax.legend()
    return _finish(ax, path)


def energy(res, ax=None, path=None):
    """Kinetic energy over time (energy.csv), log scale."""
    res = _result(res)
    t = res.table("energy")
    ax = _setup(ax)
    ax.semilogy(t["time_s"], t["kinetic_J"].clip(min=1e-300), label="kinetic")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy (J)")
    ax.legend()
    return _finish(ax, path)


_LENGTH_UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6}


def _grain_thickness_m(res):
    """[grain] t_bar (else t) of the scenario as run, in metres: a number is in the file's
    length_unit (mm by default), a string carries its own unit."""
    grain = res.scenario.get("grain", {})
    t = grain.get("t_bar", grain.get("t"))
    if t is None:
        raise ValueError(f"{res.path}: the scenario as run has no [grain] t_bar or t")
    if isinstance(t, str):
        number, unit = t.split()
        return float(number) * _LENGTH_UNITS[unit]
    return float(t) * _LENGTH_UNITS[res.scenario.get("scenario", {}).get("length_unit", "mm")]


def cracks(res, ax=None, path=None, plane="xy", surfaces=False):
    """The crack pattern: the grains (specimen.csv centres, grey), every broken bond at its
    point coloured by mode (bond_breaks.csv) and every transgranular split (splits.csv).

    surfaces=True (plane "xy", a specimen one grain thick) draws the cracks as the surfaces
    they are: each broken bond as its grain-boundary face, red, each split as its cleavage
    section, black, a segment of length area / t across its normal (t: the grains'
    thickness)."""
    res = _result(res)
    ax = _setup(ax)
    i, j = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}[plane]
    axes = "xyz"
    g = res.table("specimen")
    ax.scatter(g[f"{axes[i]}_m"] * 1e3, g[f"{axes[j]}_m"] * 1e3, s=12 if not surfaces else 3,
               c="0.85" if not surfaces else "0.7", label="grains")
    b = res.table("bond_breaks") if "bond_breaks" in res.table_names else None
    s = res.table("splits") if "splits" in res.table_names else None
    b = b if b is not None and b.size and b.dtype.names and "mode" in b.dtype.names else None
    s = s if s is not None and s.size and s.dtype.names and "x_m" in s.dtype.names else None
    if surfaces:
        if plane != "xy":
            raise ValueError("surfaces=True draws a specimen one grain thick in its xy plane")
        from matplotlib.collections import LineCollection

        t = _grain_thickness_m(res)

        def segments(table, area):
            out = []
            for row in table:
                n = math.hypot(float(row["nx"]), float(row["ny"]))
                if n == 0:
                    continue
                half = 0.5 * float(row[area]) / t * 1e3  # mm
                ux, uy = -float(row["ny"]) / n * half, float(row["nx"]) / n * half
                x, y = float(row["x_m"]) * 1e3, float(row["y_m"]) * 1e3
                out.append([(x - ux, y - uy), (x + ux, y + uy)])
            return out

        faces = segments(b, "face_area_m2") if b is not None else []
        sections = segments(s, "section_area_m2") if s is not None else []
        ax.add_collection(LineCollection(faces, colors="tab:red", linewidths=1.5,
                                         label=f"boundaries broken ({len(faces)})"))
        ax.add_collection(LineCollection(sections, colors="black", linewidths=1.5,
                                         label=f"cleavages ({len(sections)})"))
        ax.autoscale_view()
    else:
        if b is not None:
            for mode, colour in (("tension", "tab:red"), ("shear", "tab:blue"), ("bending", "tab:green"),
                                 ("torsion", "tab:purple")):
                sel = b["mode"] == mode
                if sel.any():
                    ax.scatter(b[f"{axes[i]}_m"][sel] * 1e3, b[f"{axes[j]}_m"][sel] * 1e3, s=18, c=colour,
                               marker="x", label=f"bond broken in {mode} ({int(sel.sum())})")
        if s is not None:
            ax.scatter(s[f"{axes[i]}_m"] * 1e3, s[f"{axes[j]}_m"] * 1e3, s=30, facecolors="none",
                       edgecolors="k", label=f"grain split ({s.size})")
    ax.set_aspect("equal")
    ax.set_xlabel(f"{axes[i]} (mm)")
    ax.set_ylabel(f"{axes[j]} (mm)")
    ax.set_title("crack pattern")
    ax.legend(fontsize=7, loc="upper right")
    return _finish(ax, path)


def fragment_sizes(res, ax=None, path=None):
    """The fragment size distribution (fragment_sizes.csv): cumulative mass fraction passing
    against the equivalent diameter, log d, with run.toml's Rosin-Rammler fit."""
    res = _result(res)
    t = res.table("fragment_sizes")
    ax = _setup(ax)
    import numpy as np

    d = t["diameter_m"].astype(float) * 1e3
    ax.semilogx(d, t["passing"].astype(float), "o-", ms=3, label=f"{len(d)} fragments")
    facts = res.facts
    if "fragments.rosin_rammler_d0_m" in facts:
        d0 = float(facts["fragments.rosin_rammler_d0_m"]) * 1e3
        n = float(facts["fragments.rosin_rammler_n"])
        x = np.geomspace(min(d.min(), d0) / 1.5, max(d.max(), d0) * 1.3, 200)
        ax.semilogx(x, 1 - np.exp(-((x / d0) ** n)), "--", label=f"Rosin-Rammler d0 = {d0:.3g} mm, n = {n:.3g}")
    ax.set_xlabel("equivalent diameter (mm)")
    ax.set_ylabel("cumulative mass fraction passing")
    ax.set_ylim(0, 1.02)
    ax.legend()
    return _finish(ax, path)


def weibull_fit(strengths):
    """Least-squares Weibull fit on ln(-ln(1-F)) against ln(s) with Bernard's median ranks
    F_i = (i - 0.3)/(n + 0.4), as `cleave sweep` does; returns (modulus m, scale s0)."""
    s = sorted(float(x) for x in strengths)
    n = len(s)
    if n < 2:
        raise ValueError("a Weibull fit needs at least two strengths")
    xs = [math.log(v) for v in s]
    ys = [math.log(-math.log(1.0 - (k + 1 - 0.3) / (n + 0.4))) for k in range(n)]
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    if sxx == 0.0:
        raise ValueError("a Weibull fit needs strengths that differ")
    m = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    return m, math.exp(mx - my / m)


def weibull(strengths, ax=None, path=None, unit="Pa"):
    """The Weibull plot of a set of strengths with its fitted line; returns the axes."""
    ax = _setup(ax)
    s = sorted(float(x) for x in strengths)
    n = len(s)
    m, s0 = weibull_fit(s)
    xs = [math.log(v) for v in s]
    ys = [math.log(-math.log(1.0 - (k + 1 - 0.3) / (n + 0.4))) for k in range(n)]
    ax.plot(xs, ys, "o", label="runs (median ranks)")
    lo, hi = min(xs), max(xs)
    ax.plot([lo, hi], [m * (lo - math.log(s0)), m * (hi - math.log(s0))], "-",
            label=f"fit: m = {m:.3g}, s0 = {s0:.4g} {unit}")
    ax.set_xlabel(f"ln(strength / {unit})")
    ax.set_ylabel("ln(-ln(1 - F))")
    ax.set_title("Weibull plot")
    ax.legend()
    return _finish(ax, path)
