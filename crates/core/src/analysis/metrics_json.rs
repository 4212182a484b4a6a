//! How [`Metrics`] read and write: as the keys of `packbench analyze`, with the quantities a
//! packing without non-rattlers does not define (its mean non-rattler contact number and its
//! isostatic gap) written as `null`, not as the 0 that would read "exactly isostatic".

use serde::{Deserialize, Serialize};

use super::Metrics;

/// [`Metrics`] as written: `z_nonrattler` and `iso_gap` are `None` (JSON `null`) when every
/// particle is a rattler.
#[derive(Serialize, Deserialize)]
pub(super) struct MetricsJson {
    dim: usize,
    n: usize,
    phi: f64,
    contacts: usize,
    z_mean: f64,
    rattlers: usize,
    z_nonrattler: Option<f64>,
    n_dof: usize,
    iso_gap: Option<i64>,
    isostatic: bool,
    max_overlap: f64,
    force_balance: Option<f64>,
    polydispersity: f64,
    skewness: f64,
}

impl From<Metrics> for MetricsJson {
    fn from(m: Metrics) -> Self {
        MetricsJson {
            dim: m.dim,
            n: m.n,
            phi: m.phi,
            contacts: m.contacts,
            z_mean: m.z_mean,
            rattlers: m.rattlers,
            z_nonrattler: m.defined_z_nonrattler(),
            n_dof: m.n_dof,
            iso_gap: m.defined_iso_gap(),
            isostatic: m.isostatic,
            max_overlap: m.max_overlap,
            force_balance: m.force_balance,
            polydispersity: m.polydispersity,
            skewness: m.skewness,
        }
    }
}

impl From<MetricsJson> for Metrics {
    fn from(m: MetricsJson) -> Self {
        Metrics {
            dim: m.dim,
            n: m.n,
            phi: m.phi,
            contacts: m.contacts,
            z_mean: m.z_mean,
            rattlers: m.rattlers,
            z_nonrattler: m.z_nonrattler.unwrap_or(0.0),
            n_dof: m.n_dof,
            iso_gap: m.iso_gap.unwrap_or(0),
            isostatic: m.isostatic,
            max_overlap: m.max_overlap,
            force_balance: m.force_balance,
            polydispersity: m.polydispersity,
            skewness: m.skewness,
        }
    }
}
