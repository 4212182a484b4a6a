//! The core's verdict on a packing that a method calls jammed.
//!
//! An exact method (closest-jammed, its QP form, CALiPPSO) ends with a claim: the packing is a
//! jammed hard-sphere packing. The claim is the method's own; whether the packing *is* jammed
//! is the analysis's to say, with the same definitions for every method (Baranau & Tallarek 2014 App. C: no
//! overlaps, at least `n_dof` non-rattler contacts, non-negative contact forces that balance
//! every non-rattler; CALiPPSO.jl: isostatic and force-balanced from the LP's duals). A claim
//! the analysis contradicts is reported as `not_jammed`, never as jammed.

use super::Metrics;

/// Largest relative overlap `1 − r/σ` an exactly jammed packing may keep. The exact methods
/// close their contacts to about 1e-14; a larger overlap means the packing is not a
/// hard-sphere packing.
pub const JAMMED_MAX_OVERLAP: f64 = 1e-9;

/// Largest force-balance residual (see [`Metrics::force_balance`]) of a mechanically stable
/// packing; the exact methods reach 1e-13 to 1e-10.
pub const JAMMED_FORCE_BALANCE: f64 = 1e-8;

/// Why `metrics` do not describe an exactly jammed hard-sphere packing, as one sentence, or
/// `None` when they do: overlaps at most [`JAMMED_MAX_OVERLAP`], some non-rattlers, at least
/// `n_dof` contacts among them (`iso_gap ≥ 0`), and, when the force balance was computed, a
/// residual at most [`JAMMED_FORCE_BALANCE`].
pub fn not_jammed_because(metrics: &Metrics) -> Option<String> {
    let m = metrics;
    // NaN fails too.
    if m.max_overlap.is_nan() || m.max_overlap > JAMMED_MAX_OVERLAP {
        return Some(format!(
            "the largest overlap is {:.3e} of a contact distance (an exactly jammed packing has none above {JAMMED_MAX_OVERLAP:e})",
            m.max_overlap
        ));
    }
    if m.rattlers >= m.n {
        return Some(format!(
            "all {} particles are rattlers: no contact network holds the packing",
            m.n
        ));
    }
    if m.iso_gap < 0 {
        return Some(format!(
            "the non-rattlers have {} fewer contacts than the n_dof = {} a rigid network needs (iso_gap {})",
            -m.iso_gap, m.n_dof, m.iso_gap
        ));
    }
    match m.force_balance {
        Some(r) if r.is_nan() || r > JAMMED_FORCE_BALANCE => Some(format!(
            "no non-negative contact forces balance the non-rattlers (residual {r:.3e}, above {JAMMED_FORCE_BALANCE:e})"
        )),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn jammed() -> Metrics {
        Metrics {
            dim: 3,
            n: 10,
            phi: 0.6,
            contacts: 28,
            z_mean: 5.6,
            rattlers: 0,
            z_nonrattler: 5.6,
            n_dof: 28,
            iso_gap: 0,
            isostatic: true,
            max_overlap: 1e-14,
            force_balance: Some(1e-13),
            polydispersity: 0.0,
            skewness: 0.0,
        }
    }

    #[test]
    fn an_isostatic_balanced_packing_without_overlaps_is_jammed() {
        assert_eq!(not_jammed_because(&jammed()), None);
        let unchecked = Metrics {
            force_balance: None,
            iso_gap: 3,
            ..jammed()
        };
        assert_eq!(not_jammed_because(&unchecked), None);
    }

    #[test]
    fn each_failed_condition_is_named() {
        let cases = [
            (
                Metrics {
                    max_overlap: 0.76,
                    ..jammed()
                },
                "overlap",
            ),
            (
                Metrics {
                    max_overlap: f64::NAN,
                    ..jammed()
                },
                "overlap",
            ),
            (
                Metrics {
                    rattlers: 10,
                    ..jammed()
                },
                "rattlers",
            ),
            (
                Metrics {
                    iso_gap: -2,
                    ..jammed()
                },
                "iso_gap -2",
            ),
            (
                Metrics {
                    force_balance: Some(1e-3),
                    ..jammed()
                },
                "balance",
            ),
        ];
        for (m, word) in cases {
            let why = not_jammed_because(&m).expect("not jammed");
            assert!(why.contains(word), "{why}");
        }
    }
}
