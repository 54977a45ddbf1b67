"""The library's dislocation kernels against independent implementations from PyPI
(issue 83 item 3, issue 85 item 2; docs/halfspace.md §9).

- ``cutde`` (T. Ben Thompson; Nikkhoo & Walter's triangles in C++, full space and
  half-space, its C++ back end prebuilt in the wheel): rsf's triangles, and rsf's
  rectangles as two triangles each.
- ``dislocs`` (Z. Guo; Okada's rectangles and Nikkhoo & Walter's triangles in C,
  half-space): rsf's rectangles of any strike and dip, and its half-space triangles.

Random points (seeded): near the element (within one size of its centre), far (up to ten
sizes) at several depths, and on the free surface ``z = 0``; every slip component.

Tolerances. Both sides evaluate the same closed forms in double precision, written
differently (rsf's stress is the forward derivative of its displacement, the others
differentiate by hand), so what separates them is round-off, amplified where terms cancel:
near edges and singular half-lines, and in a half-space's far field, where the field is a
small difference of the source's, its image's and the surface terms. Each point's
difference is measured against the largest entry of the field there, or of the whole-space
field (the size of the parts that cancel) where that is larger: ``1e-9``. Against dislocs'
rectangles ``1e-8``: dislocs ports DC3D with its plain ``R + ξ``, which loses digits near
the extension of an edge (docs/halfspace.md §2); at its worst point here cutde's two
triangles side with rsf (test_rectangles_against_dislocs_and_cutde). The largest
differences measured are printed (``pytest -s``) and written in docs/halfspace.md §9.
"""

import os

import numpy as np
import pytest

import rsf

# cutde tries CUDA, then OpenCL, then its C++ back end (prebuilt in its wheel: nothing is
# compiled at import); this machine and CI have neither GPU nor OpenCL.
os.environ.setdefault("CUTDE_USE_BACKEND", "cpp")

cutde_fs = pytest.importorskip("cutde.fullspace")
cutde_hs = pytest.importorskip("cutde.halfspace")
dislocs = pytest.importorskip("dislocs")

MU = 3.2e10
NU = 0.25
TOL = 1e-9
SLIPS = np.eye(3)


def relative(a, b, parts=None):
    """Largest difference of each point's field, over the larger of its largest entries
    (and of those of ``parts``, the whole-space field, if given)."""
    a = a.reshape(len(a), -1)
    b = b.reshape(len(b), -1)
    scale = np.maximum(np.abs(a).max(axis=1), np.abs(b).max(axis=1))
    if parts is not None:
        scale = np.maximum(scale, np.abs(parts.reshape(len(parts), -1)).max(axis=1))
    return (np.abs(a - b).max(axis=1) / scale).max()


def stress6(s):
    """(n, 3, 3) stress as cutde's (xx, yy, zz, xy, xz, yz)."""
    return np.stack(
        [s[:, 0, 0], s[:, 1, 1], s[:, 2, 2], s[:, 0, 1], s[:, 0, 2], s[:, 1, 2]], axis=1
    )


def points_around(rng, centre, size, n, half_space):
    """Points near the element (0.1-1 size off its centre), far (up to 10 sizes) and, in a
    half-space, on the free surface."""
    near = centre + size * rng.uniform(-1.0, 1.0, (n, 3))
    far = centre + 10.0 * size * rng.uniform(-1.0, 1.0, (n, 3))
    pts = np.concatenate([near, far])
    if half_space:
        pts[:, 2] = -np.abs(pts[:, 2])
        surface = centre + 3.0 * size * rng.uniform(-1.0, 1.0, (n, 3))
        surface[:, 2] = 0.0
        pts = np.concatenate([pts, surface])
    return pts


TRIANGLES = [
    np.array([[0.0, 0.0, -1.0], [1.0, 0.2, -2.0], [-0.3, 1.1, -1.6]]),
    np.array([[0.0, 0.0, -0.3], [2.0, 0.0, -0.3], [1.0, 1.5, -0.3]]),  # horizontal
    np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.0, -1.0]]),  # to the surface
    np.array([[0.0, -1.0, -5.2], [0.3, 1.0, -8.0], [1.5, 0.1, -6.0]]),  # deep
]


@pytest.mark.parametrize("space", ["half", "whole"])
def test_triangles_against_cutde(space):
    rng = np.random.default_rng(83)
    worst_u = worst_s = 0.0
    for tri in TRIANGLES:
        centre = tri.mean(axis=0)
        size = np.linalg.norm(tri[1] - tri[0])
        pts = points_around(rng, centre, size, 60, space == "half")
        module = cutde_hs if space == "half" else cutde_fs
        tris = np.repeat(tri[None], len(pts), axis=0)
        for slip in SLIPS:
            u, s = rsf.triangle_deformation(pts, tri, slip, MU, NU, space=space)
            uw, sw = rsf.triangle_deformation(pts, tri, slip, MU, NU, space="whole")
            slips = np.repeat(slip[None], len(pts), axis=0)
            cu = module.disp(pts, tris, slips, NU)
            cs = cutde_fs.strain_to_stress(module.strain(pts, tris, slips, NU), MU, NU)
            worst_u = max(worst_u, relative(u, cu, uw))
            worst_s = max(worst_s, relative(stress6(s), cs, stress6(sw)))
    print(f"\ntriangles, {space}: against cutde, displacement {worst_u:.1e}, stress {worst_s:.1e}")
    assert worst_u < TOL and worst_s < TOL


@pytest.mark.parametrize("space", ["half", "whole"])
def test_stress_in_the_triangles_plane_against_cutde(space):
    """In the triangle's own plane — at its centroid (a boundary-element operator's self
    term) and at points outside it — the stress is regular (the displacement jumps across
    the triangle, so only the stress is compared)."""
    rng = np.random.default_rng(7)
    worst = 0.0
    module = cutde_hs if space == "half" else cutde_fs
    for tri in TRIANGLES:
        centre = tri.mean(axis=0)
        a, b = tri[1] - tri[0], tri[2] - tri[0]
        w = rng.uniform(-1.5, 2.5, (40, 2))
        # Barycentric coordinates away from the edges' lines (10 % at least).
        bary = np.stack([1 - w.sum(axis=1), w[:, 0], w[:, 1]], axis=1)
        w = w[np.abs(bary).min(axis=1) > 0.1]
        pts = np.concatenate([centre[None], tri[0] + w[:, :1] * a + w[:, 1:] * b])
        if space == "half":
            pts = pts[pts[:, 2] <= 0.0]
        tris = np.repeat(tri[None], len(pts), axis=0)
        for slip in SLIPS:
            _, s = rsf.triangle_deformation(pts, tri, slip, MU, NU, space=space)
            _, sw = rsf.triangle_deformation(pts, tri, slip, MU, NU, space="whole")
            slips = np.repeat(slip[None], len(pts), axis=0)
            cs = cutde_fs.strain_to_stress(module.strain(pts, tris, slips, NU), MU, NU)
            worst = max(worst, relative(stress6(s), cs, stress6(sw)))
    print(f"\ntriangles' planes, {space}: against cutde, stress {worst:.1e}")
    assert worst < TOL


def dislocs_stress(s6):
    """dislocs' (xx, xy, xz, yy, yz, zz) as cutde's order."""
    return s6[:, [0, 3, 5, 1, 2, 4]]


def upward_triangles(rng, n):
    """Random triangles whose normal points up (``n_z > 0.1``), below the surface."""
    out = []
    while len(out) < n:
        v = rng.uniform(-1.0, 1.0, (3, 3)) * [2.0, 2.0, 1.0] - [0.0, 0.0, 2.0]
        normal = np.cross(v[1] - v[0], v[2] - v[0])
        normal /= np.linalg.norm(normal)
        if normal[2] > 0.1:
            out.append(v)
    return out


def test_triangles_against_dislocs():
    """dislocs' triangles take Nikkhoo & Walter's slip components where the triangle's
    normal points up; where it does not (and for a horizontal triangle's strike) its dip
    slip has the other sign (measured: opposite displacements), so the triangles here face
    up; cutde checks every orientation."""
    rng = np.random.default_rng(85)
    worst_u = worst_s = 0.0
    for tri in [TRIANGLES[0], *upward_triangles(rng, 6)]:
        centre = tri.mean(axis=0)
        size = np.linalg.norm(tri[1] - tri[0])
        pts = points_around(rng, centre, size, 40, True)
        for slip in SLIPS:
            u, s = rsf.triangle_deformation(pts, tri, slip, MU, NU)
            uw, sw = rsf.triangle_deformation(pts, tri, slip, MU, NU, space="whole")
            model = np.concatenate([tri.ravel(), slip])[None]
            du, ds, _ = dislocs.tde(pts, model, MU, NU)
            worst_u = max(worst_u, relative(u, np.asarray(du), uw))
            worst_s = max(
                worst_s, relative(stress6(s), dislocs_stress(np.asarray(ds)), stress6(sw))
            )
    print(f"\ntriangles, half: against dislocs, displacement {worst_u:.1e}, stress {worst_s:.1e}")
    assert worst_u < TOL and worst_s < TOL


RECTANGLES = [
    # centre, strike φ (counter-clockwise from +x), dip, length, width
    ([0.0, 0.0, -3.0], 0.0, 40.0, 2.0, 1.5),
    ([1.0, -2.0, -2.0], 30.0, 90.0, 3.0, 2.0),
    ([-1.0, 0.5, -0.75], -110.0, 60.0, 1.0, 1.5),  # near the surface
    ([2.0, 1.0, -4.0], 200.0, 15.0, 2.5, 1.0),
]


def test_rectangles_against_dislocs_and_cutde():
    """dislocs' rectangle: reference point the centre of the upper edge, strike θ clockwise
    from north (+y), so θ = 90° − φ; its dip and slip as Okada's. cutde: the rectangle as
    two triangles."""
    rng = np.random.default_rng(1992)
    worst = {"dislocs": [0.0, 0.0], "cutde": [0.0, 0.0]}
    for centre, phi, dip, length, width in RECTANGLES:
        centre = np.array(centre)
        p, d = np.radians(phi), np.radians(dip)
        strike = np.array([np.cos(p), np.sin(p), 0.0])
        up_dip = np.array([-np.sin(p) * np.cos(d), np.cos(p) * np.cos(d), np.sin(d)])
        top = centre + 0.5 * width * up_dip
        corner = lambda a, b: centre + 0.5 * (a * length * strike + b * width * up_dip)  # noqa: E731
        halves = [
            np.array([corner(-1, -1), corner(1, -1), corner(1, 1)]),
            np.array([corner(-1, -1), corner(1, 1), corner(-1, 1)]),
        ]
        size = max(length, width)
        pts = points_around(rng, centre, size, 60, True)
        # Away from the diagonal the two triangles share (the pair's sum is regular there,
        # each half is not): at least 5 % of the size off the rectangle's plane.
        normal = np.cross(strike, up_dip)
        pts = pts[np.abs((pts - centre) @ normal) > 0.05 * size]
        for slip in SLIPS:
            args = (centre, phi, dip, length, width, slip, MU, NU)
            u, s = rsf.rectangle_deformation(pts, *args)
            uw, sw = rsf.rectangle_deformation(pts, *args, space="whole")
            model = np.array([[*top, length, width, 90.0 - phi, dip, *slip]])
            du, ds, _, flags = dislocs.rde(pts, model, MU, NU)
            assert (np.asarray(flags).ravel() == 0).all(), "dislocs flagged a point"
            slips = np.repeat(slip[None], len(pts), axis=0)
            cu = cs = 0.0
            for t in halves:
                tris = np.repeat(t[None], len(pts), axis=0)
                cu = cu + cutde_hs.disp(pts, tris, slips, NU)
                cs = cs + cutde_fs.strain_to_stress(cutde_hs.strain(pts, tris, slips, NU), MU, NU)
            for name, (ou, os) in [
                ("dislocs", (np.asarray(du), dislocs_stress(np.asarray(ds)))),
                ("cutde", (cu, cs)),
            ]:
                worst[name][0] = max(worst[name][0], relative(u, ou, uw))
                worst[name][1] = max(worst[name][1], relative(stress6(s), os, stress6(sw)))
    for name, (wu, ws) in worst.items():
        print(f"\nrectangles, half: against {name}, displacement {wu:.1e}, stress {ws:.1e}")
    assert max(worst["dislocs"]) < 10 * TOL
    assert max(worst["cutde"]) < TOL


def test_careless_inputs():
    tri = TRIANGLES[0]
    with pytest.raises(rsf.InvalidParameterError):
        rsf.triangle_deformation(np.zeros((2, 2)), tri, [1, 0, 0], MU, NU)
    with pytest.raises(rsf.InvalidParameterError):
        rsf.triangle_deformation(np.array([[0.0, 0.0, 1.0]]), tri, [1, 0, 0], MU, NU)
    with pytest.raises(rsf.InvalidParameterError):
        rsf.triangle_deformation(np.zeros((1, 3)), tri, [1, 0, 0], MU, NU, space="moon")
    with pytest.raises(rsf.InvalidParameterError):
        rsf.rectangle_deformation(
            np.zeros((1, 3)) - 5.0, [0, 0, -0.1], 0.0, 90.0, 1.0, 1.0, [1, 0, 0], MU, NU
        )
    # Above the surface is fine in a whole space.
    u, s = rsf.triangle_deformation(
        np.array([[0.0, 0.0, 1.0]]), tri, [1, 0, 0], MU, NU, space="whole"
    )
    assert u.shape == (1, 3) and s.shape == (1, 3, 3) and np.isfinite(s).all()
