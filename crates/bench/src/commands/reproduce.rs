//! `packbench reproduce NAME`: recomputes a published table with the protocol it names, at the
//! publication's N or a smaller `--N`, and writes the published and recomputed values side by
//! side; every run a row of `runs.csv` written as it finishes, `--resume` to continue a stopped
//! run, `--shard i/n` for pieces that `merge` joins.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use clap::Args;

use super::Printed;
use crate::args::BatchArgs;
use crate::error::{BenchError, usage};
use crate::records::parse_shard;
use crate::reproduce::rows::{
    Appender, REPRODUCE_JSON, ReproduceFile, ReproduceRow, csv_text, read_file, read_rows,
    write_file,
};
use crate::reproduce::{self, ReproduceConfig, check_cases, report, run_cases, run_list, tables};
use crate::shards::is_finished;

/// Flags of `packbench reproduce`.
#[derive(Args, Debug)]
#[command(
    after_help = "Tables (`--list` gives each one's source and protocol):\n  baranau2014-table3, \
baranau2014-table4  closest-jamming densities of log-normal spheres after fast LS compressions + \
MLS (N = 10⁴ published)\n  desmond-weeks-2014  φ_RCP against polydispersity and skewness: the \
published relation, `predict` and adam\n  dimensions          φ_J and z for d = 2 … 6 by adam \
(Skoge et al. 2006, O'Hern et al. 2003)\n  ohern-2003          φ_J and z at point J, 2D disks \
1:1.4 and 3D spheres, by adam\n  3drsp-2022          3DRSP Examples 1A/1B: spheres per unit cube \
by seq-fill (no --N)\nOutputs in --out: runs.csv (one row per run, written as it finishes), \
reproduce.json, report.md (published | recomputed mean ± standard error | Δ in standard errors), \
figures/reproduce.png and .svg. Example: packbench reproduce baranau2014-table4 --N 1000 --seeds 3 \
--jobs 2"
)]
pub struct ReproduceArgs {
    /// The table to recompute (see --list).
    pub name: Option<String>,
    /// List every table with its source, and exit.
    #[arg(long)]
    pub list: bool,
    /// Particles per packing (default: the publication's N, or 1000 where it gives none);
    /// at most the publication's N.
    #[arg(long = "N", alias = "n")]
    pub n: Option<usize>,
    /// Only these rows of the table, 1-based in its order (e.g. 1,7 for σ = 0 and 0.3).
    #[arg(long, value_delimiter = ',')]
    pub rows: Vec<usize>,
    /// Packings per case (seeds base, base+1, …).
    #[arg(long, default_value_t = 3)]
    pub seeds: u64,
    /// First seed.
    #[arg(long = "seed", default_value_t = 1)]
    pub base_seed: u64,
    /// Output folder.
    #[arg(long, default_value = "reproduce-out")]
    pub out: PathBuf,
    /// Run only the i-th of n slices of the runs (1-based, e.g. 2/8); join with `merge`.
    #[arg(long)]
    pub shard: Option<String>,
    /// Continue the run an earlier command left in --out: finished rows are kept, the rest run.
    #[arg(long)]
    pub resume: bool,
    #[command(flatten)]
    pub batch: BatchArgs,
}

/// `--list`: each table, its source and what is run.
fn listing() -> String {
    let mut s = String::new();
    for t in tables::TABLES {
        let n = match (t.published_n, t.default_n) {
            (Some(p), _) => format!("published N = {p}; --N up to it"),
            (None, Some(d)) => format!("default N = {d}"),
            (None, None) => "N fixed by the publication's domains".into(),
        };
        s.push_str(&format!(
            "{}\n  source:   {}\n  protocol: {}\n  size:     {n}\n",
            t.name, t.source, t.protocol
        ));
    }
    s
}

/// The finished rows an earlier run of the same reproduction and shard left in `out`.
///
/// Errors: a usage error when `out` holds another reproduction or shard, or unreadable rows.
fn resumed_rows(out: &Path, file: &ReproduceFile) -> Result<Vec<ReproduceRow>, BenchError> {
    if !out.join(REPRODUCE_JSON).exists() {
        return Ok(Vec::new());
    }
    if read_file(out)? != *file {
        return Err(usage(format!(
            "{} holds another reproduction or shard; --resume continues only the same one (same \
             table, --N, --rows, --seeds, --seed and --shard)",
            out.display()
        )));
    }
    Ok(read_rows(out)?
        .into_iter()
        .filter(|r| is_finished(&r.record))
        .collect())
}

/// The key of a row's run, `(case, seed)`.
fn key(r: &ReproduceRow) -> (String, u64) {
    (r.case.clone(), r.record.seed)
}

/// `rows` in the order of the run list of `cases`; rows of runs not in the list are dropped.
fn in_run_order(
    cases: &[reproduce::Case],
    config: &ReproduceConfig,
    rows: Vec<ReproduceRow>,
) -> Vec<ReproduceRow> {
    let mut by_key: BTreeMap<(String, u64), ReproduceRow> =
        rows.into_iter().map(|r| (key(&r), r)).collect();
    run_list(cases, config)
        .into_iter()
        .filter_map(|(_, c, seed)| by_key.remove(&(cases[c].label.clone(), seed)))
        .collect()
}

/// How many cells lie inside their bands, outside as expected, and otherwise.
fn verdict_counts(cells: &[report::CellResult]) -> String {
    let verdicts: Vec<report::Verdict> = cells.iter().filter_map(|c| c.verdict()).collect();
    let count = |v: report::Verdict| verdicts.iter().filter(|&&x| x == v).count();
    format!(
        "{} inside their published bands, {} outside as the published files expect, {} outside \
         unexpectedly, {} inside where a disagreement was expected",
        count(report::Verdict::Inside),
        count(report::Verdict::KnownOutside),
        count(report::Verdict::Outside),
        count(report::Verdict::UnexpectedlyInside),
    )
}

/// `packbench reproduce`.
pub fn run(args: &ReproduceArgs) -> Result<Printed, BenchError> {
    if args.list {
        return Ok(Printed {
            stdout: listing(),
            stderr: vec![],
        });
    }
    let name = args
        .name
        .as_deref()
        .ok_or_else(|| usage("give the name of a table to recompute, or --list to see them"))?;
    let table = reproduce::find(name)?;
    let n = table.n(args.n)?;
    if args.seeds == 0 {
        return Err(usage("--seeds must be at least 1"));
    }
    let config = ReproduceConfig {
        table: table.name.to_string(),
        n,
        seeds: args.seeds,
        base_seed: args.base_seed,
        rows: args.rows.clone(),
    };
    let cases = config.cases(table)?;
    check_cases(&cases)?;
    let shard = match &args.shard {
        Some(s) => parse_shard(s)?,
        None => (1, 1),
    };
    let file = ReproduceFile {
        config: config.clone(),
        shard,
    };
    if !args.resume && args.out.join(REPRODUCE_JSON).exists() {
        return Err(usage(format!(
            "{} already holds a reproduction: give --resume to continue it, or another --out",
            args.out.display()
        )));
    }
    let kept = if args.resume {
        in_run_order(&cases, &config, resumed_rows(&args.out, &file)?)
    } else {
        Vec::new()
    };
    let jobs = args.batch.jobs()?;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| BenchError::Run(format!("creating {}: {e}", args.out.display())))?;
    write_file(&args.out, &file)?;
    let appender = Appender::start(&args.out, &kept)?;
    crate::interrupt::install_interrupt_handler();
    let list: Vec<_> = run_list(&cases, &config)
        .into_iter()
        .filter(|(idx, _, _)| idx % shard.1 == shard.0 - 1)
        .filter(|(_, c, seed)| {
            !kept
                .iter()
                .any(|r| r.case == cases[*c].label && r.record.seed == *seed)
        })
        .collect();
    let progress = crate::progress::RunsProgress::new("reproduce", list.len(), args.batch.quiet);
    let new = run_cases(&cases, &config, &list, jobs, |row| {
        progress.done(&row.record);
        appender.append(row)
    })?;
    progress.finish();
    let kept_count = kept.len();
    let mut rows = kept;
    rows.extend(new.into_iter().map(|(_, r)| r));
    let rows = in_run_order(&cases, &config, rows);
    packbench_core::format::write_atomic(
        &args.out.join(crate::reproduce::rows::RUNS_CSV),
        &csv_text(&rows)?,
    )?;
    let cells = report::write_report(&args.out, table, &config, shard, &cases, &rows)?;
    let banded = verdict_counts(&cells);
    Ok(Printed {
        stdout: String::new(),
        stderr: vec![format!(
            "packbench reproduce {}: {} runs{}{}{}, {banded} -> {}/ (runs.csv, report.md, \
             figures/reproduce.png)",
            table.name,
            rows.len(),
            crate::shards::unfinished_note(rows.iter().map(|r| &r.record), "--resume"),
            if kept_count > 0 {
                format!(" ({kept_count} kept from the earlier run)")
            } else {
                String::new()
            },
            if shard.1 > 1 {
                format!(" (shard {}/{})", shard.0, shard.1)
            } else {
                String::new()
            },
            args.out.display()
        )],
    })
}

/// `packbench merge` of reproduction folders: joins the shards of one reproduction (and reruns
/// of some of its runs) into one folder. A finished row wins over a stopped or unstarted one;
/// two finished rows of one run must agree.
///
/// Errors: usage errors for folders of different reproductions, a run held by no folder, and
/// finished rows that disagree; run errors for outputs that cannot be written.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<Printed, BenchError> {
    let first = read_file(&dirs[0])?;
    let config = first.config;
    let table = reproduce::find(&config.table)?;
    let cases = config.cases(table)?;
    let mut chosen: BTreeMap<(String, u64), ReproduceRow> = BTreeMap::new();
    for d in dirs {
        if read_file(d)?.config != config {
            return Err(usage(format!(
                "{} and {} come from different reproductions (table, --N, --rows, --seeds or --seed differ)",
                dirs[0].display(),
                d.display()
            )));
        }
        for row in read_rows(d)? {
            let k = key(&row);
            match chosen.get(&k) {
                Some(held) if is_finished(&held.record) && is_finished(&row.record) => {
                    let (a, b) = (&held.record, &row.record);
                    if a.phi.map(f64::to_bits) != b.phi.map(f64::to_bits)
                        || a.refined_phi.map(f64::to_bits) != b.refined_phi.map(f64::to_bits)
                    {
                        return Err(usage(format!(
                            "{} holds a result for {} seed {} that differs from another folder's: \
                             the same run gives the same result, so they are not one reproduction",
                            d.display(),
                            k.0,
                            k.1
                        )));
                    }
                }
                Some(held) if is_finished(&held.record) => {}
                _ => {
                    chosen.insert(k, row);
                }
            }
        }
    }
    let rows = in_run_order(&cases, &config, chosen.into_values().collect());
    if let Some((_, c, seed)) = run_list(&cases, &config).into_iter().find(|(_, c, seed)| {
        !rows
            .iter()
            .any(|r| r.case == cases[*c].label && r.record.seed == *seed)
    }) {
        return Err(usage(format!(
            "no folder holds the run of {} seed {seed}: every shard of the reproduction is needed",
            cases[c].label
        )));
    }
    std::fs::create_dir_all(out)
        .map_err(|e| BenchError::Run(format!("creating {}: {e}", out.display())))?;
    write_file(
        out,
        &ReproduceFile {
            config: config.clone(),
            shard: (1, 1),
        },
    )?;
    packbench_core::format::write_atomic(
        &out.join(crate::reproduce::rows::RUNS_CSV),
        &csv_text(&rows)?,
    )?;
    report::write_report(out, table, &config, (1, 1), &cases, &rows)?;
    Ok(Printed {
        stdout: String::new(),
        stderr: vec![format!(
            "packbench merge: {} reproduction rows from {} folders -> {}/",
            rows.len(),
            dirs.len(),
            out.display()
        )],
    })
}
