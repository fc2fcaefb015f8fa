#!/usr/bin/python3
"""Render a scene exported by `uvr export` with VTK 9's unstructured-grid volume mappers, time them, and save their
images; the images are then measured against uvr's reference by `uvr compare --image` (bench/peers/measure_images.py),
the one way uvr measures an image made elsewhere.

    uvr export MESH [scene options] --out DIR
    xvfb-run -a /usr/bin/python3 bench/peers/vtk_peers.py DIR --save IMAGES [--mappers raycast,pt,zsweep]
    (a volume: the same with VOLUME, and [--mappers gpu] [--step S])

Prints one JSON object (times); IMAGES/vtk-MAPPER.npy is each mapper's 8-bit RGB as float32 H x W x 3, row 0 on top
(colour only: uvr compares it with the reference's colour over black). Debian's python3-vtk9 renders through X, hence
xvfb-run (Mesa's llvmpipe under Xvfb).

Transfer function: uvr's extinction tau (per world unit) becomes VTK's scalar opacity a = tau u at each node, with
ScalarOpacityUnitDistance u = 1 / tau_max. All three mappers use a / u as an extinction coefficient (the ray caster's
vtkUnstructuredGridHomogeneousRayIntegrator divides its attenuation table by the unit length; projected tetrahedra
compute 1 - exp(-(a / u) L) per tetrahedron from thickness / unit distance), so a = tau u is exact, and u = 1 / tau_max
keeps a in [0, 1] using its whole range: projected tetrahedra truncate a to 8 bits per vertex and discard fragments
whose opacity is 0, so an a of 1/1000 (what an earlier u = diagonal / 1000 gave) left most of its image black.

A regular grid (`uvr export VOLUME`, scene.json "kind": "volume") goes to VTK's GPU ray caster
(vtkOpenGLGPUVolumeRayCastMapper, mapper "gpu"), the peer of uvr's ray caster: the same samples, trilinear
interpolation, post-classification, the sample distance uvr's ray caster uses (--step, default the scene's
default_step), no jittering, no automatic adjustment of the sample distance. That mapper corrects a sample's opacity as
1 - (1 - a)^(d / u), so with the unit distance u = d and a = 1 - exp(-tau d) each sample's opacity is uvr's exactly at
the nodes; the nodes are refined to 256 over the scalar range, because VTK interpolates a, not tau, linearly between
them. It stops a ray at its own opacity threshold (1 - 1/255), uvr's ray caster at 0.95 unless told otherwise.
"""
import argparse
import json
import math
import statistics
import sys
import time

import numpy as np
import vtk
from vtk.util import numpy_support

MAPPERS = {
    "raycast": vtk.vtkUnstructuredGridVolumeRayCastMapper,
    "pt": vtk.vtkProjectedTetrahedraMapper,
    "zsweep": vtk.vtkUnstructuredGridVolumeZSweepMapper,
    "gpu": vtk.vtkOpenGLGPUVolumeRayCastMapper,
}
VOLUME_MAPPERS = {"gpu"}  # the rest take tetrahedra


def load(scene_dir):
    with open(f"{scene_dir}/tf.json") as f:
        tf = json.load(f)
    with open(f"{scene_dir}/camera.json") as f:
        cam = json.load(f)
    with open(f"{scene_dir}/scene.json") as f:
        scene = json.load(f)
    if scene.get("kind") == "volume":
        reader = vtk.vtkStructuredPointsReader()
        reader.SetFileName(f"{scene_dir}/volume.vtk")
    else:
        reader = vtk.vtkUnstructuredGridReader()
        reader.SetFileName(f"{scene_dir}/mesh.vtk")
    reader.Update()
    return reader.GetOutput(), tf, cam, scene


def piecewise(nodes, s):
    """uvr's piecewise-linear function of s (constant beyond the first and last node)."""
    if s <= nodes[0][0]:
        return nodes[0][1:]
    for (s0, *v0), (s1, *v1) in zip(nodes, nodes[1:]):
        if s <= s1:
            w = (s - s0) / (s1 - s0) if s1 > s0 else 1.0
            return [a + w * (b - a) for a, b in zip(v0, v1)]
    return nodes[-1][1:]


def gpu_volume_property(tf, step, scalar_range):
    """VTK's GPU ray caster: per-sample opacity a = 1 - exp(-tau d) with unit distance d (the module's docstring)."""
    color = vtk.vtkColorTransferFunction()
    for s, r, g, b in tf["color"]:
        color.AddRGBPoint(s, r, g, b)
    opacity = vtk.vtkPiecewiseFunction()
    lo, hi = scalar_range
    nodes = sorted({s for s, _ in tf["extinction"]} | {lo + (hi - lo) * i / 255.0 for i in range(256)})
    for s in nodes:
        (tau,) = piecewise(tf["extinction"], s)
        opacity.AddPoint(s, 1.0 - math.exp(-tau * step))
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(step)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()
    return prop


def volume_property(tf, unit):
    color = vtk.vtkColorTransferFunction()
    for s, r, g, b in tf["color"]:
        color.AddRGBPoint(s, r, g, b)
    opacity = vtk.vtkPiecewiseFunction()
    for s, tau in tf["extinction"]:
        opacity.AddPoint(s, tau * unit)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(unit)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()
    return prop


def render(name, grid, prop, cam, width, height, repeat, step=None):
    mapper = MAPPERS[name]()
    mapper.SetInputData(grid)
    if name in VOLUME_MAPPERS:
        mapper.AutoAdjustSampleDistancesOff()
        mapper.SetSampleDistance(step)
        mapper.UseJitteringOff()
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    ren = vtk.vtkRenderer()
    ren.SetBackground(0, 0, 0)
    ren.AddVolume(volume)
    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(width, height)
    win.AddRenderer(ren)
    c = ren.GetActiveCamera()
    c.SetPosition(*cam["eye"])
    c.SetFocalPoint(*cam["target"])
    c.SetViewUp(*cam["up"])
    c.SetViewAngle(cam["fovy_deg"])
    if cam.get("projection") == "orthographic":
        c.ParallelProjectionOn()
        c.SetParallelScale(cam["ortho_height"] / 2.0)
    ren.ResetCameraClippingRange()
    win.Render()  # warm-up: builds the mapper's data structures
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        win.Render()
        times.append((time.perf_counter() - t0) * 1000.0)
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.SetInputBufferTypeToRGB()
    grab.ReadFrontBufferOff()
    grab.Update()
    img = grab.GetOutput()
    rgb = numpy_support.vtk_to_numpy(img.GetPointData().GetScalars()).reshape(height, width, 3)
    return statistics.median(times), times, np.flipud(rgb).astype(np.float32) / 255.0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene", help="directory written by `uvr export`")
    ap.add_argument("--mappers", help="comma-separated: raycast, pt, zsweep for a mesh (the default: all three); "
                    "gpu for a volume (the default)")
    ap.add_argument("--step", type=float, help="volume: the GPU ray caster's sample distance (default: the scene's "
                    "default_step, uvr's)")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--save", help="directory for the peers' images (vtk-MAPPER.npy, float32 RGB)")
    a = ap.parse_args()
    grid, tf, cam, scene = load(a.scene)
    is_volume = scene.get("kind") == "volume"
    mappers = (a.mappers or ("gpu" if is_volume else "raycast,pt,zsweep")).split(",")
    for name in mappers:
        if name not in MAPPERS:
            sys.exit(f"vtk_peers.py: unknown mapper '{name}' (one of {', '.join(MAPPERS)})")
        if (name in VOLUME_MAPPERS) != is_volume:
            sys.exit(f"vtk_peers.py: {a.scene} holds a {'volume' if is_volume else 'mesh'}; mapper '{name}' takes "
                     f"{'a volume' if name in VOLUME_MAPPERS else 'tetrahedra'}")
    step = a.step or scene.get("default_step")
    if is_volume:
        prop = gpu_volume_property(tf, step, scene["scalar_range"])
    else:
        tau_max = max(tau for _, tau in tf["extinction"])
        b = grid.GetBounds()
        diagonal = math.sqrt((b[1] - b[0]) ** 2 + (b[3] - b[2]) ** 2 + (b[5] - b[4]) ** 2)
        prop = volume_property(tf, 1.0 / tau_max if tau_max > 0 else diagonal)
    out = {"vtk": vtk.vtkVersion.GetVTKVersion(), "cells": grid.GetNumberOfCells(), "width": scene["width"],
           "height": scene["height"], "results": []}
    if is_volume:
        out["step"] = step
    for name in mappers:
        median_ms, times, rgb = render(name, grid, prop, cam, scene["width"], scene["height"], a.repeat, step)
        r = {"algo": f"vtk-{name}", "backend": "vtk", "frame_ms": median_ms, "frame_ms_all": times}
        if a.save:
            np.save(f"{a.save}/vtk-{name}.npy", np.ascontiguousarray(rgb, dtype=np.float32))
        out["results"].append(r)
    json.dump(out, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
