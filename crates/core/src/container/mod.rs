//! Containers: a box of side lengths `L[d]` whose axes are periodic or bounded by flat hard
//! walls, optionally with a curved wall given as an exact signed distance.
//!
//! Coordinates run over `[0, L_k)` on every axis. Curved walls are centred in the box.
//! Each wall is reported by [`Container::for_each_wall`] as a signed distance (positive inside)
//! and an outward unit normal, which is all that energies, contact analysis and constraint
//! solvers need.

mod ball;
mod hemisphere_brick;
mod shell;

use serde::{Deserialize, Serialize};

use crate::MAX_DIM;
use crate::error::CoreError;

/// The curved part of a container, if any.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Shape {
    /// Only the box: each axis periodic or flat-walled.
    Box,
    /// A (hyper)sphere over the first `axes` axes whose diameter is `lengths[0]`
    /// (RCPGenerator's negative first `--walls` entry): a circle, cylinder, sphere, 4-ball…
    /// The remaining axes keep their own periodic/wall flag.
    Ball { axes: usize },
    /// A cylindrical shell (Particle Assembler): the annulus `inner_radius ≤ ρ ≤ outer_radius`
    /// over axes 0 and 1, `lengths[0] = lengths[1] = 2·outer_radius`; the other axes keep their flags.
    CylindricalShell {
        inner_radius: f64,
        outer_radius: f64,
    },
    /// A brick minus two hemispheres of radii `radii[0]`, `radii[1]`, centred on the faces
    /// `x = 0` and `x = L_0` (3DRSP Example 3). All brick faces are flat walls.
    HemisphereCutBrick { radii: [f64; 2] },
}

/// A simulation container. See the module docs for the coordinate convention.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Container {
    /// Side lengths of the bounding box, one per axis.
    pub lengths: Vec<f64>,
    /// Per axis: `true` periodic, `false` bounded by flat hard walls at 0 and `L_k`.
    /// Axes covered by a curved wall are `false` and carry no flat walls.
    pub periodic: Vec<bool>,
    /// The curved wall, if any.
    pub shape: Shape,
    /// `--fix-height`: the last axis is held at this multiple of the largest diameter.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fix_height: Option<f64>,
}

/// One wall near a point, as reported by [`Container::for_each_wall`].
#[derive(Clone, Copy, Debug)]
pub struct Wall<'a> {
    /// Identifies the wall within its container (stable across calls).
    pub id: usize,
    /// Signed distance from the point to the wall surface, positive inside the container.
    pub distance: f64,
    /// Unit normal pointing from the point towards the wall (out of the container).
    pub normal: &'a [f64],
}

impl Container {
    /// A fully periodic box.
    pub fn periodic_box(lengths: &[f64]) -> Result<Self, CoreError> {
        Self::with_flags(lengths, &vec![false; lengths.len()])
    }

    /// A box whose axis `k` has hard walls when `walls[k]` is true and is periodic otherwise.
    pub fn with_flags(lengths: &[f64], walls: &[bool]) -> Result<Self, CoreError> {
        let c = Container {
            lengths: lengths.to_vec(),
            periodic: walls.iter().map(|w| !w).collect(),
            shape: Shape::Box,
            fix_height: None,
        };
        c.validate()?;
        Ok(c)
    }

    /// A container from RCPGenerator's `--box` and `--walls` lists: `0` periodic, `1` hard
    /// wall; a negative first entry `-t` makes a ball of diameter `box[0]` over the first `t`
    /// axes (circle, cylinder, sphere, hypersphere), the other axes keeping their own flags.
    /// An empty `walls` means fully periodic.
    pub fn from_rcp_flags(lengths: &[f64], walls: &[i64]) -> Result<Self, CoreError> {
        let d = lengths.len();
        check_dim(d)?;
        if walls.is_empty() {
            return Self::periodic_box(lengths);
        }
        if walls.len() != d {
            return Err(CoreError::Container(format!(
                "--walls has {} entries but --box has {d}; give one flag per axis",
                walls.len()
            )));
        }
        if walls[0] < 0 {
            let t = (-walls[0]) as usize;
            if t < 2 || t > d {
                return Err(CoreError::Container(format!(
                    "--walls {} asks for a ball over {t} axes, which must be between 2 and the dimension {d}",
                    walls[0]
                )));
            }
            let mut lens = lengths.to_vec();
            let mut periodic = vec![false; d];
            for k in 0..t {
                lens[k] = lengths[0];
            }
            for k in t..d {
                periodic[k] = parse_wall_flag(walls[k], k)?;
            }
            let c = Container {
                lengths: lens,
                periodic,
                shape: Shape::Ball { axes: t },
                fix_height: None,
            };
            c.validate()?;
            return Ok(c);
        }
        let flags = walls
            .iter()
            .enumerate()
            .map(|(k, &w)| parse_wall_flag(w, k).map(|p| !p))
            .collect::<Result<Vec<_>, _>>()?;
        Self::with_flags(lengths, &flags)
    }

    /// A cylindrical shell of the given radii over axes 0 and 1 and height `lengths[2..]`;
    /// `walls[k]` for `k ≥ 2` says whether those axes are walled.
    pub fn cylindrical_shell(
        inner_radius: f64,
        outer_radius: f64,
        other_lengths: &[f64],
        other_walls: &[bool],
    ) -> Result<Self, CoreError> {
        let mut lengths = vec![2.0 * outer_radius, 2.0 * outer_radius];
        lengths.extend_from_slice(other_lengths);
        let mut periodic = vec![false, false];
        periodic.extend(other_walls.iter().map(|w| !w));
        let c = Container {
            lengths,
            periodic,
            shape: Shape::CylindricalShell {
                inner_radius,
                outer_radius,
            },
            fix_height: None,
        };
        c.validate()?;
        Ok(c)
    }

    /// A walled brick minus two hemispheres centred on the faces normal to x.
    pub fn hemisphere_cut_brick(lengths: &[f64], radii: [f64; 2]) -> Result<Self, CoreError> {
        let c = Container {
            lengths: lengths.to_vec(),
            periodic: vec![false; lengths.len()],
            shape: Shape::HemisphereCutBrick { radii },
            fix_height: None,
        };
        c.validate()?;
        Ok(c)
    }

    /// Checks lengths, flags and curved-wall parameters for consistency.
    pub fn validate(&self) -> Result<(), CoreError> {
        let d = self.lengths.len();
        check_dim(d)?;
        if self.periodic.len() != d {
            return Err(CoreError::Container(format!(
                "{} periodicity flags for {d} axes",
                self.periodic.len()
            )));
        }
        for (k, &l) in self.lengths.iter().enumerate() {
            if !(l.is_finite() && l > 0.0) {
                return Err(CoreError::Container(format!(
                    "box length {l} on axis {k} must be a positive finite number"
                )));
            }
        }
        if let Some(h) = self.fix_height
            && !(h.is_finite() && h > 0.0)
        {
            return Err(CoreError::Container(format!(
                "fix-height multiple {h} must be positive"
            )));
        }
        match &self.shape {
            Shape::Box => Ok(()),
            Shape::Ball { axes } => ball::validate(self, *axes),
            Shape::CylindricalShell {
                inner_radius,
                outer_radius,
            } => shell::validate(self, *inner_radius, *outer_radius),
            Shape::HemisphereCutBrick { radii } => hemisphere_brick::validate(self, *radii),
        }
    }

    /// Dimension `d`.
    #[inline]
    pub fn dim(&self) -> usize {
        self.lengths.len()
    }

    /// True when every axis is periodic (no walls of any kind).
    pub fn is_fully_periodic(&self) -> bool {
        matches!(self.shape, Shape::Box) && self.periodic.iter().all(|&p| p)
    }

    /// True when the container has any wall, flat or curved.
    pub fn has_walls(&self) -> bool {
        !self.is_fully_periodic()
    }

    /// Exact volume (area in 2D), the denominator of φ.
    pub fn volume(&self) -> f64 {
        match &self.shape {
            Shape::Box => self.lengths.iter().product(),
            Shape::Ball { axes } => ball::volume(self, *axes),
            Shape::CylindricalShell {
                inner_radius,
                outer_radius,
            } => shell::volume(self, *inner_radius, *outer_radius),
            Shape::HemisphereCutBrick { radii } => hemisphere_brick::volume(self, *radii),
        }
    }

    /// Volume per unit length of the last axis (the container's volume is linear in its height
    /// for every shape whose curved wall does not cover the last axis). Used by `--fix-height`.
    pub fn volume_per_height(&self) -> f64 {
        self.volume() / self.lengths[self.dim() - 1]
    }

    /// Number of rigid motions the container allows, `m` in `n_dof = d·N' − m + 1`: one
    /// translation per periodic axis, `t(t−1)/2` rotations for a ball over `t` axes, one
    /// rotation for a cylindrical shell.
    pub fn rigid_motions(&self) -> usize {
        let translations = self.periodic.iter().filter(|&&p| p).count();
        let rotations = match &self.shape {
            Shape::Ball { axes } => axes * (axes - 1) / 2,
            Shape::CylindricalShell { .. } => 1,
            _ => 0,
        };
        translations + rotations
    }

    /// Replaces `delta` by its minimum image along every periodic axis.
    #[inline]
    pub fn min_image(&self, delta: &mut [f64]) {
        for k in 0..delta.len() {
            if self.periodic[k] {
                let l = self.lengths[k];
                delta[k] -= l * (delta[k] / l).round();
            }
        }
    }

    /// Separation vector `b − a` by minimum image, written into `out`.
    #[inline]
    pub fn separation(&self, a: &[f64], b: &[f64], out: &mut [f64]) {
        for k in 0..a.len() {
            out[k] = b[k] - a[k];
        }
        self.min_image(out);
    }

    /// Wraps a position into `[0, L_k)` along periodic axes.
    #[inline]
    pub fn wrap(&self, x: &mut [f64]) {
        for k in 0..x.len() {
            if self.periodic[k] {
                let l = self.lengths[k];
                x[k] -= l * (x[k] / l).floor();
                if x[k] >= l {
                    x[k] = 0.0;
                }
            }
        }
    }

    /// Calls `f` for every wall whose signed distance from `x` is below `reach`.
    /// A sphere of radius `r` at `x` overlaps a wall when `distance < r`.
    pub fn for_each_wall(&self, x: &[f64], reach: f64, mut f: impl FnMut(Wall<'_>)) {
        let d = self.dim();
        let mut normal = [0.0; MAX_DIM];
        let flat_axes_from = match &self.shape {
            Shape::Ball { axes } => *axes,
            Shape::CylindricalShell { .. } => 2,
            _ => 0,
        };
        for k in flat_axes_from..d {
            if self.periodic[k] {
                continue;
            }
            for (side, dist) in [(0usize, x[k]), (1usize, self.lengths[k] - x[k])] {
                if dist < reach {
                    normal[..d].fill(0.0);
                    normal[k] = if side == 0 { -1.0 } else { 1.0 };
                    f(Wall {
                        id: 2 * k + side,
                        distance: dist,
                        normal: &normal[..d],
                    });
                }
            }
        }
        match &self.shape {
            Shape::Box => {}
            Shape::Ball { axes } => ball::walls(self, *axes, x, reach, &mut normal, &mut f),
            Shape::CylindricalShell {
                inner_radius,
                outer_radius,
            } => shell::walls(
                self,
                *inner_radius,
                *outer_radius,
                x,
                reach,
                &mut normal,
                &mut f,
            ),
            Shape::HemisphereCutBrick { radii } => {
                hemisphere_brick::walls(self, *radii, x, reach, &mut normal, &mut f)
            }
        }
    }

    /// The shortest periodic length and its axis, the first of equals (`None` without
    /// periodic axes).
    pub fn shortest_periodic_length(&self) -> Option<(usize, f64)> {
        (0..self.dim())
            .filter(|&k| self.periodic[k])
            .map(|k| (k, self.lengths[k]))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// Why a sphere of `diameter` cannot be in this container, if it is wider than a periodic
    /// length: it would overlap its own image, which no packing has (and a neighbour search
    /// would visit ever more images of it). One sentence naming the axis.
    pub fn too_wide_for_periodic_axis(&self, diameter: f64) -> Option<String> {
        let k = (0..self.dim()).find(|&k| self.periodic[k] && diameter > self.lengths[k])?;
        Some(format!(
            "diameter {diameter:?} is wider than the periodic box length {} on axis {}: the particle would overlap its own image; check the diameters and --box",
            self.lengths[k],
            k + 1
        ))
    }

    /// Smallest signed distance from `x` to any wall (`+∞` in a fully periodic box).
    pub fn wall_clearance(&self, x: &[f64]) -> f64 {
        let mut best = f64::INFINITY;
        self.for_each_wall(x, f64::INFINITY, |w| best = best.min(w.distance));
        best
    }

    /// True when a sphere of radius `radius` at `x` lies inside the container up to `tol`
    /// (overlapping a wall by at most `tol`), and `x` lies in the box along periodic axes.
    pub fn contains(&self, x: &[f64], radius: f64, tol: f64) -> bool {
        x.iter()
            .zip(&self.lengths)
            .all(|(&xi, &l)| xi.is_finite() && xi >= -tol && xi <= l + tol)
            && self.wall_clearance(x) >= radius - tol
    }

    /// Scales every length (and curved-wall radius) by `s`.
    pub fn scale(&mut self, s: f64) {
        for l in &mut self.lengths {
            *l *= s;
        }
        match &mut self.shape {
            Shape::CylindricalShell {
                inner_radius,
                outer_radius,
            } => {
                *inner_radius *= s;
                *outer_radius *= s;
            }
            Shape::HemisphereCutBrick { radii } => {
                radii[0] *= s;
                radii[1] *= s;
            }
            _ => {}
        }
    }

    /// Short human-readable description, e.g. `"box 1×1×1, periodic x,y,z"`.
    pub fn describe(&self) -> String {
        let lens = self
            .lengths
            .iter()
            .map(|l| format!("{l}"))
            .collect::<Vec<_>>()
            .join("×");
        let flags = self
            .periodic
            .iter()
            .map(|&p| if p { "p" } else { "w" })
            .collect::<Vec<_>>()
            .join("");
        match &self.shape {
            Shape::Box => format!("box {lens} [{flags}]"),
            Shape::Ball { axes } => format!(
                "ball over {axes} axes, diameter {} [{flags}]",
                self.lengths[0]
            ),
            Shape::CylindricalShell {
                inner_radius,
                outer_radius,
            } => {
                format!(
                    "cylindrical shell r∈[{inner_radius}, {outer_radius}], box {lens} [{flags}]"
                )
            }
            Shape::HemisphereCutBrick { radii } => {
                format!(
                    "brick {lens} minus hemispheres of radii {}, {}",
                    radii[0], radii[1]
                )
            }
        }
    }
}

fn check_dim(d: usize) -> Result<(), CoreError> {
    if (2..=MAX_DIM).contains(&d) {
        Ok(())
    } else {
        Err(CoreError::Dimension(d))
    }
}

/// `--walls` entry → periodic?
fn parse_wall_flag(w: i64, axis: usize) -> Result<bool, CoreError> {
    match w {
        0 => Ok(true),
        1 => Ok(false),
        _ => Err(CoreError::Container(format!(
            "--walls entry {w} on axis {axis} must be 0 (periodic) or 1 (hard wall); only the first entry may be negative"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn rcp_flags_make_cylinders_spheres_and_balls() {
        let cyl = Container::from_rcp_flags(&[1.5, 1.0, 0.8], &[-2, 0, 0]).unwrap();
        assert_eq!(cyl.shape, Shape::Ball { axes: 2 });
        assert_eq!(cyl.periodic, vec![false, false, true]);
        assert!((cyl.volume() - PI * 0.75 * 0.75 * 0.8).abs() < 1e-14);
        assert_eq!(cyl.rigid_motions(), 2);
        let sphere = Container::from_rcp_flags(&[1.5, 0.8, 0.8], &[-3, 0, 0]).unwrap();
        assert!((sphere.volume() - 4.0 / 3.0 * PI * 0.75f64.powi(3)).abs() < 1e-14);
        assert_eq!(sphere.rigid_motions(), 3);
        let ball4 = Container::from_rcp_flags(&[1.5, 1.0, 0.8, 3.0], &[-4, 0, 0, 1]).unwrap();
        assert!((ball4.volume() - PI * PI / 2.0 * 0.75f64.powi(4)).abs() < 1e-14);
        let disk = Container::from_rcp_flags(&[1.5, 0.8], &[-2, 0]).unwrap();
        assert!((disk.volume() - PI * 0.5625).abs() < 1e-14);
        assert_eq!(disk.rigid_motions(), 1);
    }

    #[test]
    fn bad_flags_are_refused_with_a_reason() {
        assert!(
            Container::from_rcp_flags(&[1.0, 1.0], &[0])
                .unwrap_err()
                .to_string()
                .contains("--walls")
        );
        assert!(Container::from_rcp_flags(&[1.0, 1.0], &[2, 0]).is_err());
        assert!(Container::from_rcp_flags(&[1.0, 1.0], &[-3, 0]).is_err());
        assert!(
            Container::from_rcp_flags(&[1.0], &[])
                .unwrap_err()
                .to_string()
                .contains("dimension 1")
        );
        assert!(Container::periodic_box(&[1.0, -1.0]).is_err());
        assert!(Container::periodic_box(&[1.0, f64::NAN]).is_err());
    }

    #[test]
    fn shell_and_hemisphere_brick_volumes_are_exact() {
        let s = Container::cylindrical_shell(0.5, 2.0, &[3.0], &[true]).unwrap();
        assert!((s.volume() - PI * (4.0 - 0.25) * 3.0).abs() < 1e-12);
        assert_eq!(s.rigid_motions(), 1);
        let h = Container::hemisphere_cut_brick(&[4.0, 2.0, 2.0], [1.0, 0.5]).unwrap();
        let half = |r: f64| 2.0 / 3.0 * PI * r * r * r;
        assert!((h.volume() - (16.0 - half(1.0) - half(0.5))).abs() < 1e-12);
        assert!(Container::hemisphere_cut_brick(&[4.0, 2.0, 2.0], [1.5, 0.5]).is_err());
    }

    #[test]
    fn walls_report_signed_distance_and_outward_normal() {
        let s = Container::cylindrical_shell(0.5, 2.0, &[3.0], &[true]).unwrap();
        let mut seen = Vec::new();
        s.for_each_wall(&[2.0 + 1.0, 2.0, 0.2], 0.6, |w| {
            seen.push((w.id, w.distance, w.normal.to_vec()))
        });
        // Outer wall at distance 1 is beyond reach; inner wall 0.5 away, bottom wall 0.2 away.
        assert_eq!(seen.len(), 2);
        let inner = seen.iter().find(|w| w.0 == 7).unwrap();
        assert!((inner.1 - 0.5).abs() < 1e-15 && (inner.2[0] + 1.0).abs() < 1e-15);
        let bottom = seen.iter().find(|w| w.0 == 4).unwrap();
        assert!((bottom.1 - 0.2).abs() < 1e-15 && bottom.2[2] == -1.0);
        let h = Container::hemisphere_cut_brick(&[4.0, 2.0, 2.0], [1.0, 0.5]).unwrap();
        assert!(!h.contains(&[0.5, 1.0, 1.0], 0.1, 0.0));
        assert!(h.contains(&[2.0, 1.0, 1.0], 0.5, 0.0));
    }

    #[test]
    fn minimum_image_and_wrap_only_touch_periodic_axes() {
        let c = Container::with_flags(&[2.0, 2.0], &[false, true]).unwrap();
        let mut v = [1.5, 1.5];
        c.min_image(&mut v);
        assert_eq!(v, [-0.5, 1.5]);
        let mut x = [2.5, 1.0];
        c.wrap(&mut x);
        assert_eq!(x, [0.5, 1.0]);
    }
}
