"""A scene's box obstacles as the tests check them, computed here independently of the C++ and
of Blender: the rotation of a rotation vector in degrees (the scene format's `rotation_deg`) in
double precision, and a box's 8 world corners. Shared by tests/viewer/test_viewer.py and
blender/tests/test_addon.py (which runs in Blender's Python: plain Python only)."""
import math


def rotation_matrix(rotation_deg):
    """Rodrigues, R = I + sin(a) K + (1 - cos(a)) K^2 for the unit axis's cross-product matrix K."""
    v = [math.radians(x) for x in rotation_deg]
    a = math.sqrt(sum(x * x for x in v))
    if a == 0.0:
        return [[float(r == c) for c in range(3)] for r in range(3)]
    x, y, z = (c / a for c in v)
    k = [[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]]
    k2 = [[sum(k[r][m] * k[m][c] for m in range(3)) for c in range(3)] for r in range(3)]
    return [[(r == c) + math.sin(a) * k[r][c] + (1.0 - math.cos(a)) * k2[r][c] for c in range(3)]
            for r in range(3)]


def box_corners(box):
    """The 8 world corners of a scene box: centre + R (+-a, +-b, +-c), indexed by the signs'
    bits (bit 0: x, bit 1: y, bit 2: z)."""
    r = rotation_matrix(box.get("rotation_deg", [0, 0, 0]))
    h, c = box["half_extents"], box["center"]
    out = []
    for k in range(8):
        local = [h[a] * (1 if k >> a & 1 else -1) for a in range(3)]
        out.append([c[i] + sum(r[i][a] * local[a] for a in range(3)) for i in range(3)])
    return out
