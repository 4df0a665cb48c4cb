#!/usr/bin/env python3
"""Generates caustica's own textures (textures/) and meshes (scenes/meshes/).

Everything here is procedural and made for this project: released under
CC0 1.0 (see textures/PROVENANCE.md). Needs numpy and Pillow; the outputs are
committed, so building caustica does not need this script.
"""
import math
import os

import numpy as np
from PIL import Image

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TEX = os.path.join(ROOT, "textures")
MESH = os.path.join(ROOT, "scenes", "meshes")
rng = np.random.default_rng(2026)


def value_noise(h, w, cells, octaves=4):
    out = np.zeros((h, w))
    amp, total = 1.0, 0.0
    for o in range(octaves):
        c = cells * 2**o
        grid = rng.random((c + 1, c + 1))
        grid[-1, :] = grid[0, :]  # tileable
        grid[:, -1] = grid[:, 0]
        ys = np.linspace(0, c, h, endpoint=False)
        xs = np.linspace(0, c, w, endpoint=False)
        y0, x0 = ys.astype(int), xs.astype(int)
        fy, fx = ys - y0, xs - x0
        fy, fx = fy * fy * (3 - 2 * fy), fx * fx * (3 - 2 * fx)
        a = grid[y0][:, x0]
        b = grid[y0][:, x0 + 1]
        cc = grid[y0 + 1][:, x0]
        d = grid[y0 + 1][:, x0 + 1]
        top = a + (b - a) * fx[None, :]
        bot = cc + (d - cc) * fx[None, :]
        out += amp * (top + (bot - top) * fy[:, None])
        total += amp
        amp *= 0.5
    return out / total


def save(name, rgb):
    Image.fromarray(np.clip(rgb * 255 + 0.5, 0, 255).astype(np.uint8)).save(os.path.join(TEX, name))


def bark():
    h, w = 512, 256
    n = value_noise(h, w, 4)
    x = np.linspace(0, 1, w, endpoint=False)[None, :]
    ridges = 0.5 + 0.5 * np.sin(2 * math.pi * (12 * x + 3 * n))
    t = 0.55 * ridges + 0.45 * value_noise(h, w, 16)
    base = np.array([0.28, 0.18, 0.10])
    dark = np.array([0.12, 0.07, 0.04])
    save("bark.png", dark + (base - dark) * t[..., None])


def foliage():
    h, w = 256, 512
    n = value_noise(h, w, 6, 5)
    leaves = np.array([0.10, 0.45, 0.12])
    light = np.array([0.45, 0.75, 0.20])
    save("foliage.png", leaves + (light - leaves) * (n**1.5)[..., None])


def rainbow():
    h = w = 256
    u = np.linspace(0, 1, w)[None, :].repeat(h, 0)
    v = np.linspace(0, 1, h)[:, None].repeat(w, 1)
    hue = (u + 0.5 * v) % 1.0
    k = lambda n: (n + hue * 6) % 6
    f = lambda n: 1 - np.maximum(0, np.minimum(np.minimum(k(n), 4 - k(n)), 1))
    rgb = np.stack([f(5), f(3), f(1)], -1) * 0.85 + 0.1
    save("rainbow.png", rgb)


def planet():
    h, w = 256, 512
    lat = np.linspace(1, -1, h)[:, None]
    n = value_noise(h, w, 8, 4)
    bands = 0.5 + 0.5 * np.sin(lat * 14 + 2.5 * n)
    a, b = np.array([0.80, 0.62, 0.42]), np.array([0.55, 0.30, 0.18])
    rgb = b + (a - b) * bands[..., None]
    # A storm whose position tells longitude apart (checks the seam side).
    yy, xx = np.mgrid[0:h, 0:w]
    storm = np.exp(-(((xx - 0.25 * w) / 30.0) ** 2 + ((yy - 0.62 * h) / 14.0) ** 2))
    rgb = rgb * (1 - storm[..., None]) + np.array([0.75, 0.2, 0.12]) * storm[..., None]
    Image.fromarray(np.clip(rgb * 255 + 0.5, 0, 255).astype(np.uint8)).save(os.path.join(TEX, "planet.jpg"), quality=92)


def tiles():
    h = w = 256
    yy, xx = np.mgrid[0:h, 0:w] / 256.0
    grout = (np.maximum(np.abs(((xx * 2) % 1) - 0.5), np.abs(((yy * 2) % 1) - 0.5)) > 0.46)
    n = value_noise(h, w, 8)
    stone = np.array([0.72, 0.68, 0.60]) * (0.85 + 0.3 * n)[..., None]
    rgb = np.where(grout[..., None], np.array([0.25, 0.24, 0.22]), stone)
    save("tiles.png", rgb)


def vase_obj():
    """A surface of revolution with vertex normals and texture coordinates."""
    rings, seg = 48, 64
    prof = lambda t: 0.25 + 0.12 * math.sin(2.8 * t + 0.4) + 0.06 * math.sin(7 * t)
    lines = ["# caustica vase: surface of revolution, made by tools/make_assets.py (CC0)"]
    verts, norms, uvs = [], [], []
    for i in range(rings + 1):
        t = i / rings
        y, r = t, prof(t * math.pi)
        dr = (prof((t + 1e-3) * math.pi) - prof((t - 1e-3) * math.pi)) / 2e-3
        for j in range(seg + 1):
            a = 2 * math.pi * j / seg
            verts.append((r * math.cos(a), y, r * math.sin(a)))
            n = np.array([math.cos(a), -dr, math.sin(a)])
            n /= np.linalg.norm(n)
            norms.append(tuple(n))
            uvs.append((j / seg, t))
    lines += ["v %.5f %.5f %.5f" % v for v in verts]
    lines += ["vt %.5f %.5f" % t for t in uvs]
    lines += ["vn %.5f %.5f %.5f" % n for n in norms]
    lines.append("usemtl glaze")
    for i in range(rings):
        for j in range(seg):
            a = i * (seg + 1) + j + 1
            b, c, d = a + 1, a + seg + 1, a + seg + 2
            lines.append(f"f {a}/{a}/{a} {c}/{c}/{c} {d}/{d}/{d} {b}/{b}/{b}")
    with open(os.path.join(MESH, "vase.obj"), "w") as f:
        f.write("mtllib vase.mtl\n" + "\n".join(lines) + "\n")
    with open(os.path.join(MESH, "vase.mtl"), "w") as f:
        f.write("newmtl glaze\nKd 0.8 0.8 0.8\nKs 0.3 0.3 0.3\nNs 60\nmap_Kd ../../textures/rainbow.png\n")


if __name__ == "__main__":
    os.makedirs(TEX, exist_ok=True)
    os.makedirs(MESH, exist_ok=True)
    bark(); foliage(); rainbow(); planet(); tiles(); vase_obj()
