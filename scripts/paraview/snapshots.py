"""Draw every time step of a `dem` snapshot series (snapshots.pvd) as a PNG with ParaView.

    pvbatch scripts/paraview/snapshots.py RUN/snapshots.pvd [OUT_PREFIX] [COLOR]

Discs are drawn as "Point Gaussian" splats of their true radius (the `radius` point array,
metres), coloured by COLOR: `speed` (default, |velocity| in m/s), or any point array of the
snapshot (`grain`, `group`, `material`, ...). Walls and the tool (the `walls-*.vtp` part of
the series) are drawn as grey lines. One image per time step: OUT_PREFIX-<k>.png (default:
beside the .pvd, `frame-<k>.png`). In the ParaView GUI the same is: open snapshots.pvd,
Representation "Point Gaussian", untick "Scale by array" off / Gaussian radius = 1, tick
"Scale by array" with `radius`, ShaderPreset "Plain circle".
"""
import os
import sys

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetAnimationScene, GetColorTransferFunction,
                             GetDisplayProperties, GetScalarBar, PVDReader, Calculator, ExtractBlock, Hide,
                             ResetCamera, SaveScreenshot, Show, UpdatePipeline)

if len(sys.argv) < 2:
    sys.exit(__doc__)
pvd = os.path.abspath(sys.argv[1])
if not os.path.isfile(pvd):
    sys.exit(f"snapshots.py: {pvd}: no such file")
prefix = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(pvd), "frame")
color = sys.argv[3] if len(sys.argv) > 3 else "speed"

reader = PVDReader(FileName=pvd)
reader.UpdatePipelineInformation()
times = list(reader.TimestepValues) if hasattr(reader.TimestepValues, "__len__") else [reader.TimestepValues]
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [1200, 700]
view.Background = [1, 1, 1]
view.OrientationAxesVisibility = 0
try:
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass

# Part 0: the discs (points with radius, velocity, ...); part 1: walls and tool (lines).
discs = ExtractBlock(Input=reader)
walls = ExtractBlock(Input=reader)
try:
    discs.Selectors = ["/Root/Block0"] if hasattr(discs, "Selectors") else None
    walls.Selectors = ["/Root/Block1"]
except Exception:
    discs.BlockIndices = [1]
    walls.BlockIndices = [2]
source = discs
if color == "speed":
    source = Calculator(Input=discs)
    source.ResultArrayName = "speed"
    source.Function = "mag(velocity)"
d = Show(source, view)
d.SetRepresentationType("Point Gaussian")
d.ScaleByArray = 1
d.SetScaleArray = ["POINTS", "radius"]
# The radius array itself is the splat radius (no transfer function in between).
d.UseScaleFunction = 0
d.GaussianRadius = 1.0
d.ShaderPreset = "Plain circle"
ColorBy(d, ("POINTS", color))
d.SetScalarBarVisibility(view, True)
w = Show(walls, view)
w.SetRepresentationType("Wireframe")
w.AmbientColor = w.DiffuseColor = [0.35, 0.35, 0.35]
w.LineWidth = 4.0
w.ColorArrayName = ["POINTS", ""]

view.InteractionMode = "2D"
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()
for k, t in enumerate(times):
    view.ViewTime = t
    UpdatePipeline(time=t, proxy=source)
    if k == 0:
        ResetCamera(view)
    lut = GetColorTransferFunction(color)
    if color == "speed":
        lut.RescaleTransferFunction(0.0, max(source.PointData["speed"].GetRange()[1], 1e-12))
    bar = GetScalarBar(lut, view)
    bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
    bar.Title = "speed (m/s)" if color == "speed" else color
    bar.ComponentTitle = ""
    out = f"{prefix}-{k}.png"
    SaveScreenshot(out, view, ImageResolution=[1200, 700])
    print(f"{out}: t = {t:.6g} s")
