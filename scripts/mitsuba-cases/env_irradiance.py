#!/usr/bin/env python3
"""Exact expected value of plane-diffuse-envmap.pbrt under restir-lab's definition of an equirect
map (nearest texel, row j covers theta in [j, j+1] pi / H, +z of the map = the plane's normal):
0.5 / pi * sum_ij L_ij (2 pi / W) (sin^2 theta_j+1 - sin^2 theta_j) / 2 over the upper rows,
in luminance. Usage: env_irradiance.py MAP.exr [ALBEDO]"""
import sys
import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")
img = np.maximum(np.array(mi.Bitmap(sys.argv[1]), dtype=np.float64)[..., :3], 0)
albedo = float(sys.argv[2]) if len(sys.argv) > 2 else 0.5
h, w = img.shape[:2]
lum = img @ np.array([0.2126, 0.7152, 0.0722])
edges = np.arange(h + 1) / h * np.pi
band = 0.5 * (np.sin(np.minimum(edges[1:], np.pi / 2))**2 - np.sin(np.minimum(edges[:-1], np.pi / 2))**2)
E = np.sum(lum.sum(1) * (2 * np.pi / w) * band)
print(f"{sys.argv[1]}: {w}x{h}, expected pixel luminance {albedo / np.pi * E:.6g}")
