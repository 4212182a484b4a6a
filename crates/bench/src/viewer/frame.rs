//! One drawable state of a packing for the page: positions, diameters, the contact network
//! with per-particle contact numbers and rattlers, optionally the contact forces and the
//! core's metrics. Everything physical comes from `packbench-core`'s analysis.

use packbench_core::Packing;
use packbench_core::analysis::void_space::radical_voronoi;
use packbench_core::analysis::{
    AnalysisOptions, Metrics, analyze, balancing_forces, contact_network, rattlers,
};
use serde::Serialize;

use super::encode::{f32_base64, u8_base64, u32_base64};
use crate::error::BenchError;

/// What to compute for a frame beyond positions and contacts.
#[derive(Clone, Copy, Debug)]
pub struct FrameOptions {
    /// Largest relative gap `r/σ − 1` counted as a contact (as in `packbench analyze`).
    pub contact_tol: f64,
    /// Attach the core's metrics ([`analyze`]).
    pub metrics: bool,
    /// Solve for force balance inside the metrics.
    pub force_balance: bool,
    /// Attach the balancing contact forces (core force balance), to colour the network.
    pub forces: bool,
}

/// One frame as the page reads it; arrays are base64 of little-endian typed arrays.
#[derive(Clone, Debug, Serialize)]
pub struct Frame {
    /// What the frame is (`step 4000`, `final`, `seed 2`).
    pub label: String,
    /// The method's step count at this frame (for the trace marker), if known.
    pub step: Option<u64>,
    /// Packing fraction.
    pub phi: f64,
    /// Number of particles.
    pub n: usize,
    /// Float32, N·d, row-major positions (the packing's length unit).
    pub positions: String,
    /// Float32, N diameters.
    pub diameters: String,
    /// Uint32, 2 per particle–particle contact (i, j); self-image contacts are left out.
    pub pairs: String,
    /// Uint8, contacts per particle (walls included), capped at 255.
    pub z: String,
    /// Uint8, 1 for a rattler (iterative removal, fewer than d+1 contacts).
    pub rattlers: String,
    /// Float32, one force per pair in `pairs` (mean 1 over loaded contacts), when computed.
    pub forces: Option<String>,
    /// Relative residual of those forces.
    pub force_residual: Option<f64>,
    /// The core's metrics, exactly what `packbench analyze` prints.
    pub metrics: Option<Metrics>,
    /// Float32, N local packing fractions (particle / radical Voronoi cell volume), on frames
    /// with metrics in 2D and 3D; absent where the tessellation refuses the packing (overlaps).
    pub local_phi: Option<String>,
}

impl Frame {
    /// The frame of `packing`, labelled `label`. Errors: the analysis failed (bad tolerance,
    /// solver failure).
    pub fn of(
        packing: &Packing,
        label: impl Into<String>,
        step: Option<u64>,
        options: &FrameOptions,
    ) -> Result<Frame, BenchError> {
        let n = packing.n();
        let net = contact_network(packing, options.contact_tol);
        let rattler = rattlers(&net, n, packing.dim);
        let mut z = vec![0u8; n];
        let mut pairs = Vec::new();
        let mut pair_index = Vec::new();
        for (c, ct) in net.contacts.iter().enumerate() {
            z[ct.i] = z[ct.i].saturating_add(1);
            if let Some(j) = ct.j {
                z[j] = z[j].saturating_add(1);
                if j != ct.i {
                    pairs.extend([ct.i as u32, j as u32]);
                    pair_index.push(c);
                }
            }
        }
        let (forces, force_residual) = if options.forces {
            let b = balancing_forces(&net, &rattler, packing.dim)?;
            let f: Vec<f64> = pair_index.iter().map(|&c| b.forces[c]).collect();
            (Some(f32_base64(&f)), Some(b.residual))
        } else {
            (None, None)
        };
        let metrics = if options.metrics {
            Some(analyze(
                packing,
                &AnalysisOptions {
                    contact_tol: options.contact_tol,
                    force_balance: options.force_balance,
                },
            )?)
        } else {
            None
        };
        // The page colours by local φ where the void-space analysis accepts the packing; a
        // packing it refuses (large overlaps of an early frame) is shown without that colouring.
        let local_phi = if options.metrics && (packing.dim == 2 || packing.dim == 3) {
            radical_voronoi(packing)
                .ok()
                .map(|c| f32_base64(&c.local_phi))
        } else {
            None
        };
        let flags: Vec<u8> = rattler.iter().map(|&r| u8::from(r)).collect();
        Ok(Frame {
            label: label.into(),
            step,
            phi: packing.phi(),
            n,
            positions: f32_base64(&packing.positions),
            diameters: f32_base64(&packing.diameters),
            pairs: u32_base64(&pairs),
            z: u8_base64(&z),
            rattlers: u8_base64(&flags),
            forces,
            force_residual,
            metrics,
            local_phi,
        })
    }
}
