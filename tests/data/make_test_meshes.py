#!/usr/bin/env python3
"""Writes the small STL files used by tests/body (run from this folder: python3 make_test_meshes.py).

Independent of settle's own STL writer on purpose, so the reader is tested against files it
did not produce. Every file is tiny; the broken ones each carry exactly one defect.
"""
import struct

CUBE_VERTS = [(x, y, z) for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)]


def v(i):
    return CUBE_VERTS[i]


# Unit cube [0,1]^3 (centroid at (0.5, 0.5, 0.5), off the origin on purpose). Vertex index =
# 4x + 2y + z. Each face as two triangles, counterclockwise seen from outside.
CUBE = [
    (0, 1, 3), (0, 3, 2),  # x = 0, normal -x
    (4, 6, 7), (4, 7, 5),  # x = 1, normal +x
    (0, 4, 5), (0, 5, 1),  # y = 0, normal -y
    (2, 3, 7), (2, 7, 6),  # y = 1, normal +y
    (0, 2, 6), (0, 6, 4),  # z = 0, normal -z
    (1, 5, 7), (1, 7, 3),  # z = 1, normal +z
]
CUBE_TRIS = [(v(a), v(b), v(c)) for a, b, c in CUBE]

# Right-angled tetrahedron with legs 2, 3, 4: volume 4, centroid (0.5, 0.75, 1).
T0, T1, T2, T3 = (0.0, 0.0, 0.0), (2.0, 0.0, 0.0), (0.0, 3.0, 0.0), (0.0, 0.0, 4.0)
TET_TRIS = [(T0, T2, T1), (T0, T1, T3), (T0, T3, T2), (T1, T2, T3)]


def normal(tri):
    (ax, ay, az), (bx, by, bz), (cx, cy, cz) = tri
    ux, uy, uz = bx - ax, by - ay, bz - az
    wx, wy, wz = cx - ax, cy - ay, cz - az
    n = (uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx)
    length = sum(c * c for c in n) ** 0.5 or 1.0
    return tuple(c / length for c in n)


def ascii(tris, name="test", normals=True):
    lines = [f"solid {name}"]
    for tri in tris:
        n = normal(tri) if normals else (0.0, 0.0, 0.0)
        lines.append("  facet normal {} {} {}".format(*n))
        lines.append("    outer loop")
        for p in tri:
            lines.append("      vertex {!r} {!r} {!r}".format(*p))
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append(f"endsolid {name}")
    return "\n".join(lines) + "\n"


def binary(tris, header=b"binary test mesh", count=None):
    out = bytearray(header.ljust(80, b" ")[:80])
    out += struct.pack("<I", len(tris) if count is None else count)
    for tri in tris:
        out += struct.pack("<3f", *normal(tri))
        for p in tri:
            out += struct.pack("<3f", *p)
        out += struct.pack("<H", 0)
    return bytes(out)


def reversed_tri(tri):
    return (tri[0], tri[2], tri[1])


def write(name, data):
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(name, mode) as f:
        f.write(data)


write("cube_ascii.stl", ascii(CUBE_TRIS, "cube", normals=False))  # zero normals: must be ignored
# A binary file whose header starts with "solid", as some CAD exporters write them.
write("cube_binary.stl", binary(CUBE_TRIS, header=b"solid cube written as binary"))
write("tetrahedron_ascii.stl", ascii(TET_TRIS, "tetrahedron"))
write("tetrahedron_binary.stl", binary(TET_TRIS))
# Two disjoint tetrahedra in two 'solid' blocks of one file.
shifted = [tuple((x + 5.0, y, z) for x, y, z in tri) for tri in TET_TRIS]
write("two_solids_ascii.stl", ascii(TET_TRIS, "first") + ascii(shifted, "second"))

# Broken files: one defect each.
write("open_box.stl", ascii(CUBE_TRIS[:-2], "open"))                      # a face missing
write("flipped_facet.stl", ascii(CUBE_TRIS[:-1] + [reversed_tri(CUBE_TRIS[-1])], "flipped"))
write("inverted_cube.stl", ascii([reversed_tri(t) for t in CUBE_TRIS], "inverted"))  # all inward
write("nonmanifold.stl", ascii(CUBE_TRIS + [CUBE_TRIS[0]], "duplicate"))  # a facet twice
write("empty.stl", "")
write("no_facets.stl", "solid nothing\nendsolid nothing\n")
write("nan_ascii.stl", ascii(CUBE_TRIS, "nan").replace("vertex 1.0 1.0 1.0", "vertex nan 1.0 1.0", 1))
nan_bin = bytearray(binary(CUBE_TRIS))
nan_bin[84 + 12:84 + 16] = struct.pack("<f", float("nan"))
write("nan_binary.stl", bytes(nan_bin))
write("truncated_binary.stl", binary(CUBE_TRIS)[: 84 + 50 * 5])          # header says 12
write("count_too_large_binary.stl", binary(CUBE_TRIS, count=0xFFFFFFFF))  # 4 billion announced
write("quad_facet.stl", ascii(CUBE_TRIS, "quad").replace(
    "    endloop", "      vertex 0.5 0.5 0.5\n    endloop", 1))            # 4-vertex loop
write("garbage.stl", "this is not a mesh at all\n")
# Closed and consistently oriented but flat: one triangle and its reverse enclose nothing.
flat = ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0))
write("flat_sheet.stl", ascii([flat, reversed_tri(flat)], "flat"))
