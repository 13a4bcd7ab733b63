"""Show a cleave result folder in ParaView: the grains (semi-transparent, coloured by grain),
the walls, and the crack network (broken bonds and split sections, coloured by mode).

Run with ParaView's Python (Debian: apt-get install paraview python3-paraview):

  pvpython tools/paraview_cracks.py RESULT_DIR                  # an interactive window
  pvbatch tools/paraview_cracks.py RESULT_DIR --screenshot cracks.png
  pvbatch tools/paraview_cracks.py RESULT_DIR --state cracks.pvsm   # then: paraview --state=cracks.pvsm

Without a display, prefix pvbatch with `xvfb-run -a` (Debian's ParaView renders through X).
The frame shown is the last one unless --time says otherwise.
"""

import argparse
import os
import sys

from paraview import simple as pv

# The cracks' "mode" field (io/paraview_frames.hpp).
MODES = [(1, "bond: tension", (0.85, 0.10, 0.10)), (2, "bond: shear", (0.95, 0.60, 0.05)),
         (3, "bond: bending", (0.60, 0.20, 0.75)), (4, "bond: torsion", (0.10, 0.55, 0.85)),
         (5, "grain split", (0.05, 0.05, 0.05))]


def arguments(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("result", help="a cleave result folder (with bodies.pvd)")
    p.add_argument("--screenshot", metavar="FILE.png", help="write a picture and exit")
    p.add_argument("--state", metavar="FILE.pvsm", help="write a ParaView state file and exit")
    p.add_argument("--time", type=float, help="the time to show, s (default: the last frame)")
    p.add_argument("--size", type=int, nargs=2, default=[1600, 1000], metavar=("W", "H"))
    p.add_argument("--grain-opacity", type=float, default=0.25)
    p.add_argument("--grain-colors", action="store_true", help="colour the grains by grain_id")
    p.add_argument("--elevation", type=float, default=25.0,
                   help="degrees the camera is raised from the specimen's thinnest axis")
    return p.parse_args(argv)


def open_series(folder, name):
    path = os.path.join(folder, name + ".pvd")
    if not os.path.exists(path):
        return None
    reader = pv.PVDReader(registrationName=name, FileName=os.path.abspath(path))
    reader.UpdatePipelineInformation()
    return reader


def main(argv):
    args = arguments(argv)
    folder = args.result
    bodies = open_series(folder, "bodies")
    if bodies is None:
        sys.exit(f"{folder}: no bodies.pvd (only [dynamics] runs write frames)")
    walls = open_series(folder, "walls")
    cracks = open_series(folder, "cracks")

    times = list(bodies.TimestepValues) if bodies.TimestepValues else [0.0]
    time = times[-1] if args.time is None else min(times, key=lambda t: abs(t - args.time))
    scene = pv.GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.AnimationTime = time

    view = pv.GetActiveViewOrCreate("RenderView")
    view.ViewSize = args.size
    view.Background = [1.0, 1.0, 1.0]
    try:  # ParaView 5.10+: a single background colour needs the palette off
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.OrientationAxesVisibility = 1
    view.DepthPeeling = 1

    shown = pv.Show(bodies, view)
    if args.grain_colors:
        pv.ColorBy(shown, ("CELLS", "grain_id"))
        pv.GetColorTransferFunction("grain_id").ApplyPreset("Pastel1 (ColorBrewer)", True)
        shown.SetScalarBarVisibility(view, False)
    else:
        shown.ColorArrayName = ["POINTS", ""]
        shown.AmbientColor = shown.DiffuseColor = [0.78, 0.76, 0.70]
    shown.Opacity = args.grain_opacity

    if walls is not None:
        w = pv.Show(walls, view)
        w.ColorArrayName = ["POINTS", ""]
        w.AmbientColor = w.DiffuseColor = [0.55, 0.55, 0.6]
        w.Opacity = 0.35

    if cracks is not None:
        c = pv.Show(cracks, view)
        pv.ColorBy(c, ("CELLS", "mode"))
        lut = pv.GetColorTransferFunction("mode")
        lut.InterpretValuesAsCategories = 1
        lut.Annotations = [str(v) for m in MODES for v in (m[0], m[1])]
        lut.IndexedColors = [x for m in MODES for x in m[2]]
        c.SetScalarBarVisibility(view, True)
        bar = pv.GetScalarBar(lut, view)
        bar.Title = "crack"
        bar.ComponentTitle = ""
        bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
        # Cracks seen edge-on (a disc viewed along its axis) still show as lines.
        edges = pv.FeatureEdges(registrationName="crack_edges", Input=cracks)
        edges.BoundaryEdges = 1
        edges.FeatureEdges = 0
        edges.NonManifoldEdges = 0
        edges.ManifoldEdges = 0
        e = pv.Show(edges, view)
        pv.ColorBy(e, ("CELLS", "mode"))
        e.LineWidth = 2.5
        # What the picture shows, counted from the frame's own cracks.
        data = pv.servermanager.Fetch(cracks)
        kinds = data.GetCellData().GetArray("kind") if data.GetNumberOfCells() else None
        counts = [0, 0, 0]
        for i in range(kinds.GetNumberOfTuples() if kinds else 0):
            counts[int(kinds.GetValue(i))] += 1
        name = os.path.basename(os.path.normpath(folder))
        title = pv.Text(registrationName="title", Text=(
            f"{name}, t = {time:.4g} s: {counts[1]} broken bonds (coloured by mode), "
            f"{counts[2]} grain split sections (black)"))
        t = pv.Show(title, view)
        t.WindowLocation = "Upper Center"
        t.FontSize = 22
        t.Color = [0.0, 0.0, 0.0]

    # Look along the specimen's thinnest axis, raised by --elevation so that cracks through
    # the thickness show their faces.
    b = bodies.GetDataInformation().GetBounds()
    extent = [b[1] - b[0], b[3] - b[2], b[5] - b[4]]
    thin = extent.index(min(extent))
    centre = [(b[2 * k] + b[2 * k + 1]) / 2 for k in range(3)]
    up = [0.0, 0.0, 0.0]
    up[(thin + 2) % 3] = 1.0
    direction = [0.0, 0.0, 0.0]
    direction[thin] = 1.0
    view.CameraFocalPoint = centre
    view.CameraPosition = [centre[k] + direction[k] for k in range(3)]
    view.CameraViewUp = up
    view.ResetCamera()
    camera = pv.GetActiveCamera()
    camera.Elevation(args.elevation)
    view.ResetCamera()
    camera.Dolly(1.15)
    view.ViewTime = time
    pv.Render(view)

    if args.state:
        pv.SaveState(args.state)
        print(f"wrote {args.state} (t = {time:.6g} s): paraview --state={args.state}")
    if args.screenshot:
        pv.SaveScreenshot(args.screenshot, view, ImageResolution=args.size,
                          TransparentBackground=0)
        print(f"wrote {args.screenshot} (t = {time:.6g} s)")
    if not args.state and not args.screenshot:
        pv.Interact(view)


if __name__ == "__main__":
    main(sys.argv[1:])
