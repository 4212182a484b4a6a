//! The parameters of a fill, named as in Black & Cheviakov 2022 §2.3 (ProbabilityDistr, FaceGoal, BodyGoal,
//! SphereContactParameter ε, ParentParameter δ, BrickSideLengths, BrickNumbers,
//! HemisphereRadii), plus the few search budgets the seed leaves implicit.

use packbench_core::SizeDistribution;
use serde::{Deserialize, Serialize};

use crate::error::SeqFillError;

/// Mean radius r̄ = λΓ(1 + 1/k) of the seed's Weibull radius distribution (λ = 15.7 µm,
/// k = 3.55; eqns 2.3–2.4), used to size the default brick.
const SEED_MEAN_RADIUS_UM: f64 = 14.136_712_421_627_204;

/// Largest dimension the fill supports (its tuples of parents grow as d-cliques).
pub const MAX_FILL_DIM: usize = 8;

/// How a unit brick is filled and copied (Black & Cheviakov 2022 §2 and §3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "u8", into = "u8")]
pub enum Variant {
    /// Method 1: every edge and face filled separately with spheres inside the brick that touch
    /// its faces; bricks joined by reflection about their faces.
    Method1,
    /// Method 2: one edge per direction and one face per orientation filled, with sphere centres
    /// on the brick faces, and copied to the parallel ones; bricks joined by plain copying.
    Method2,
}

impl TryFrom<u8> for Variant {
    type Error = String;
    fn try_from(v: u8) -> Result<Self, String> {
        match v {
            1 => Ok(Variant::Method1),
            2 => Ok(Variant::Method2),
            _ => Err(format!("variant {v} does not exist; use 1 or 2")),
        }
    }
}

impl From<Variant> for u8 {
    fn from(v: Variant) -> u8 {
        match v {
            Variant::Method1 => 1,
            Variant::Method2 => 2,
        }
    }
}

/// Everything a fill needs. `Default` is the seed's Example 1A (§2.4): Weibull radii with
/// λ = 15.7 µm, k = 3.55 (diameter scale 31.4 µm), FaceGoal 0.8, BodyGoal 0.55, ε = 0.2,
/// δ = 0.5, a cube of side 15 r̄ ≈ 212.05 µm, 2 × 2 × 1 bricks, Method 1.
/// All lengths are in the units of the distribution's diameters (µm in the seed).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Params {
    /// Method 1 or 2 (`--variant 1|2`).
    pub variant: Variant,
    /// BrickSideLengths: absolute side lengths of the unit brick, one per axis; their count is
    /// the dimension d (2 to 8). `--brick L1,L2,L3`.
    pub brick_lengths: Vec<f64>,
    /// BrickNumbers: copies of the unit brick along each axis (each ≥ 1). `--bricks n1,n2,n3`.
    pub brick_numbers: Vec<usize>,
    /// FaceGoal: fraction of each unit-brick face covered by the projections of the spheres
    /// touching it at which that face's fill stops, in [0, 1]. `--face-goal`.
    pub face_goal: f64,
    /// BodyGoal: volume fraction of the unit brick at which the volume fill stops, in [0, 1].
    /// `--body-goal`.
    pub body_goal: f64,
    /// SphereContactParameter ε in [0, 1]: two spheres whose surface gap is at most ε·r̄ are in
    /// contact (and a sphere within ε·r̄ of a face touches it). `--contact-param`.
    pub contact_param: f64,
    /// Whether ε also bounds the overlap a new sphere may have with those placed: Black &
    /// Cheviakov 2022 §2.1 call ε the "acceptable separation/overlap of two particles to be
    /// considered in contact", and their Table 1's counts fall as ε grows, which a contact
    /// tolerance alone cannot do. Off by default (the fill stays overlap-free); on, a putative
    /// position is refused only for an overlap deeper than ε·r̄.
    pub contact_overlap: bool,
    /// ParentParameter δ in [0, 1]: spheres whose surface gap is at most δ·r̄ are candidate
    /// parents of a new sphere together. `--parent-param`.
    pub parent_param: f64,
    /// HemisphereRadii (Example 3): radii of the two hemispheres cut from the brick, centred on
    /// the faces x = 0 and x = L₁. Needs Method 1 and brick numbers all 1. `--hemispheres R1,R2`.
    pub hemispheres: Option<[f64; 2]>,
    /// Seed of the random radius draws. `--seed`.
    pub seed: u64,
    /// ProbabilityDistr: the distribution of diameters (the seed's radius scale 15.7 µm is a
    /// diameter scale of 31.4). The core's `--dist` flags.
    pub distribution: SizeDistribution,
    /// Parent tuples a drawn radius tries before it is discarded (a radius that fits none of
    /// them "fits nowhere", seed §2.1). Larger is closer to the seed's exhaustive search and
    /// slower. Default 64.
    pub tuples_per_draw: usize,
    /// Radii a parent tuple may fail to host before it is closed for good. Default 32.
    pub tuple_retries: u32,
    /// An edge, face or volume is declared full ("no more sphere fits") when fewer than this
    /// fraction of the last [`ACCEPTANCE_WINDOW`] radii drawn for it were placed. It bounds the
    /// small-radius bias of the fill: the placed radii follow the target density times the
    /// chance to fit, and a low acceptance means a strong bias. In (0, 1]; default 0.15.
    pub min_acceptance: f64,
    /// Placed spheres between snapshots sent to the observer (0: none).
    pub save_interval: u64,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            variant: Variant::Method1,
            brick_lengths: vec![15.0 * SEED_MEAN_RADIUS_UM; 3],
            brick_numbers: vec![2, 2, 1],
            face_goal: 0.8,
            body_goal: 0.55,
            contact_param: 0.2,
            contact_overlap: false,
            parent_param: 0.5,
            hemispheres: None,
            seed: 0,
            distribution: SizeDistribution::Weibull {
                scale: 31.4,
                shape: 3.55,
            },
            tuples_per_draw: 64,
            tuple_retries: 32,
            min_acceptance: 0.15,
            save_interval: 0,
        }
    }
}

/// Radii over which the acceptance rate of [`Params::min_acceptance`] is measured.
pub const ACCEPTANCE_WINDOW: usize = 200;

/// Spheres a single fill may produce in the whole domain; beyond it the run is refused
/// before any memory is taken.
pub const MAX_SPHERES: f64 = 5e7;

impl Params {
    /// The dimension d, the number of brick lengths.
    pub fn dim(&self) -> usize {
        self.brick_lengths.len()
    }

    /// Checks every parameter; the message names the one that is wrong.
    pub fn validate(&self) -> Result<(), SeqFillError> {
        let bad = |m: String| Err(SeqFillError::Parameter(m));
        let d = self.dim();
        if !(2..=MAX_FILL_DIM).contains(&d) {
            return bad(format!(
                "{d} brick lengths give dimension {d}; seq-fill works in 2 to {MAX_FILL_DIM} dimensions"
            ));
        }
        if let Some(l) = self
            .brick_lengths
            .iter()
            .find(|l| !(l.is_finite() && **l > 0.0))
        {
            return bad(format!("brick length {l} must be a positive finite number"));
        }
        if self.brick_numbers.len() != d {
            return bad(format!(
                "{} brick numbers for {d} brick lengths; give one per axis",
                self.brick_numbers.len()
            ));
        }
        if self.brick_numbers.contains(&0) {
            return bad("brick numbers must be at least 1".into());
        }
        for (name, v) in [
            ("face_goal", self.face_goal),
            ("body_goal", self.body_goal),
            ("contact_param (ε)", self.contact_param),
            ("parent_param (δ)", self.parent_param),
        ] {
            if !(0.0..=1.0).contains(&v) {
                return bad(format!("{name} = {v} must lie in [0, 1]"));
            }
        }
        if self.tuples_per_draw == 0 || self.tuple_retries == 0 {
            return bad("tuples_per_draw and tuple_retries must be at least 1".into());
        }
        if !(self.min_acceptance > 0.0 && self.min_acceptance <= 1.0) {
            return bad(format!(
                "min_acceptance = {} must lie in (0, 1]",
                self.min_acceptance
            ));
        }
        if self.hemispheres.is_some() {
            if self.variant != Variant::Method1 {
                return bad(
                    "the hemisphere-cut domain (Example 3) is filled with Method 1; set variant 1"
                        .into(),
                );
            }
            if self.brick_numbers.iter().any(|&n| n != 1) {
                return bad(
                    "the hemisphere-cut domain is a single brick; set every brick number to 1"
                        .into(),
                );
            }
        }
        self.distribution.validate()?;
        Ok(())
    }
}
