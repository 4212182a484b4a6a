//! A packing drawn to scale: 2D disks, or a slice of a 3D (or higher) packing.

use packbench_core::Packing;
use packbench_core::analysis::{contact_network, rattlers};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{FONT, Res};

/// A packing to scale: 2D disks, or for d ≥ 3 the disks where spheres cut the plane through
/// the middle of axes 3…d. Rattlers are red, contacts between drawn particles are lines.
// Long because every drawing step (frame, disks or slice, contacts, rattlers, caption) writes into
// the one chart context plotters lends for the call; the split waits for the 3D slice's axes and
// legend.
pub fn draw_packing<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    p: &Packing,
    title: &str,
) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (w, h) = root.dim_in_pixel();
    let margin = 40.0;
    let (lx, ly) = (p.container.lengths[0], p.container.lengths[1]);
    let scale = ((w as f64 - 2.0 * margin) / lx).min((h as f64 - 2.0 * margin) / ly);
    let px = |x: f64, y: f64| {
        (
            (margin + x * scale) as i32,
            (h as f64 - margin - y * scale) as i32,
        )
    };
    let net = contact_network(p, 1e-6);
    let rattler = rattlers(&net, p.n(), p.dim);
    // In-plane radius of each particle (None when it does not cut the drawing plane).
    let cut: Vec<Option<f64>> = (0..p.n())
        .map(|i| {
            let x = p.position(i);
            let off2: f64 = (2..p.dim)
                .map(|k| (x[k] - 0.5 * p.container.lengths[k]).powi(2))
                .sum();
            let r2 = 0.25 * p.diameters[i] * p.diameters[i] - off2;
            (r2 > 0.0).then(|| r2.sqrt())
        })
        .collect();
    let images = |k: usize| {
        if p.container.periodic[k] {
            vec![-1.0, 0.0, 1.0]
        } else {
            vec![0.0]
        }
    };
    for i in 0..p.n() {
        let Some(r) = cut[i] else { continue };
        let x = p.position(i);
        let fill = if rattler[i] {
            RGBColor(220, 60, 60)
        } else {
            RGBColor(120, 160, 210)
        };
        for sx in images(0) {
            for sy in images(1) {
                let (cx, cy) = (x[0] + sx * lx, x[1] + sy * ly);
                if cx + r < 0.0 || cx - r > lx || cy + r < 0.0 || cy - r > ly {
                    continue;
                }
                let radius = ((r * scale) as i32).max(1);
                root.draw(&Circle::new(px(cx, cy), radius, fill.mix(0.75).filled()))?;
                root.draw(&Circle::new(px(cx, cy), radius, BLACK.stroke_width(1)))?;
            }
        }
    }
    for (c, ct) in net.contacts.iter().enumerate() {
        let Some(j) = ct.j else { continue };
        if cut[ct.i].is_none() || cut[j].is_none() {
            continue;
        }
        let xi = p.position(ct.i);
        let n = &net.normals[c * p.dim..(c + 1) * p.dim];
        let r = 0.5 * (p.diameters[ct.i] + p.diameters[j]);
        let end = (xi[0] + n[0] * r, xi[1] + n[1] * r);
        root.draw(&PathElement::new(
            vec![px(xi[0], xi[1]), px(end.0, end.1)],
            BLACK.stroke_width(2),
        ))?;
    }
    // Periodic images spill over the box edge: mask the margins, then draw frame and title.
    let (x0, y0) = px(0.0, ly);
    let (x1, y1) = px(lx, 0.0);
    let (wi, hi) = (w as i32, h as i32);
    for r in [
        [(0, 0), (wi, y0)],
        [(0, y1), (wi, hi)],
        [(0, 0), (x0, hi)],
        [(x1, 0), (wi, hi)],
    ] {
        root.draw(&Rectangle::new(r, WHITE.filled()))?;
    }
    root.draw(&Rectangle::new([(x0, y0), (x1, y1)], BLACK.stroke_width(1)))?;
    if let packbench_core::Shape::Ball { .. } = p.container.shape {
        let c = px(0.5 * lx, 0.5 * lx);
        root.draw(&Circle::new(
            c,
            (0.5 * lx * scale) as i32,
            BLACK.stroke_width(2),
        ))?;
    }
    let slice = if p.dim > 2 {
        " (slice through the middle)"
    } else {
        ""
    };
    root.draw(&Text::new(
        format!("{title}: N = {}, φ = {:.4}{slice}", p.n(), p.phi()),
        (10, 10),
        (FONT, 18),
    ))?;
    Ok(())
}
