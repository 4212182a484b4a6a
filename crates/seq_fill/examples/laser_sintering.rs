//! Black & Cheviakov 2022 §5: heat-induced bonding in powder-bed 3D printing, on the contact graph of a
//! Method 2 bed. A laser of power Q and radius r_ℓ rasters over a square in the middle of the
//! bed; each particle under the beam gains Q r_i³/r_ℓ³, loses k_b (T_R − T_i) to the air and
//! exchanges k_t (T_j − T_i) with every particle it touches; T_i advances by explicit Euler
//! steps q_i Δt/(m_i C_p). Two touching particles both above the sintering temperature T_s
//! form a bond. Writes one PNG of the bonded particles (top view) and prints a summary.
//!
//! `cargo run --release -p packbench-seqfill --example laser_sintering [-- out.png]`
//!
//! The seed gives no scan speed or time step; this example uses 1 m/s and Δt = 0.25 µs
//! (well below the conduction time m C_p / (z k_t) ≈ 20 µs), with hatch spacing r_ℓ.

use std::collections::BTreeSet;
use std::time::Instant;

use packbench_core::run::NullObserver;
use packbench_seqfill::{Params, Variant, run};
use plotters::prelude::*;

/// Mean radius of the seed's Weibull radii (eqn 2.4), µm.
const R_AVG: f64 = 14.136_712_421_627_204;
/// Laser power Q, W.
const Q: f64 = 100.0;
/// Heat transfer coefficient at the air boundary k_b = π τ_a r_avg / 2, W/K.
const K_B: f64 = 2.9090e-6;
/// Heat transfer coefficient of steel k_t = π τ_s r_avg / 2, W/K.
const K_T: f64 = 3.3309e-4;
/// Specific heat of steel C_p, J/(g·K).
const C_P: f64 = 0.5;
/// Steel density ρ, g/µm³.
const RHO: f64 = 8e-12;
/// Laser radius r_ℓ, µm.
const R_LASER: f64 = 50.0;
/// Ambient temperature T_R, K.
const T_AIR: f64 = 300.0;
/// Sintering temperature T_s, K.
const T_SINTER: f64 = 1000.0;
/// Scan speed, µm/s (1 m/s; not given by the seed).
const SPEED: f64 = 1e6;
/// Time step, s.
const DT: f64 = 0.25e-6;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out_path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "laser_sintering.png".into());
    // The bed of §5.2: Method 2, Weibull radii, FaceGoal 1.0, BodyGoal 0.9, ε 0.1, δ 0.5,
    // bricks of [1, 1, 0.12]·30 r̄, 6 × 6 × 1 of them.
    let std_length = 30.0 * R_AVG;
    let params = Params {
        variant: Variant::Method2,
        face_goal: 1.0,
        body_goal: 0.9,
        contact_param: 0.1,
        parent_param: 0.5,
        brick_lengths: vec![std_length, std_length, 0.12 * std_length],
        brick_numbers: vec![6, 6, 1],
        ..Params::default()
    };
    let t0 = Instant::now();
    let bed = run(&params, &mut NullObserver)?;
    let fill_s = t0.elapsed().as_secs_f64();
    let p = &bed.outcome.packing;
    let n = p.n();
    let r: Vec<f64> = p.diameters.iter().map(|d| 0.5 * d).collect();
    let heat_capacity: Vec<f64> = r
        .iter()
        .map(|ri| 4.0 / 3.0 * std::f64::consts::PI * RHO * ri.powi(3) * C_P)
        .collect();
    let (lx, ly) = (p.container.lengths[0], p.container.lengths[1]);

    // The laser path: a back-and-forth raster over a square of side 0.3 L in the middle.
    let side = 0.3 * lx;
    let (x0, y0) = (0.5 * (lx - side), 0.5 * (ly - side));
    let lines = (side / R_LASER).floor() as usize + 1;
    let mut path = Vec::new();
    for l in 0..lines {
        let y = y0 + l as f64 * R_LASER;
        let (a, b) = if l % 2 == 0 {
            (x0, x0 + side)
        } else {
            (x0 + side, x0)
        };
        path.push(((a, y), (b, y)));
    }

    let mut t = vec![T_AIR; n];
    let mut peak = vec![T_AIR; n];
    let mut q = vec![0.0; n];
    let mut bonds = BTreeSet::new();
    let mut steps = 0u64;
    for &((ax, ay), (bx, by)) in &path {
        let len = (bx - ax).hypot(by - ay);
        let n_steps = (len / (SPEED * DT)).ceil() as usize;
        for s in 0..n_steps {
            let f = s as f64 / n_steps as f64;
            let (cx, cy) = (ax + f * (bx - ax), ay + f * (by - ay));
            // Convection and laser input (particles whose centre is under the beam).
            for i in 0..n {
                let x = p.position(i);
                q[i] = K_B * (T_AIR - t[i]);
                if (x[0] - cx).hypot(x[1] - cy) <= R_LASER {
                    q[i] += Q * (r[i] / R_LASER).powi(3);
                }
            }
            // Conduction through the contacts of the bed.
            for &[i, j] in &bed.contacts {
                let flow = K_T * (t[j] - t[i]);
                q[i] += flow;
                q[j] -= flow;
            }
            for i in 0..n {
                t[i] += q[i] * DT / heat_capacity[i];
                peak[i] = peak[i].max(t[i]);
            }
            for &[i, j] in &bed.contacts {
                if t[i] >= T_SINTER && t[j] >= T_SINTER {
                    bonds.insert((i, j));
                }
            }
            steps += 1;
        }
    }
    let bonded: BTreeSet<usize> = bonds.iter().flat_map(|&(i, j)| [i, j]).collect();
    println!(
        "bed: {n} particles, {} contacts, domain {:.0} × {:.0} × {:.2} µm, filled in {fill_s:.2} s",
        bed.contacts.len(),
        lx,
        ly,
        p.container.lengths[2]
    );
    println!(
        "laser: {} passes, {steps} steps of {DT:e} s; {} bonds between {} particles; hottest particle {:.0} K",
        path.len(),
        bonds.len(),
        bonded.len(),
        peak.iter().cloned().fold(0.0, f64::max)
    );

    // Top view of the bonded particles and their bonds, coloured by peak temperature.
    let margin = 2.0 * R_LASER;
    let (vx0, vx1, vy0, vy1) = (
        x0 - margin,
        x0 + side + margin,
        y0 - margin,
        y0 + side + margin,
    );
    let root = BitMapBackend::new(&out_path, (1000, 1000)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Simulated print of a square: bonded particles (Black & Cheviakov 2022 §5)",
            ("sans-serif", 22),
        )
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(vx0..vx1, vy0..vy1)?;
    chart
        .configure_mesh()
        .x_desc("x, µm")
        .y_desc("y, µm")
        .disable_mesh()
        .draw()?;
    let px_per_um = chart.plotting_area().dim_in_pixel().0 as f64 / (vx1 - vx0);
    let (t_lo, t_hi) = (
        T_SINTER,
        bonded.iter().map(|&i| peak[i]).fold(T_SINTER, f64::max),
    );
    chart.draw_series(bonded.iter().map(|&i| {
        let x = p.position(i);
        let s = ((peak[i] - t_lo) / (t_hi - t_lo).max(1.0)).clamp(0.0, 1.0);
        let colour = RGBColor(255, (200.0 * (1.0 - s)) as u8, (60.0 * (1.0 - s)) as u8);
        Circle::new(
            (x[0], x[1]),
            (r[i] * px_per_um).max(1.0) as i32,
            colour.mix(0.8).filled(),
        )
    }))?;
    chart.draw_series(bonds.iter().map(|&(i, j)| {
        let (a, b) = (p.position(i), p.position(j));
        PathElement::new(vec![(a[0], a[1]), (b[0], b[1])], BLACK.stroke_width(1))
    }))?;
    root.present()?;
    println!("wrote {out_path}");
    Ok(())
}
