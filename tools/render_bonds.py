#!/usr/bin/python3
"""Renders the last frame of a bonded run: grains coloured by von Mises stress (grey
scale), intact bonds as thin dark lines, broken bonds as thick red lines. Needs Debian's
python3-vtk9; run headless through xvfb-run:

  xvfb-run -a /usr/bin/python3 tools/render_bonds.py RESULT_DIR OUT.png [HEIGHT_PX]
"""
import glob
import os
import sys

import vtk


def last(folder, stem):
    files = sorted(glob.glob(os.path.join(folder, "frames", stem + "_*.vtp")))
    if not files:
        sys.exit(f"no {stem}_*.vtp frames in {folder}/frames")
    return files[-1]


def reader(path):
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    return r


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    folder, out = sys.argv[1], sys.argv[2]
    ren = vtk.vtkRenderer()
    ren.SetBackground(1, 1, 1)

    bodies = reader(last(folder, "bodies"))
    data = bodies.GetOutput()
    data.GetCellData().SetActiveScalars("von_mises_Pa")
    lo, hi = data.GetCellData().GetArray("von_mises_Pa").GetRange()
    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.6, 0.0)
    lut.SetRange(lo, hi if hi > lo else lo + 1)
    lut.Build()
    m = vtk.vtkPolyDataMapper()
    m.SetInputConnection(bodies.GetOutputPort())
    m.SetScalarModeToUseCellData()
    m.SetLookupTable(lut)
    m.SetScalarRange(lut.GetRange())
    a = vtk.vtkActor()
    a.SetMapper(m)
    a.GetProperty().SetOpacity(0.55)
    ren.AddActor(a)

    bonds = reader(last(folder, "bonds"))
    for intact, colour, width in ((1, (0.15, 0.15, 0.15), 1.5), (0, (0.85, 0.0, 0.0), 5.0)):
        t = vtk.vtkThreshold()
        t.SetInputConnection(bonds.GetOutputPort())
        t.SetInputArrayToProcess(0, 0, 0, vtk.vtkDataObject.FIELD_ASSOCIATION_CELLS, "intact")
        t.SetLowerThreshold(intact - 0.5)
        t.SetUpperThreshold(intact + 0.5)
        g = vtk.vtkGeometryFilter()
        g.SetInputConnection(t.GetOutputPort())
        bm = vtk.vtkPolyDataMapper()
        bm.SetInputConnection(g.GetOutputPort())
        bm.ScalarVisibilityOff()
        ba = vtk.vtkActor()
        ba.SetMapper(bm)
        ba.GetProperty().SetColor(*colour)
        ba.GetProperty().SetLineWidth(width)
        ba.SetPosition(0, 0, 0.003)  # in front of the grains (z up to 5 mm)
        ren.AddActor(ba)

    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.AddRenderer(ren)
    win.SetSize(1200, int(sys.argv[3]) if len(sys.argv) > 3 else 420)
    cam = ren.GetActiveCamera()
    cam.ParallelProjectionOn()
    ren.ResetCamera()
    # Fit the specimen's xy box to the picture.
    x0, x1, y0, y1, _, _ = data.GetBounds()
    w, h = win.GetSize()
    cam.SetParallelScale(1.08 * max((y1 - y0) / 2, (x1 - x0) / 2 * h / w))
    win.Render()
    shot = vtk.vtkWindowToImageFilter()
    shot.SetInput(win)
    w = vtk.vtkPNGWriter()
    w.SetFileName(out)
    w.SetInputConnection(shot.GetOutputPort())
    w.Write()


if __name__ == "__main__":
    main()
