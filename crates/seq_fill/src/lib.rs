//! packbench-seqfill: sequential random sphere placement after 3DRSP (Black & Cheviakov,
//! SoftwareX 18, 101051 (2022), Black & Cheviakov 2022).
//!
//! What it is: a geometric filler for modellers who need a non-overlapping, contacting bed of
//! spheres whose radii follow a measured distribution, and its contact graph, without
//! simulating settling. A unit brick gets a sphere of mean radius in each corner, then its
//! edges, faces and volume are filled with spheres each placed in exact contact with a tuple of
//! parents (three in 3D, two in 2D; one on an edge, two on a face), kept only if it lies inside
//! and overlaps nothing; radii that fit nowhere are discarded. Method 1 joins bricks by
//! reflection, Method 2 by copying; the hemisphere-cut domain of Example 3 is a Method 1 brick
//! with two hemispheres as fixed obstacles. A spatial grid keeps the cost per sphere constant.
//! Works in 2 to 8 dimensions.
//!
//! What it is not: not a jammed packing (it is neither mechanically stable nor isostatic, and its
//! density is what the goals ask for, not φ_J), not a dynamics of settling, and it draws no
//! figures (the bench and the examples do).

mod bed;
mod draws;
mod error;
mod grid;
mod ks;
mod outcome;
mod params;
mod reflection;
mod stratum;
mod tangent_sphere;
mod tiling;
mod unit_brick;

pub use error::SeqFillError;
pub use ks::radii_against_distribution;
pub use outcome::{FaceList, SeqFillOutcome, face_name, write_contacts_csv, write_face_lists_csv};
pub use packbench_core::ks::{KsTest, two_sample_ks};
pub use params::{MAX_FILL_DIM, MAX_SPHERES, Params, Variant};

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome};
use serde_json::json;

use unit_brick::{End, UnitBrick};

/// Fills the domain described by `params` (it needs no starting packing).
///
/// Reports progress to `observer` a few times per second, sends a snapshot of the unit brick
/// every `save_interval` placed spheres, and stops early with termination `interrupted` (the
/// bricks assembled from what was placed) when `observer.should_stop()`.
///
/// Errors: [`SeqFillError::Parameter`] for a parameter out of range (the message names it), a
/// brick shorter than the mean diameter or a domain above [`MAX_SPHERES`];
/// [`SeqFillError::Core`] for a bad size distribution or hemisphere radii.
pub fn run(params: &Params, observer: &mut dyn Observer) -> Result<SeqFillOutcome, SeqFillError> {
    params.validate()?;
    let d = params.dim();
    let outside =
        || SeqFillError::Parameter(format!("dimension {d} is outside 2 to {MAX_FILL_DIM}"));
    // `validate` refuses d above MAX_FILL_DIM (below the core's MAX_DIM); the constant test
    // keeps those fills from being instantiated.
    packbench_core::dispatch_dim!(
        d,
        D => if const { D <= MAX_FILL_DIM } { run_in::<D>(params, observer) } else { Err(outside()) },
        _ => Err(outside()),
    )
}

/// The fill monomorphised over the dimension.
fn run_in<const D: usize>(
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<SeqFillOutcome, SeqFillError> {
    let started = std::time::Instant::now();
    let mut brick = UnitBrick::<D>::new(params, observer)?;
    let end = brick.fill()?;
    let fill_s = started.elapsed().as_secs_f64();
    let domain = match params.variant {
        Variant::Method1 => reflection::reflect(&brick, &params.brick_numbers)?,
        Variant::Method2 => tiling::tile(&brick, &params.brick_numbers)?,
    };
    let packing = Packing::new(domain.positions, domain.diameters, domain.container)?;
    let termination = match end {
        End::GoalReached => "goals_reached",
        End::NothingFits => "nothing_fits",
        End::Interrupted => "interrupted",
    };
    let face_fractions = brick.face_fractions();
    let extra = json!({
        "variant": u8::from(params.variant),
        "unit_brick_spheres": brick.bed.len(),
        "total_spheres": packing.n(),
        "mean_radius": brick.mean_radius,
        "body_fraction": brick.body_fraction(),
        "face_fractions": face_fractions,
        "contacts": domain.contacts.len(),
        "radii_drawn": brick.draws.count(),
        "radii_discarded": brick.draws.discarded.len(),
        "unit_brick_time_s": fill_s,
        "total_time_s": started.elapsed().as_secs_f64(),
    });
    let serde_json::Value::Object(extra) = extra else {
        unreachable!("json! of an object literal is an object")
    };
    Ok(SeqFillOutcome {
        outcome: Outcome {
            packing,
            steps: brick.draws.count(),
            termination: termination.into(),
            trace: std::mem::take(&mut brick.trace),
            extra,
        },
        contacts: domain.contacts,
        faces: domain.faces,
        face_fractions,
        body_fraction: brick.body_fraction(),
        unit_brick_spheres: brick.bed.len(),
        mean_radius: brick.mean_radius,
        radii_placed: std::mem::take(&mut brick.draws.placed),
        radii_discarded: std::mem::take(&mut brick.draws.discarded),
    })
}
