//! Plane geometry: points, segments, polygons, clipping and exact polygon
//! integration. This module knows no physics.
//!
//! Conventions: a point is `[x, y]` (`Vec2`). Polygons are vertex lists without
//! a repeated closing vertex; a *counter-clockwise* (CCW) polygon has positive
//! signed area. A signed distance to an oriented segment is positive on its
//! left (for a CCW polygon edge: inside) unless a function says otherwise.

pub mod clip;
pub mod cut;
pub mod moments;
pub mod polygon;
pub mod region;

/// Shapes shared by the unit tests of several modules.
#[cfg(test)]
pub(crate) mod fixtures {
    use super::Vec2;

    /// L-shaped polygon, CCW, area 3: reflex corner at (1, 1), notch x > 1, y > 1.
    pub fn l_shape() -> Vec<Vec2> {
        vec![
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ]
    }
}

/// A point or vector in the plane.
pub type Vec2 = [f64; 2];

#[inline]
pub fn add(a: Vec2, b: Vec2) -> Vec2 {
    [a[0] + b[0], a[1] + b[1]]
}
#[inline]
pub fn sub(a: Vec2, b: Vec2) -> Vec2 {
    [a[0] - b[0], a[1] - b[1]]
}
#[inline]
pub fn scale(a: Vec2, s: f64) -> Vec2 {
    [a[0] * s, a[1] * s]
}
#[inline]
pub fn dot(a: Vec2, b: Vec2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
/// z-component of the cross product a × b.
#[inline]
pub fn cross(a: Vec2, b: Vec2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
/// Euclidean length. `sqrt(x² + y²)`, not `hypot`: lengths of a model (metres to
/// kilometres, displacements down to 1e-12 m) neither overflow nor underflow in the
/// squares, and glibc's correctly rounded `hypot` was 5.9% of the arch example's run
/// (contact gaps and projections call this in the narrow phase and at every residual).
#[inline]
pub fn norm(a: Vec2) -> f64 {
    (a[0] * a[0] + a[1] * a[1]).sqrt()
}
#[inline]
pub fn dist(a: Vec2, b: Vec2) -> f64 {
    norm(sub(a, b))
}
/// Linear interpolation a + t (b − a).
#[inline]
pub fn lerp(a: Vec2, b: Vec2, t: f64) -> Vec2 {
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

/// Axis-aligned bounding box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    pub min: Vec2,
    pub max: Vec2,
}

impl Aabb {
    pub fn empty() -> Self {
        Aabb {
            min: [f64::INFINITY; 2],
            max: [f64::NEG_INFINITY; 2],
        }
    }
    pub fn of_points(pts: &[Vec2]) -> Self {
        let mut b = Aabb::empty();
        for p in pts {
            b.include(*p);
        }
        b
    }
    pub fn include(&mut self, p: Vec2) {
        self.min = [self.min[0].min(p[0]), self.min[1].min(p[1])];
        self.max = [self.max[0].max(p[0]), self.max[1].max(p[1])];
    }
    pub fn merge(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: [self.min[0].min(o.min[0]), self.min[1].min(o.min[1])],
            max: [self.max[0].max(o.max[0]), self.max[1].max(o.max[1])],
        }
    }
    pub fn inflate(&self, d: f64) -> Aabb {
        Aabb {
            min: [self.min[0] - d, self.min[1] - d],
            max: [self.max[0] + d, self.max[1] + d],
        }
    }
    pub fn overlaps(&self, o: &Aabb) -> bool {
        self.min[0] <= o.max[0]
            && o.min[0] <= self.max[0]
            && self.min[1] <= o.max[1]
            && o.min[1] <= self.max[1]
    }
    pub fn diagonal(&self) -> f64 {
        dist(self.min, self.max)
    }
}
