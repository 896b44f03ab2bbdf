#!/usr/bin/env python3
"""Contact sheet of a cloth rollout: a few frames from the front and the side.
Usage: plot_preview.py OUT.png [--title T] FRAME:GARMENT.obj[:BODY.obj] ...
The garment is shaded by its facing to the light (folds show), its vertices inside the body
are drawn red (an OBJ vertex line 'v x y z 1 0 0' marks one), the body grey. Orthographic,
y up, painter's algorithm per panel. Written by `pb4u simulate` (preview.png)."""
import argparse

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

GARMENT = np.array([0.30, 0.52, 0.80])
INSIDE = np.array([0.90, 0.12, 0.10])
BODY = np.array([0.78, 0.76, 0.74])
LIGHT = np.array([0.35, 0.6, 0.72])
VIEWS = [("front", 0.0), ("side", 90.0)]  # camera azimuth about y (degrees), +z faces the camera


def read_obj(path):
    verts, flags, faces = [], [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "v":
                verts.append([float(c) for c in w[1:4]])
                flags.append(len(w) >= 7 and float(w[4]) > 0.5)
            elif w[0] == "f":
                faces.append([int(c.split("/")[0]) - 1 for c in w[1:4]])
    return np.array(verts), np.array(flags, bool), np.array(faces, int)


def rotate(v, azimuth):
    a = np.radians(azimuth)
    c, s = np.cos(a), np.sin(a)
    # Camera looks along -z after rotating the scene by -azimuth about y.
    return np.stack([c * v[:, 0] - s * v[:, 2], v[:, 1], s * v[:, 0] + c * v[:, 2]], axis=1)


def shaded(v, f, base, light):
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
    lam = np.abs(n @ light)  # two-sided cloth
    return np.clip(base * (0.25 + 0.75 * lam[:, None]), 0, 1)


def panel(ax, meshes, azimuth, bounds):
    polys, colors, depth = [], [], []
    for v, f, colours, bias in meshes:
        r = rotate(v, azimuth)
        polys.append(r[f][:, :, :2])
        colors.append(colours)
        depth.append(r[f][:, :, 2].mean(axis=1) + bias)
    polys, colors, depth = np.concatenate(polys), np.concatenate(colors), np.concatenate(depth)
    order = np.argsort(depth)  # far (small z) first
    ax.add_collection(PolyCollection(polys[order], facecolors=colors[order], edgecolors="none", antialiased=False))
    (x0, x1), (y0, y1) = bounds
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.axis("off")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("png")
    ap.add_argument("--title", default="")
    ap.add_argument("frames", nargs="+", help="FRAME:GARMENT.obj[:BODY.obj]")
    a = ap.parse_args()
    frames = []
    for spec in a.frames:
        parts = spec.split(":")
        g = read_obj(parts[1])
        b = read_obj(parts[2]) if len(parts) > 2 else None
        frames.append((int(parts[0]), g, b))
    cols = len(frames)
    fig, axes = plt.subplots(len(VIEWS), cols, figsize=(2.6 * cols, 2.9 * len(VIEWS)), squeeze=False)
    for row, (view, azimuth) in enumerate(VIEWS):
        light = rotate(LIGHT[None, :], -azimuth)[0]  # the light follows the camera
        # One frame of reference per row: the garment's extent over all frames, padded.
        pts = np.concatenate([rotate(g[0], azimuth) for _, g, _ in frames])
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        pad = 0.25 * max(hi[0] - lo[0], hi[1] - lo[1])
        bounds = ((lo[0] - pad, hi[0] + pad), (lo[1] - pad, hi[1] + pad))
        for col, (frame, (gv, gin, gf), body) in enumerate(frames):
            colours = shaded(gv, gf, GARMENT, light)
            bad = gin[gf].any(axis=1)
            colours[bad] = shaded(gv, gf[bad], INSIDE, light)
            # The garment is drawn 1 cm nearer than it is: a body face larger than the cloth's
            # faces beneath them would otherwise speckle it (painter's order by face centre);
            # real penetrations are red whatever is drawn on top.
            meshes = [(gv, gf, colours, 0.01)]
            if body is not None:
                bv, _, bf = body
                meshes.append((bv, bf, shaded(bv, bf, BODY, light), 0.0))
            ax = axes[row][col]
            panel(ax, meshes, azimuth, bounds)
            inside = f", {100.0 * gin.mean():.1f}% inside" if body is not None else ""
            ax.set_title(f"frame {frame} ({view}){inside}", fontsize=8)
    if a.title:
        fig.suptitle(a.title, fontsize=9)
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)


if __name__ == "__main__":
    main()
