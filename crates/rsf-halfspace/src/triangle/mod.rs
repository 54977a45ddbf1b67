//! Triangular dislocations: the displacement and its gradient of a triangle of constant
//! slip (strike, dip, tensile) in a full space or a half-space, by the artefact-free
//! solution of Nikkhoo & Walter (2015).
//!
//! Source: M. Nikkhoo and T. R. Walter, "Triangular dislocation: an analytical,
//! artefact-free solution", Geophys. J. Int. 201, 1119–1141 (2015). The triangle is the
//! superposition of three angular dislocations, one at each vertex, in one of two
//! configurations chosen by where the observation point projects onto the triangle's
//! plane, so that no point meets the angular dislocations' singular half-lines (§3 of
//! the paper; `angular.rs` holds Appendices A and B); plus the Burgers function, the
//! solid angle the triangle subtends. In a half-space (§4): the triangle, its image in
//! the surface `z = 0`, and the harmonic function of an angular-dislocation pair on each
//! side. The gradient is the exact derivative of the displacement, computed with it by
//! forward differentiation (`crate::dual`), instead of the paper's strain formulas.
//!
//! # Conventions (docs/halfspace.md §6)
//! Coordinates as Okada's: `z` up, the half-space `z ≤ 0`. The triangle's frame (the
//! paper's TDCS) from its vertices `P1, P2, P3` in order: the normal
//! `n = (P2 − P1) × (P3 − P1)/|…|`, the strike `e_s = e_z × n/|…|` (`e_s = ±e_y` for a
//! horizontal triangle: `n_z e_y`), the up-dip `e_d = n × e_s`. The slip `[s, d, t]` is
//! the motion of the side `n` points into relative to the other side, along `e_s`, `e_d`
//! and `n`: for a triangle whose frame is a rectangle's Okada frame, the same as Okada's
//! `[U1, U2, U3]` (checked by two triangles against one rectangle, `tests/suite/triangle.rs`).

mod angular;

use crate::dual::{Dual3, Real};
use crate::error::Error;
use crate::okada::Deformation;
use crate::space::Space;

/// A triangle in space (m): three vertices, not on a line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Triangle {
    vertices: [[f64; 3]; 3],
    /// `[normal, strike, up dip]` (the paper's TDCS axes, in that order).
    axes: [[f64; 3]; 3],
    /// The triangle in its own frame, relative to `P2`.
    local: Local,
    /// The image in `z = 0` (vertices mirrored): its axes and own frame.
    image: ([[f64; 3]; 3], [[f64; 3]; 3], Local),
}

/// A triangle in its own frame (TDCS, origin `P2`): what the angular dislocations need.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Local {
    /// `(y, z)` of `P1`, `P2 = 0` and `P3` in the TDCS.
    p: [[f64; 2]; 3],
    /// Unit vectors `e12`, `e13`, `e23` (`(y, z)` components).
    e12: [f64; 2],
    e13: [f64; 2],
    e23: [f64; 2],
    /// The angles at `P1`, `P2`, `P3` (rad).
    angles: [f64; 3],
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: &[f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// The TDCS axes `[n, e_s, e_d]` of the triangle `v`; `image` flips a horizontal
/// triangle's strike (the paper's image of a horizontal triangle below the surface).
fn axes_of(v: &[[f64; 3]; 3], image: bool) -> [[f64; 3]; 3] {
    let n = cross(&sub(&v[1], &v[0]), &sub(&v[2], &v[0]));
    let n = n.map(|x| x / norm(&n));
    let mut s = cross(&[0.0, 0.0, 1.0], &n);
    if norm(&s) == 0.0 {
        s = [0.0, n[2], 0.0];
        if image {
            s = s.map(|x| -x);
        }
    }
    let s = s.map(|x| x / norm(&s));
    [n, s, cross(&n, &s)]
}

impl Local {
    fn new(v: &[[f64; 3]; 3], axes: &[[f64; 3]; 3]) -> Self {
        let to_local = |p: &[f64; 3]| {
            let d = sub(p, &v[1]);
            [dot(&axes[1], &d), dot(&axes[2], &d)]
        };
        let p = [to_local(&v[0]), [0.0, 0.0], to_local(&v[2])];
        let unit = |a: [f64; 2], b: [f64; 2]| {
            let d = [b[0] - a[0], b[1] - a[1]];
            let l = d[0].hypot(d[1]);
            [d[0] / l, d[1] / l]
        };
        let (e12, e13, e23) = (unit(p[0], p[1]), unit(p[0], p[2]), unit(p[1], p[2]));
        let d2 = |a: [f64; 2], b: [f64; 2]| (a[0] * b[0] + a[1] * b[1]).clamp(-1.0, 1.0);
        let angles = [
            d2(e12, e13).acos(),
            (-d2(e12, e23)).acos(),
            d2(e23, e13).acos(),
        ];
        Self {
            p,
            e12,
            e13,
            e23,
            angles,
        }
    }

    /// The paper's "trimodefinder": `1` (configuration I), `−1` (configuration II) or `0`
    /// (on an edge of the triangle, in its plane) for the point `(x, y, z)` of the TDCS.
    fn mode(&self, x: f64, y: f64, z: f64) -> i8 {
        let [p1, p2, p3] = self.p;
        let den = (p2[1] - p3[1]) * (p1[0] - p3[0]) + (p3[0] - p2[0]) * (p1[1] - p3[1]);
        let a = ((p2[1] - p3[1]) * (y - p3[0]) + (p3[0] - p2[0]) * (z - p3[1])) / den;
        let b = ((p3[1] - p1[1]) * (y - p3[0]) + (p1[0] - p3[0]) * (z - p3[1])) / den;
        let c = 1.0 - a - b;
        let mut mode = 1;
        if (a <= 0.0 && b > c && c > a)
            || (b <= 0.0 && c > a && a > b)
            || (c <= 0.0 && a > b && b > c)
        {
            mode = -1;
        }
        let on_edge = (a == 0.0 && b >= 0.0 && c >= 0.0)
            || (a >= 0.0 && b == 0.0 && c >= 0.0)
            || (a >= 0.0 && b >= 0.0 && c == 0.0);
        if on_edge && x == 0.0 {
            mode = 0;
        }
        mode
    }

    /// The displacement (TDCS) of the triangle in a full space at the TDCS point
    /// `(x, y, z)` for the unit slips `b = (t, s, d)` (the TDCS's `x`, `y`, `z`):
    /// `out[b][i]` ("TDdispFS" in the TDCS). `None` on an edge.
    fn full_space<T: Real>(&self, x: T, y: T, z: T, nu: f64) -> Option<[[T; 3]; 3]> {
        let mode = self.mode(x.value(), y.value(), z.value());
        if mode == 0 {
            return None;
        }
        let s = if mode == 1 { 1.0 } else { -1.0 };
        let neg = |e: [f64; 2]| [-e[0], -e[1]];
        let scale = |e: [f64; 2], k: f64| [k * e[0], k * e[1]];
        let sides = [
            (self.angles[0], self.p[0], scale(neg(self.e13), s)),
            (self.angles[1], self.p[1], scale(self.e12, s)),
            (self.angles[2], self.p[2], scale(self.e23, s)),
        ];
        let mut out = [[T::cst(0.0); 3]; 3];
        for (alpha, vertex, side) in sides {
            let g = setup([x, y, z], alpha, vertex, side, nu);
            for b in 0..3 {
                for i in 0..3 {
                    out[b][i] = out[b][i] + g[b][i];
                }
            }
        }
        // The Burgers function: the solid angle of the triangle seen from the point
        // (Van Oosterom & Strackee), −Ω/(4π), added to the slip's own component.
        let [p1, _, p3] = self.p;
        let va = [-x, T::cst(p1[0]) - y, T::cst(p1[1]) - z];
        let vb = [-x, -y, -z];
        let vc = [-x, T::cst(p3[0]) - y, T::cst(p3[1]) - z];
        let d = |u: &[T; 3], v: &[T; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
        let (na, nb, nc) = (d(&va, &va).sqrt(), d(&vb, &vb).sqrt(), d(&vc, &vc).sqrt());
        let triple = va[0] * (vb[1] * vc[2] - vb[2] * vc[1])
            - va[1] * (vb[0] * vc[2] - vb[2] * vc[0])
            + va[2] * (vb[0] * vc[1] - vb[1] * vc[0]);
        let den = na * nb * nc + d(&va, &vb) * nc + d(&va, &vc) * nb + d(&vb, &vc) * na;
        let fi = triple.atan2(den) * (-2.0 / (4.0 * std::f64::consts::PI));
        for b in 0..3 {
            out[b][b] = out[b][b] + fi;
        }
        Some(out)
    }
}

/// One angular dislocation of the triangle ("TDSetupD"): at the vertex `(y, z)` of the
/// TDCS, angle `alpha`, its side `(y, z)` components; the response in the TDCS to the
/// unit slips `(t, s, d)`.
fn setup<T: Real>(
    [x, y, z]: [T; 3],
    alpha: f64,
    vertex: [f64; 2],
    side: [f64; 2],
    nu: f64,
) -> [[T; 3]; 3] {
    let [s2, s3] = side;
    let (dy, dz) = (y - vertex[0], z - vertex[1]);
    let y1 = dy * s3 - dz * s2;
    let z1 = dy * s2 + dz * s3;
    let g = angular::full_space(x, y1, z1, alpha - std::f64::consts::PI, nu);
    // Back to the TDCS: (v, w) = Aᵀ (v₀, w₀).
    let back = |r: [T; 3]| [r[0], r[1] * s3 + r[2] * s2, r[2] * s3 - r[1] * s2];
    let comb = |p: f64, q: f64| [0, 1, 2].map(|i| g[1][i] * p + g[2][i] * q);
    // TDCS slip s (y) is (s₃, s₂) in the ADCS's (y, z); slip d (z) is (−s₂, s₃).
    [back(g[0]), back(comb(s3, s2)), back(comb(-s2, s3))]
}

/// The harmonic function of the angular-dislocation pair on the side `pa → pb` of a
/// triangle below the surface ("AngSetupFSC"), at the point `x` (global), for the unit
/// global slips: `out[m][i]`, component `i` of the displacement for unit slip along the
/// global axis `m`. Zero for a vertical side.
fn side_correction<T: Real>(x: [T; 3], pa: [f64; 3], pb: [f64; 3], nu: f64) -> [[T; 3]; 3] {
    let side = sub(&pb, &pa);
    let len = norm(&side);
    let beta = (-side[2] / len).clamp(-1.0, 1.0).acos();
    let zero = [[T::cst(0.0); 3]; 3];
    if beta.abs() < f64::EPSILON || (std::f64::consts::PI - beta).abs() < f64::EPSILON {
        return zero;
    }
    let h = side[0].hypot(side[1]);
    let e1 = [side[0] / h, side[1] / h, 0.0];
    // The ADCS axes e1, e2 = e3 × e1, e3 = −e_z: a symmetric orthogonal matrix.
    let a = [[e1[0], e1[1], 0.0], [e1[1], -e1[0], 0.0], [0.0, 0.0, -1.0]];
    let rel = [x[0] - pa[0], x[1] - pa[1], x[2] - pa[2]];
    let ya: [T; 3] = [0, 1, 2].map(|i| rel[0] * a[i][0] + rel[1] * a[i][1] + rel[2] * a[i][2]);
    let ab = [0, 1, 2].map(|i| dot(&a[i], &side));
    let yb = [ya[0] - ab[0], ya[1] - ab[1], ya[2] - ab[2]];
    let angle = if beta * ya[0].value() >= 0.0 {
        beta - std::f64::consts::PI
    } else {
        beta
    };
    let va = angular::surface_correction(ya, angle, nu, -pa[2]);
    let vb = angular::surface_correction(yb, angle, nu, -pb[2]);
    let mut out = zero;
    for m in 0..3 {
        // Unit global slip along m is row m of the symmetric A in the ADCS.
        let v: [T; 3] = [0, 1, 2]
            .map(|i| (0..3).fold(T::cst(0.0), |acc, b| acc + (vb[b][i] - va[b][i]) * a[m][b]));
        out[m] = [0, 1, 2].map(|i| v[0] * a[i][0] + v[1] * a[i][1] + v[2] * a[i][2]);
    }
    out
}

impl Triangle {
    /// The triangle `P1, P2, P3` (m).
    ///
    /// # Errors
    /// [`Error::Parameter`] for a non-finite coordinate or vertices on a line (an area
    /// below `10⁻¹²` of its longest side squared).
    pub fn new(vertices: [[f64; 3]; 3]) -> Result<Self, Error> {
        for v in &vertices {
            for &c in v {
                if !c.is_finite() {
                    return Err(Error::Parameter {
                        name: "vertex",
                        value: c,
                        expected: "finite",
                    });
                }
            }
        }
        let n = cross(
            &sub(&vertices[1], &vertices[0]),
            &sub(&vertices[2], &vertices[0]),
        );
        let longest = [(0, 1), (1, 2), (2, 0)]
            .map(|(i, j)| norm(&sub(&vertices[i], &vertices[j])))
            .into_iter()
            .fold(0.0, f64::max);
        let area2 = norm(&n);
        if !(area2 > 1e-12 * longest * longest && area2.is_finite()) {
            return Err(Error::Parameter {
                name: "triangle area",
                value: 0.5 * area2,
                expected: "> 0: three vertices not on a line",
            });
        }
        let axes = axes_of(&vertices, false);
        let image = vertices.map(|v| [v[0], v[1], -v[2]]);
        let image_axes = axes_of(&image, true);
        Ok(Self {
            vertices,
            axes,
            local: Local::new(&vertices, &axes),
            image: (image, image_axes, Local::new(&image, &image_axes)),
        })
    }

    /// The vertices (m).
    pub fn vertices(&self) -> &[[f64; 3]; 3] {
        &self.vertices
    }

    /// The centroid (m).
    pub fn centroid(&self) -> [f64; 3] {
        let v = &self.vertices;
        [0, 1, 2].map(|i| (v[0][i] + v[1][i] + v[2][i]) / 3.0)
    }

    /// The area (m²).
    pub fn area(&self) -> f64 {
        let v = &self.vertices;
        0.5 * norm(&cross(&sub(&v[1], &v[0]), &sub(&v[2], &v[0])))
    }

    /// Unit vectors `[strike, up dip, normal]` (see the [module docs](self)); the slip's
    /// components are along them.
    pub fn frame(&self) -> [[f64; 3]; 3] {
        [self.axes[1], self.axes[2], self.axes[0]]
    }

    /// The deformations at `point` (m) due to unit strike slip, unit dip slip and unit
    /// opening, in that order, for Poisson's ratio `nu`, in a full space or a half-space
    /// `z ≤ 0` (see the [module docs](self) for the conventions).
    ///
    /// # Errors
    /// [`Error::Parameter`] for a non-finite point or `nu` outside `(−1, ½)`;
    /// [`Error::AboveSurface`] (half-space) for `z > 0`; [`Error::SourceAboveSurface`]
    /// (half-space) for a vertex above `z = 0`; [`Error::OnEdge`] on an edge of the
    /// triangle (or of its image); [`Error::NonFinite`] if the result overflows.
    pub fn unit_responses(
        &self,
        nu: f64,
        point: [f64; 3],
        space: Space,
    ) -> Result<[Deformation; 3], Error> {
        self.check(nu, point, space)?;
        let var = |j: usize| Dual3::variable(point[j], j);
        let g = self
            .response([var(0), var(1), var(2)], nu, space)
            .ok_or(Error::OnEdge { point })?;
        // TDCS order (t, s, d) → (strike, dip, tensile).
        let out = [1, 2, 0].map(|b| Deformation {
            u: g[b].map(|c| c.v),
            grad: g[b].map(|c| c.d),
        });
        if out.iter().all(|d| {
            d.u.iter()
                .chain(d.grad.iter().flatten())
                .all(|x| x.is_finite())
        }) {
            Ok(out)
        } else {
            Err(Error::NonFinite {
                what: "deformation",
            })
        }
    }

    /// The displacement at `point` (m) due to the slip `[strike, dip, tensile]`, without
    /// the gradient (a third of the work of [`unit_responses`](Self::unit_responses)).
    ///
    /// # Errors
    /// As [`unit_responses`](Self::unit_responses); [`Error::Parameter`] for a
    /// non-finite slip.
    pub fn displacement(
        &self,
        nu: f64,
        point: [f64; 3],
        slip: [f64; 3],
        space: Space,
    ) -> Result<[f64; 3], Error> {
        if let Some(&s) = slip.iter().find(|s| !s.is_finite()) {
            return Err(Error::Parameter {
                name: "slip",
                value: s,
                expected: "finite",
            });
        }
        self.check(nu, point, space)?;
        let g = self
            .response(point, nu, space)
            .ok_or(Error::OnEdge { point })?;
        let b = [slip[2], slip[0], slip[1]];
        let u = [0, 1, 2].map(|i| (0..3).map(|k| b[k] * g[k][i]).sum::<f64>());
        if u.iter().all(|x| x.is_finite()) {
            Ok(u)
        } else {
            Err(Error::NonFinite {
                what: "displacement",
            })
        }
    }

    fn check(&self, nu: f64, point: [f64; 3], space: Space) -> Result<(), Error> {
        if !(nu > -1.0 && nu < 0.5) {
            return Err(Error::Parameter {
                name: "nu",
                value: nu,
                expected: "in (-1, 0.5)",
            });
        }
        for (name, value) in [("x", point[0]), ("y", point[1]), ("z", point[2])] {
            if !value.is_finite() {
                return Err(Error::Parameter {
                    name,
                    value,
                    expected: "finite",
                });
            }
        }
        if space == Space::HalfSpace {
            if point[2] > 0.0 {
                return Err(Error::AboveSurface { z: point[2] });
            }
            let z_top = self.vertices.iter().map(|v| v[2]).fold(f64::MIN, f64::max);
            if z_top > 0.0 {
                return Err(Error::SourceAboveSurface { z_top });
            }
        }
        Ok(())
    }

    /// The displacement (global) for the unit TDCS slips `(t, s, d)`: `out[b][i]`.
    fn response<T: Real>(&self, x: [T; 3], nu: f64, space: Space) -> Option<[[T; 3]; 3]> {
        let mut out = full_space_global(&self.vertices, &self.axes, &self.local, x, nu)?;
        if space == Space::WholeSpace {
            return Some(out);
        }
        if self.vertices.iter().all(|v| v[2] == 0.0) {
            // On the surface: no displacement (the paper's convention).
            return Some([[T::cst(0.0); 3]; 3]);
        }
        // The image: the vertices mirrored in z = 0, the same slip in its own frame.
        let (image, image_axes, image_local) = &self.image;
        let g = full_space_global(image, image_axes, image_local, x, nu)?;
        // The harmonic function, for the slip in global components.
        let mut h = [[T::cst(0.0); 3]; 3];
        for (pa, pb) in [(0, 1), (1, 2), (2, 0)] {
            let c = side_correction(x, self.vertices[pa], self.vertices[pb], nu);
            for m in 0..3 {
                for i in 0..3 {
                    h[m][i] = h[m][i] + c[m][i];
                }
            }
        }
        for b in 0..3 {
            let axis = self.axes[b];
            for i in 0..3 {
                let hb = h[0][i] * axis[0] + h[1][i] * axis[1] + h[2][i] * axis[2];
                out[b][i] = out[b][i] + g[b][i] + hb;
            }
        }
        Some(out)
    }
}

/// [`Local::full_space`] at a global point, the result in global components.
fn full_space_global<T: Real>(
    v: &[[f64; 3]; 3],
    axes: &[[f64; 3]; 3],
    local: &Local,
    x: [T; 3],
    nu: f64,
) -> Option<[[T; 3]; 3]> {
    let rel = [x[0] - v[1][0], x[1] - v[1][1], x[2] - v[1][2]];
    let [lx, ly, lz] = axes.map(|a| rel[0] * a[0] + rel[1] * a[1] + rel[2] * a[2]);
    let g = local.full_space(lx, ly, lz, nu)?;
    Some(g.map(|r| [0, 1, 2].map(|i| r[0] * axes[0][i] + r[1] * axes[1][i] + r[2] * axes[2][i])))
}
