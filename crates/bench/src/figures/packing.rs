//! A packing drawn to scale: 2D disks, or a slice of a 3D (or higher) packing.

use packbench_core::Packing;
use packbench_core::analysis::{ContactNetwork, contact_network, rattlers};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{FONT, Res};

/// Fill of a particle that carries load, and of a rattler.
const PARTICLE: RGBColor = RGBColor(120, 160, 210);
const RATTLER: RGBColor = RGBColor(220, 60, 60);

/// In a slice, a contact is drawn when its contact point lies within this fraction of the
/// smaller diameter of the pair from the drawing plane: a contact between two spheres that only
/// graze the plane would be a line between two specks, far from where they touch.
const CONTACT_NEAR_PLANE: f64 = 0.25;

/// Where the box sits on the drawing: pixels per length unit and the margins (left and bottom
/// hold the axes' ticks and labels).
struct Frame {
    scale: f64,
    left: f64,
    bottom: f64,
    height: f64,
}

impl Frame {
    fn new(w: u32, h: u32, lx: f64, ly: f64) -> Self {
        let (left, right, top, bottom) = (70.0, 20.0, 45.0, 55.0);
        let scale = ((w as f64 - left - right) / lx).min((h as f64 - top - bottom) / ly);
        Frame {
            scale,
            left,
            bottom,
            height: h as f64,
        }
    }

    fn px(&self, x: f64, y: f64) -> (i32, i32) {
        (
            (self.left + x * self.scale) as i32,
            (self.height - self.bottom - y * self.scale) as i32,
        )
    }
}

/// A packing to scale: 2D disks, or for d ≥ 3 the disks where spheres cut the plane through
/// the middle of axes 3…d. Rattlers are red, contacts between drawn particles are lines; the
/// axes are in mean diameters, and a key names what is drawn.
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
    let (lx, ly) = (p.container.lengths[0], p.container.lengths[1]);
    let frame = Frame::new(w, h, lx, ly);
    let net = contact_network(p, 1e-6);
    let rattler = rattlers(&net, p.n(), p.dim);
    let cut = in_plane_radii(p);
    draw_disks(root, &frame, p, &cut, &rattler)?;
    draw_contacts(root, &frame, p, &net, &cut)?;
    draw_box_and_axes(root, &frame, p)?;
    draw_key(root, w)?;
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

/// Each particle's radius in the drawing plane (axes 3…d at the box's middle), `None` when
/// it does not cut the plane; in 2D every disk's radius.
fn in_plane_radii(p: &Packing) -> Vec<Option<f64>> {
    (0..p.n())
        .map(|i| {
            let r2 = 0.25 * p.diameters[i] * p.diameters[i] - off_plane(p, p.position(i));
            (r2 > 0.0).then(|| r2.sqrt())
        })
        .collect()
}

/// Squared distance of the point `x` from the drawing plane.
fn off_plane(p: &Packing, x: &[f64]) -> f64 {
    (2..p.dim)
        .map(|k| (x[k] - 0.5 * p.container.lengths[k]).powi(2))
        .sum()
}

/// The disks, with their periodic images across the box's edges.
fn draw_disks<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    frame: &Frame,
    p: &Packing,
    cut: &[Option<f64>],
    rattler: &[bool],
) -> Res
where
    DB::ErrorType: 'static,
{
    let (lx, ly) = (p.container.lengths[0], p.container.lengths[1]);
    let images = |k: usize| {
        if p.container.periodic[k] {
            vec![-1.0, 0.0, 1.0]
        } else {
            vec![0.0]
        }
    };
    for (i, r) in cut.iter().enumerate() {
        let Some(r) = *r else { continue };
        let x = p.position(i);
        let fill = if rattler[i] { RATTLER } else { PARTICLE };
        for sx in images(0) {
            for sy in images(1) {
                let (cx, cy) = (x[0] + sx * lx, x[1] + sy * ly);
                if cx + r < 0.0 || cx - r > lx || cy + r < 0.0 || cy - r > ly {
                    continue;
                }
                let radius = ((r * frame.scale) as i32).max(1);
                let c = frame.px(cx, cy);
                root.draw(&Circle::new(c, radius, fill.mix(0.75).filled()))?;
                root.draw(&Circle::new(c, radius, BLACK.stroke_width(1)))?;
            }
        }
    }
    Ok(())
}

/// Contacts between drawn particles whose contact point lies near the plane
/// ([`CONTACT_NEAR_PLANE`]), centre to centre.
fn draw_contacts<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    frame: &Frame,
    p: &Packing,
    net: &ContactNetwork,
    cut: &[Option<f64>],
) -> Res
where
    DB::ErrorType: 'static,
{
    for (c, ct) in net.contacts.iter().enumerate() {
        let Some(j) = ct.j else { continue };
        if cut[ct.i].is_none() || cut[j].is_none() {
            continue;
        }
        let xi = p.position(ct.i);
        let n = &net.normals[c * p.dim..(c + 1) * p.dim];
        let (ri, rj) = (0.5 * p.diameters[ct.i], 0.5 * p.diameters[j]);
        let touch: Vec<f64> = xi.iter().zip(n).map(|(x, n)| x + n * ri).collect();
        if off_plane(p, &touch).sqrt() > CONTACT_NEAR_PLANE * 2.0 * ri.min(rj) {
            continue;
        }
        let end = (xi[0] + n[0] * (ri + rj), xi[1] + n[1] * (ri + rj));
        root.draw(&PathElement::new(
            vec![frame.px(xi[0], xi[1]), frame.px(end.0, end.1)],
            BLACK.stroke_width(2),
        ))?;
    }
    Ok(())
}

/// Masks the periodic images that spill over the box's edges, then draws the box (and a
/// ball's wall), ticks and labels on x and y in mean diameters.
fn draw_box_and_axes<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    frame: &Frame,
    p: &Packing,
) -> Res
where
    DB::ErrorType: 'static,
{
    let (w, h) = root.dim_in_pixel();
    let (lx, ly) = (p.container.lengths[0], p.container.lengths[1]);
    let (x0, y0) = frame.px(0.0, ly);
    let (x1, y1) = frame.px(lx, 0.0);
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
        let c = frame.px(0.5 * lx, 0.5 * lx);
        root.draw(&Circle::new(
            c,
            (0.5 * lx * frame.scale) as i32,
            BLACK.stroke_width(2),
        ))?;
    }
    let mean_d = p.mean_diameter();
    let label = (FONT, 13).into_font().color(&BLACK);
    let step = tick_step(lx.max(ly) / mean_d);
    let digits = (-step.log10().floor()).max(0.0) as usize;
    let ticks = |length: f64| {
        (0..)
            .map(move |k| k as f64 * step)
            .take_while(move |t| t * mean_d <= length * (1.0 + 1e-9))
    };
    for t in ticks(lx) {
        let (x, y) = frame.px(t * mean_d, 0.0);
        root.draw(&PathElement::new(vec![(x, y), (x, y + 5)], BLACK))?;
        root.draw(&Text::new(
            format!("{t:.digits$}"),
            (x - 6, y + 8),
            label.clone(),
        ))?;
    }
    for t in ticks(ly) {
        let (x, y) = frame.px(0.0, t * mean_d);
        root.draw(&PathElement::new(vec![(x - 5, y), (x, y)], BLACK))?;
        root.draw(&Text::new(
            format!("{t:.digits$}"),
            (x - 35, y - 6),
            label.clone(),
        ))?;
    }
    let desc = (FONT, 14).into_font().color(&BLACK);
    root.draw(&Text::new(
        "x (mean diameters)",
        ((x0 + x1) / 2 - 70, y1 + 28),
        desc.clone(),
    ))?;
    root.draw(&Text::new(
        "y (mean diameters)",
        (4, (y0 + y1) / 2 + 70),
        desc.transform(FontTransform::Rotate270),
    ))?;
    Ok(())
}

/// A round tick spacing (1, 2 or 5 times a power of ten) giving about six ticks over `span`.
fn tick_step(span: f64) -> f64 {
    let raw = (span / 6.0).max(1e-12);
    let decade = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * decade)
}

/// The key in the title bar: a particle, a rattler, a contact.
fn draw_key<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, w: u32) -> Res
where
    DB::ErrorType: 'static,
{
    let style = (FONT, 13).into_font().color(&BLACK);
    let x = w as i32 - 300;
    let y = 36;
    root.draw(&Circle::new((x, y), 6, PARTICLE.mix(0.75).filled()))?;
    root.draw(&Text::new("particle", (x + 10, y - 7), style.clone()))?;
    root.draw(&Circle::new((x + 95, y), 6, RATTLER.mix(0.75).filled()))?;
    root.draw(&Text::new("rattler", (x + 105, y - 7), style.clone()))?;
    root.draw(&PathElement::new(
        vec![(x + 180, y), (x + 200, y)],
        BLACK.stroke_width(2),
    ))?;
    root.draw(&Text::new("contact", (x + 206, y - 7), style))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_about_six() {
        assert_eq!(tick_step(12.0), 2.0);
        assert_eq!(tick_step(30.0), 5.0);
        assert_eq!(tick_step(3.0), 0.5);
    }
}
