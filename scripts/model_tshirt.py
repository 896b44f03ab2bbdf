#!/usr/bin/env python3
"""Models the t-shirt in data/meshes/tshirt.obj: a front and a back panel cut from the
same T-shaped lattice and stitched along the side, underarm, sleeve and shoulder seams.
The openings (neck, waist, two cuffs) stay open: four boundary loops, one component.
Metres, y up, the front faces +z. Usage: scripts/model_tshirt.py OUT.obj"""
import math
import sys

H = 0.025            # lattice cell (m)
A, B = 10, 28        # half torso width and torso height (cells)
S, C = 8, 8          # sleeve length and sleeve width (cells)
N, D = 3, 3          # neck half width and depth (cells)
DEPTH = 0.09         # half thickness of the torso (m)


def in_region(x, y):  # cell (x, y) with lower-left corner at lattice point (x, y)
    torso = 0 <= x < 2 * A and 0 <= y < B
    sleeve = (-S <= x < 0 or 2 * A <= x < 2 * A + S) and B - C <= y < B
    neck = A - N <= x < A + N and B - D <= y < B
    return (torso or sleeve) and not neck


def main(out):
    cells = {(x, y) for x in range(-S, 2 * A + S) for y in range(B) if in_region(x, y)}
    # Boundary edges of the region, then which of them are openings (not stitched).
    edge_cells = {}
    for (x, y) in cells:
        for e in (((x, y), (x + 1, y)), ((x + 1, y), (x + 1, y + 1)),
                  ((x, y + 1), (x + 1, y + 1)), ((x, y), (x, y + 1))):
            edge_cells.setdefault(e, []).append((x, y))
    boundary = [e for e, c in edge_cells.items() if len(c) == 1]

    def opening(e):
        (x0, y0), (x1, y1) = e
        if y0 == y1 == 0:
            return True                                  # waist
        if x0 == x1 and x0 in (-S, 2 * A + S):
            return True                                  # cuffs
        # The cell across the edge: a neck cell makes the edge part of the neck opening.
        across = [(x0, y0 - 1), (x0, y0)] if y0 == y1 else [(x0 - 1, y0), (x0, y0)]
        ox, oy = [c for c in across if c not in cells][0]
        return A - N <= ox < A + N and B - D <= oy < B

    seam_points = set()
    for e in boundary:
        if not opening(e):
            seam_points.update(e)
    points = sorted({p for c in cells for p in ((c[0], c[1]), (c[0] + 1, c[1]),
                                                 (c[0], c[1] + 1), (c[0] + 1, c[1] + 1))})

    def dist_to_seam(p):
        return min(math.hypot(p[0] - q[0], p[1] - q[1]) for q in seam_points)

    verts, index = [], {}
    for side in (+1, -1):
        for p in points:
            if p in seam_points and side == -1:
                index[(p, side)] = index[(p, +1)]
                continue
            t = min(1.0, dist_to_seam(p) * H / DEPTH)
            z = side * DEPTH * math.sqrt(t * (2 - t))  # round profile, 0 on the seams
            if p[0] < 0 or p[0] > 2 * A:               # sleeves are thinner tubes
                z *= 0.5
            index[(p, side)] = len(verts)
            verts.append(((p[0] - A) * H, p[1] * H + 0.8, z))
    faces = []
    for (x, y) in sorted(cells):
        for side in (+1, -1):
            a, b = index[((x, y), side)], index[((x + 1, y), side)]
            c, d = index[((x, y + 1), side)], index[((x + 1, y + 1), side)]
            tris = [(a, b, d), (a, d, c)] if (x + y) % 2 else [(a, b, c), (b, d, c)]
            for t in tris:  # counter-clockwise seen from outside: +z front, -z back
                faces.append(t if side == 1 else (t[0], t[2], t[1]))
    with open(out, "w") as f:
        f.write("# pb4u t-shirt: two stitched panels, openings neck, waist, two cuffs\n")
        for v in verts:
            f.write("v %.6f %.6f %.6f\n" % v)
        for t in faces:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))
    print("%s: %d vertices, %d faces" % (out, len(verts), len(faces)))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "tshirt.obj")
