//! `compare --pores`: the void space of every packing a comparison saved, as `pores.csv` (one
//! row per run), a "Void space" section appended to `report.md` (mean ± std per method) and
//! two figures (local φ and pore sizes, the first seed of each method overlaid).

use std::fmt::Write as _;
use std::path::Path;

use packbench_core::analysis::void_space::{ChordOptions, PoreOptions, chords, voronoi_and_pores};
use packbench_core::format::write_atomic;
use plotters::prelude::*;
use serde::Serialize;

use crate::error::BenchError;
use crate::figures::void_space::{
    VoidSpaceKind, VoidSpaceSeries, draw_void_space, pore_panels, voronoi_panels,
};
use crate::outputs::load_packing;
use crate::records::{RunsFile, mean_std};

/// One row of `pores.csv`. Lengths are in the packing's unit (diameters of spheres).
#[derive(Clone, Debug, Serialize)]
pub struct PoreRow {
    pub method: String,
    pub seed: u64,
    pub phi: f64,
    /// Mean and std of the per-particle local φ (radical Voronoi).
    pub local_phi_mean: f64,
    pub local_phi_std: f64,
    /// Voronoi cell volume std / mean, and entropy of v/⟨v⟩.
    pub volume_std_relative: f64,
    pub volume_entropy: f64,
    /// D_i and D_f.
    pub included_sphere_diameter: f64,
    pub free_sphere_diameter: Option<f64>,
    /// Volume-weighted mean pore diameter and mean throat diameter.
    pub pore_size_mean: f64,
    pub throat_size_mean: f64,
    /// Mean void chord and its stereological prediction 4(1 − φ)/s (periodic boxes).
    pub void_chord_mean: Option<f64>,
    pub void_chord_predicted: Option<f64>,
}

/// The columns of the report's table: header and value.
type Column = (&'static str, fn(&PoreRow) -> Option<f64>);
const COLUMNS: [Column; 8] = [
    ("φ", |r| Some(r.phi)),
    ("local φ std", |r| Some(r.local_phi_std)),
    ("σ_v/⟨v⟩", |r| Some(r.volume_std_relative)),
    ("S_v", |r| Some(r.volume_entropy)),
    ("D_i", |r| Some(r.included_sphere_diameter)),
    ("D_f", |r| r.free_sphere_diameter),
    ("⟨pore⟩", |r| Some(r.pore_size_mean)),
    ("⟨void chord⟩", |r| r.void_chord_mean),
];

/// Measures the void space of every saved packing of the comparison in `out`, writes
/// `pores.csv` and the figures, and appends the section to `report.md`.
///
/// Errors: a packing the void-space analysis refuses (its sentence, naming the run), or a
/// file that cannot be written.
pub fn write_pore_comparison(out: &Path, file: &RunsFile) -> Result<Vec<PoreRow>, BenchError> {
    let mut rows = Vec::new();
    let mut firsts: Vec<(String, [VoidSpaceSeries; 2])> = Vec::new();
    for rec in file.runs.iter().filter(|r| r.made_packing()) {
        let Some(p) = load_packing(out, &rec.method, rec.seed) else {
            continue;
        };
        let name = |e: packbench_core::CoreError| {
            let what = format!("{} seed {}", rec.method, rec.seed);
            match BenchError::from(e) {
                BenchError::Usage(m) => BenchError::Usage(format!("{what}: {m}")),
                BenchError::Run(m) => BenchError::Run(format!("{what}: {m}")),
            }
        };
        let (v, pr) = voronoi_and_pores(&p, &PoreOptions::default()).map_err(name)?;
        let ch = if p.container.is_fully_periodic() {
            Some(chords(&p, &ChordOptions::default()).map_err(name)?)
        } else {
            None
        };
        if !firsts.iter().any(|(m, _)| *m == rec.method) {
            let series = |panels| VoidSpaceSeries {
                name: rec.method.clone(),
                panels,
            };
            firsts.push((
                rec.method.clone(),
                [series(voronoi_panels(&v, &p)), series(pore_panels(&pr, &p))],
            ));
        }
        rows.push(PoreRow {
            method: rec.method.clone(),
            seed: rec.seed,
            phi: p.phi(),
            local_phi_mean: v.local_phi_mean,
            local_phi_std: v.local_phi_std,
            volume_std_relative: v.volume_std_relative,
            volume_entropy: v.volume_entropy,
            included_sphere_diameter: pr.included_sphere_diameter,
            free_sphere_diameter: pr.free_sphere_diameter,
            pore_size_mean: pr.pore_size_mean,
            throat_size_mean: pr.throat_size_mean,
            void_chord_mean: ch.as_ref().map(|c| c.void.mean),
            void_chord_predicted: ch.as_ref().map(|c| c.void_mean_predicted),
        });
    }
    let mut csv = csv::Writer::from_writer(Vec::new());
    for r in &rows {
        csv.serialize(r)
            .map_err(|e| BenchError::Run(format!("pores.csv: {e}")))?;
    }
    let bytes = csv
        .into_inner()
        .map_err(|e| BenchError::Run(format!("pores.csv: {e}")))?;
    write_atomic(&out.join("pores.csv"), &bytes)?;
    let figures = out.join("figures");
    std::fs::create_dir_all(&figures)
        .map_err(|e| BenchError::Run(format!("{}: {e}", figures.display())))?;
    for (k, (kind, stem)) in [
        (VoidSpaceKind::Voronoi, "void_space_local_phi"),
        (VoidSpaceKind::Pores, "void_space_pore_sizes"),
    ]
    .into_iter()
    .enumerate()
    {
        let series: Vec<VoidSpaceSeries> = firsts
            .iter()
            .map(|(_, s)| VoidSpaceSeries {
                name: s[k].name.clone(),
                panels: s[k].panels.clone(),
            })
            .collect();
        let path = figures.join(format!("{stem}.png"));
        let root = BitMapBackend::new(&path, (1100, 480)).into_drawing_area();
        draw_void_space(&root, kind, &series)
            .and_then(|_| Ok(root.present()?))
            .map_err(|e| BenchError::Run(format!("drawing {}: {e}", path.display())))?;
    }
    let report = out.join("report.md");
    let mut md = std::fs::read_to_string(&report).unwrap_or_default();
    md.push_str(&markdown(&rows));
    write_atomic(&report, md.as_bytes())?;
    Ok(rows)
}

/// The report section: mean ± std over seeds per method, then the figures.
pub fn markdown(rows: &[PoreRow]) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "\n## Void space\n\nRadical Voronoi cells (voro++), the Voronoi pore network and chord lengths of every packing (`pores.csv`; lengths in units of the sphere diameters' unit). σ_v/⟨v⟩: cell-volume std over mean; S_v: differential entropy of v/⟨v⟩ (bins of 0.01); D_i, D_f: largest included and free sphere; ⟨pore⟩: volume-weighted mean pore diameter.\n"
    );
    let _ = write!(md, "| method | runs |");
    for (h, _) in COLUMNS {
        let _ = write!(md, " {h} |");
    }
    let _ = write!(md, "\n|---|---|");
    for _ in COLUMNS {
        let _ = write!(md, "---|");
    }
    md.push('\n');
    let mut methods: Vec<&str> = Vec::new();
    for r in rows {
        if !methods.contains(&r.method.as_str()) {
            methods.push(&r.method);
        }
    }
    for m in methods {
        let of: Vec<&PoreRow> = rows.iter().filter(|r| r.method == m).collect();
        let _ = write!(md, "| {m} | {} |", of.len());
        for (_, f) in COLUMNS {
            let v: Vec<f64> = of.iter().filter_map(|&r| f(r)).collect();
            match mean_std(&v) {
                Some((mean, std)) if v.len() > 1 => {
                    let _ = write!(md, " {mean:.4} ± {std:.4} |");
                }
                Some((mean, _)) => {
                    let _ = write!(md, " {mean:.4} |");
                }
                None => {
                    let _ = write!(md, " – |");
                }
            }
        }
        md.push('\n');
    }
    let _ = writeln!(
        md,
        "\n![local φ](figures/void_space_local_phi.png)\n\nLocal φ distribution and local φ against diameter (first seed of each method).\n\n![pore sizes](figures/void_space_pore_sizes.png)\n\nVolume-weighted pore-size and throat-size distributions (first seed of each method)."
    );
    md
}
