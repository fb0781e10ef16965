#!/usr/bin/env python3
"""Writes cases/grain.stl: an irregular, sub-angular sand grain (python3 + numpy only).

    python3 scripts/make_grain_stl.py [--output cases/grain.stl] [--seed 20240501] [--levels 3]

(run from the repository's root)

The grain is reproducible: the same seed gives the same bytes. It stands for a natural medium-sand
or volcanic-ash particle: a rounded body with bumps and shallow dents, a few flat facets (the
broken faces that make a grain "sub-angular"), and the proportions of natural sand.

How it is made (and why the result is a valid, watertight, outward-oriented surface):

1. An icosphere: the regular icosahedron with each triangle cut into four, `levels` times
   (level 3: 642 vertices, 1280 triangles), every vertex pushed onto the unit sphere. Its triangles
   are counterclockwise seen from outside.
2. A radial map: each vertex u goes to r(u) u with r > 0, where log r is a sum of smooth random
   lobes (bumps and dents), and then r is capped by a few random planes (a vertex beyond a plane
   slides along its ray onto it, which leaves flat facets). Because every vertex stays on its own
   ray from the origin, each triangle stays inside the cone its three rays span; the cones of
   different triangles only meet along shared rays, so the surface cannot intersect itself, and
   det(r1 u1, r2 u2, r3 u3) = r1 r2 r3 det(u1, u2, u3) > 0 keeps every triangle facing outwards.
3. A stretch diag(1, e, e f) with natural-sand proportions (a positive diagonal map keeps the
   orientation and the star shape), then the centroid moved to the origin, the principal axes of
   inertia turned onto the file axes (x the longest, z the shortest dimension, det +1), and the
   size scaled so that the volume-equivalent diameter is exactly 1 file unit. A case gives the
   size with `particle.scale` (metres per file unit), e.g. scale = 5.0e-4 for d_eq = 0.5 mm.
4. Written as binary STL (float32). The volume, area and inertia printed at the end are computed
   from the float32 vertices actually written, by the divergence theorem (signed tetrahedra from
   the origin; Mirtich 1996, J. Graphics Tools 1(2), 31-50, doi:10.1080/10867651.1996.10487458), so
   they can be compared with what `settle shape --mesh` reads back.

Proportions: the stretch's elongation 0.80 and flatness 0.78 become I/L = 0.739 and S/I = 0.716
after the bumps and cuts (seed 20240501; sphericity 0.896, Corey shape factor 0.615): a sand-like
grain within the range of the natural and volcanic particles behind the settling law of Bagheri and
Bonadonna 2016 (Powder Technol. 301, 526-544, doi:10.1016/j.powtec.2016.06.015), flatness and
elongation both between 0.4 and 1.

Needs numpy (Debian: python3-numpy; a pyenv or conda python3 may lack it: /usr/bin/python3 has it).
"""
import argparse
import struct

import numpy as np

ELONGATION = 0.80  # I / L of the stretch
FLATNESS = 0.78  # S / I of the stretch
LOBES = 16  # smooth bumps and dents
LOBE_AMPLITUDE = 0.22  # largest |log r| change of one lobe
LOBE_SHARPNESS = (3.0, 10.0)  # kappa range of exp(kappa (u.c - 1)): angular width about 1/sqrt(kappa)
FACETS = 7  # flat cuts
FACET_DEPTH = (0.72, 0.88)  # a cut sits at this fraction of the radius in its direction


def icosphere(levels):
    """Vertices on the unit sphere and counterclockwise (outward) triangles."""
    t = (1.0 + 5.0**0.5) / 2.0
    vertices = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    points = [np.array(v, dtype=float) / np.linalg.norm(v) for v in vertices]
    for _ in range(levels):
        midpoint_index = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoint_index:
                m = points[a] + points[b]
                points.append(m / np.linalg.norm(m))
                midpoint_index[key] = len(points) - 1
            return midpoint_index[key]

        refined = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = refined
    return np.array(points), np.array(faces, dtype=np.int64)


def random_unit_vectors(rng, n):
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def radial_profile(directions, rng):
    """r(u) > 0: smooth random lobes, then flat facets (the grain's broken faces)."""
    centres = random_unit_vectors(rng, LOBES)
    amplitudes = rng.uniform(-LOBE_AMPLITUDE, LOBE_AMPLITUDE, LOBES)
    sharpness = rng.uniform(*LOBE_SHARPNESS, LOBES)
    log_r = np.zeros(len(directions))
    for c, a, k in zip(centres, amplitudes, sharpness):
        log_r += a * np.exp(k * (directions @ c - 1.0))
    r = np.exp(log_r)
    for n in random_unit_vectors(rng, FACETS):
        along = directions @ n
        nearest = np.argmax(along)  # the vertex closest to the cut's direction sets its depth
        depth = rng.uniform(*FACET_DEPTH) * r[nearest] * along[nearest]
        beyond = along * r > depth
        r[beyond] = depth / along[beyond]  # slide along the ray onto the plane u.n = depth
    return r


def signed_volume_terms(p, faces):
    a, b, c = p[faces[:, 0]], p[faces[:, 1]], p[faces[:, 2]]
    return a, b, c, np.einsum("ij,ij->i", a, np.cross(b, c))  # 6 x signed tetrahedron volumes


def moments(p, faces):
    """Volume, centroid and second moment S = int (x - c)(x - c)^T dV of the closed surface."""
    a, b, c, det = signed_volume_terms(p, faces)
    volume = det.sum() / 6.0
    centroid = (det[:, None] * (a + b + c)).sum(axis=0) / 24.0 / volume
    # Tetrahedron (0, a, b, c): int x x^T dV = det/120 (a a^T + b b^T + c c^T + s s^T), s = a + b + c.
    s = a + b + c
    second = sum(np.einsum("i,ij,ik->jk", det, q, q) for q in (a, b, c, s)) / 120.0
    return volume, centroid, second - volume * np.outer(centroid, centroid)


def surface_area(p, faces):
    a, b, c = p[faces[:, 0]], p[faces[:, 1]], p[faces[:, 2]]
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum()


def to_principal_axes(p, faces):
    """Centroid to the origin; principal axes onto x (longest), y, z (shortest); det +1."""
    _, centroid, second = moments(p, faces)
    p = p - centroid
    eigenvalues, axes = np.linalg.eigh(second)  # ascending second moments: shortest extent first
    axes = axes[:, ::-1]  # x along the largest second moment (the longest dimension)
    axes *= np.sign(axes[np.argmax(np.abs(axes), axis=0), range(3)])  # canonical signs
    if np.linalg.det(axes) < 0.0:
        axes[:, 2] *= -1.0
    return p @ axes


def check_closed_and_outward(faces, volume):
    """Every directed edge once, its reverse once: watertight, manifold, consistently oriented."""
    directed = {}
    for f, (a, b, c) in enumerate(faces):
        for edge in ((a, b), (b, c), (c, a)):
            if edge in directed:
                raise SystemExit(f"edge {edge} traversed twice in the same direction")
            directed[edge] = f
    for a, b in directed:
        if (b, a) not in directed:
            raise SystemExit(f"edge ({a}, {b}) has one triangle only")
    if volume <= 0.0:
        raise SystemExit("the surface is oriented inwards")


def write_binary_stl(path, p, faces, header):
    out = bytearray(header.encode("ascii").ljust(80, b" ")[:80])
    out += struct.pack("<I", len(faces))
    for a, b, c in faces:
        n = np.cross(p[b] - p[a], p[c] - p[a])
        n /= np.linalg.norm(n)
        out += struct.pack("<3f", *n)
        for v in (a, b, c):
            out += struct.pack("<3f", *p[v])
        out += struct.pack("<H", 0)
    with open(path, "wb") as f:
        f.write(bytes(out))


def widths_along_axes(p):
    return p.max(axis=0) - p.min(axis=0)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--output", default="cases/grain.stl")
    parser.add_argument("--seed", type=int, default=20240501)
    parser.add_argument("--levels", type=int, default=3, help="icosphere subdivisions (3: 1280 triangles)")
    args = parser.parse_args()

    rng = np.random.default_rng(args.seed)
    directions, faces = icosphere(args.levels)
    p = directions * radial_profile(directions, rng)[:, None]
    p = p * np.array([1.0, ELONGATION, ELONGATION * FLATNESS])
    p = to_principal_axes(p, faces)
    volume, _, _ = moments(p, faces)
    p *= (np.pi / 6.0 / volume) ** (1.0 / 3.0)  # d_eq = (6 V / pi)^(1/3) = 1 file unit

    p32 = p.astype(np.float32)  # what the file holds; every figure below is of these vertices
    q = p32.astype(np.float64)
    volume, centroid, second = moments(q, faces)
    check_closed_and_outward([tuple(f) for f in faces], volume)
    area = surface_area(q, faces)
    d_eq = (6.0 * volume / np.pi) ** (1.0 / 3.0)
    inertia = np.trace(second) * np.eye(3) - second  # unit density
    lengths = widths_along_axes(q)
    header = f"settle grain: scripts/make_grain_stl.py --seed {args.seed} --levels {args.levels}; d_eq = 1"
    write_binary_stl(args.output, q, faces, header)

    print(f"wrote {args.output}: {len(faces)} triangles, {len(directions)} vertices (binary STL, float32)")
    print(f"volume {volume:.9f}  surface_area {area:.9f}  equivalent_diameter {d_eq:.9f}")
    print(f"centroid {centroid[0]:.3e} {centroid[1]:.3e} {centroid[2]:.3e}")
    print("principal moments (unit density) " + " ".join(f"{m:.9e}" for m in np.sort(np.linalg.eigvalsh(inertia))))
    print(f"sphericity {np.pi * d_eq**2 / area:.4f}")
    # The principal axes lie on the file axes, so these widths are the principal extents L, I, S.
    print("widths along x, y, z " + " ".join(f"{w:.9f}" for w in lengths))
    print(f"elongation I/L {lengths[1] / lengths[0]:.4f}  flatness S/I {lengths[2] / lengths[1]:.4f}  "
          f"Corey S/sqrt(L I) {lengths[2] / np.sqrt(lengths[0] * lengths[1]):.4f}")


if __name__ == "__main__":
    main()
