//! The history of a design search: one row per evaluation (`evaluations.csv`), each a
//! comparison row of `runs.csv` ([`RunRecord`]) after the candidate's own columns, appended as
//! it finishes and read back by `--resume` and `merge`; and `design.json`, the search that
//! made them.
//!
//! A row is tied to its evaluation by `(kind, island, generation, candidate, seed)`, not by its
//! place in the file, so rows appended in any order (parallel runs) and rows of several folders
//! (islands, reruns) join unambiguously.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde::{Deserialize, Serialize};

use super::DesignConfig;
use super::family::Family;
use crate::error::{BenchError, usage};
use crate::records::RunRecord;

/// Name of the rows file in a design folder.
pub const EVALUATIONS: &str = "evaluations.csv";
/// Name of the search's description in a design folder.
pub const DESIGN_JSON: &str = "design.json";

/// `screened` of a candidate that was packed.
pub const PACKED: &str = "";
/// `screened` of a candidate skipped on its predicted φ_J.
pub const SKIPPED_PREDICTED: &str = "predicted";
/// `screened` of a candidate whose diameters break `--max-ratio`.
pub const SKIPPED_RATIO: &str = "ratio";
/// `screened` of a candidate whose values make no distribution (scored infeasible; the row's
/// `error` says why).
pub const INVALID: &str = "invalid";

/// Termination in the run columns of a row whose candidate was not packed.
pub const NOT_PACKED: &str = "screened_out";

/// What an evaluation was part of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RowKind {
    /// A packing of a candidate during the search.
    Search,
    /// A confirmation rerun of the best candidate with a fresh seed.
    Confirm,
}

/// One evaluation: a candidate (its generation, index and parameter values), what was known
/// of it before packing (size measures, predictions, the screen's verdict) and the packing's
/// row as in `compare`'s runs.csv.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignRow {
    pub kind: RowKind,
    /// The search (1 unless split into islands with `--shard i/n`).
    pub island: usize,
    /// Generation of the optimiser, from 0.
    pub generation: usize,
    /// Index of the candidate in its generation.
    pub candidate: usize,
    /// Every parameter of the family, in its order.
    pub params: Vec<f64>,
    /// D_max / D_min of the candidate's diameters at this seed.
    pub size_ratio: f64,
    /// std / mean of the candidate's diameters at this seed.
    pub polydispersity: f64,
    /// Desmond–Weeks φ_RCP of the diameters (3D only).
    pub predicted_dw: Option<f64>,
    /// Farr–Groot φ_RCP of the diameters (3D only).
    pub predicted_fg: Option<f64>,
    /// Why the candidate was not packed ([`SKIPPED_PREDICTED`], [`SKIPPED_RATIO`],
    /// [`INVALID`]), or empty.
    pub screened: String,
    /// The packing's row (`termination = screened_out` and no φ when it was not packed).
    pub record: RunRecord,
}

/// The identity of a row's evaluation.
pub type RowKey = (RowKind, usize, usize, usize, u64);

impl DesignRow {
    /// `(kind, island, generation, candidate, seed)`.
    pub fn key(&self) -> RowKey {
        (
            self.kind,
            self.island,
            self.generation,
            self.candidate,
            self.record.seed,
        )
    }

    /// φ_J of the row: φ after `--refine` when the search refines, else φ; `None` when the
    /// run made no packing.
    pub fn phi_j(&self, refined: bool) -> Option<f64> {
        if !self.record.made_packing() {
            return None;
        }
        if refined {
            self.record.refined_phi
        } else {
            self.record.phi
        }
    }
}

/// `design.json`: the search and the island this folder holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignFile {
    pub config: DesignConfig,
    /// `(i, n)`: island i of n (`(1, 1)` for a whole search or a merge).
    pub shard: (usize, usize),
}

/// The column names of [`RunRecord`] in runs.csv.
fn record_header() -> Vec<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    // Serialising a plain struct into memory cannot fail.
    let _ = w.serialize(RunRecord::default());
    let bytes = w.into_inner().unwrap_or_default();
    let mut r = csv::Reader::from_reader(bytes.as_slice());
    r.headers()
        .map(|h| h.iter().map(str::to_string).collect())
        .unwrap_or_default()
}

/// The header of `evaluations.csv` for `family`.
pub fn header(family: &Family) -> Vec<String> {
    let mut h: Vec<String> = ["kind", "island", "generation", "candidate"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    h.extend(family.params.iter().map(|p| p.name.clone()));
    h.extend(
        [
            "size_ratio",
            "polydispersity",
            "predicted_dw",
            "predicted_fg",
            "screened",
        ]
        .iter()
        .map(|s| s.to_string()),
    );
    h.extend(record_header());
    h
}

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |x| x.to_string())
}

/// The fields of `row` in the order of [`header`].
fn fields(row: &DesignRow) -> Result<Vec<String>, BenchError> {
    let mut f = vec![
        match row.kind {
            RowKind::Search => "search".to_string(),
            RowKind::Confirm => "confirm".to_string(),
        },
        row.island.to_string(),
        row.generation.to_string(),
        row.candidate.to_string(),
    ];
    f.extend(row.params.iter().map(|v| v.to_string()));
    f.push(row.size_ratio.to_string());
    f.push(row.polydispersity.to_string());
    f.push(opt(row.predicted_dw));
    f.push(opt(row.predicted_fg));
    f.push(row.screened.clone());
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    w.serialize(&row.record)
        .map_err(|e| BenchError::Run(format!("writing a row: {e}")))?;
    let bytes = w
        .into_inner()
        .map_err(|e| BenchError::Run(format!("writing a row: {e}")))?;
    let mut r = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(bytes.as_slice());
    if let Some(rec) = r.records().next() {
        let rec = rec.map_err(|e| BenchError::Run(format!("writing a row: {e}")))?;
        f.extend(rec.iter().map(str::to_string));
    }
    Ok(f)
}

/// One CSV line (with its newline) for `cells`.
fn line(cells: &[String]) -> Result<Vec<u8>, BenchError> {
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    w.write_record(cells)
        .map_err(|e| BenchError::Run(format!("writing a row: {e}")))?;
    w.into_inner()
        .map_err(|e| BenchError::Run(format!("writing a row: {e}")))
}

/// The whole file for `rows`, header first, rows in key order.
pub fn csv_text(family: &Family, rows: &[DesignRow]) -> Result<Vec<u8>, BenchError> {
    let mut sorted: Vec<&DesignRow> = rows.iter().collect();
    sorted.sort_by_key(|r| r.key());
    let mut out = line(&header(family))?;
    for r in sorted {
        out.extend(line(&fields(r)?)?);
    }
    Ok(out)
}

/// Parses one data line of `evaluations.csv`.
fn parse_row(
    family: &Family,
    record_header: &csv::StringRecord,
    rec: &csv::StringRecord,
) -> Result<DesignRow, String> {
    let k = family.params.len();
    let get = |i: usize| {
        rec.get(i)
            .ok_or_else(|| format!("column {} missing", i + 1))
    };
    let num = |i: usize| -> Result<f64, String> {
        get(i)?
            .parse::<f64>()
            .map_err(|_| format!("column {} is not a number", i + 1))
    };
    let int = |i: usize| -> Result<usize, String> {
        get(i)?
            .parse::<usize>()
            .map_err(|_| format!("column {} is not a count", i + 1))
    };
    let optnum = |i: usize| -> Result<Option<f64>, String> {
        let s = get(i)?;
        if s.is_empty() {
            Ok(None)
        } else {
            num(i).map(Some)
        }
    };
    let kind = match get(0)? {
        "search" => RowKind::Search,
        "confirm" => RowKind::Confirm,
        other => return Err(format!("kind `{other}` is neither search nor confirm")),
    };
    let params = (0..k).map(|j| num(4 + j)).collect::<Result<Vec<_>, _>>()?;
    let o = 4 + k;
    let rest = csv::StringRecord::from(rec.iter().skip(o + 5).collect::<Vec<_>>());
    let record: RunRecord = rest
        .deserialize(Some(record_header))
        .map_err(|e| format!("run columns: {e}"))?;
    Ok(DesignRow {
        kind,
        island: int(1)?,
        generation: int(2)?,
        candidate: int(3)?,
        params,
        size_ratio: num(o)?,
        polydispersity: num(o + 1)?,
        predicted_dw: optnum(o + 2)?,
        predicted_fg: optnum(o + 3)?,
        screened: get(o + 4)?.to_string(),
        record,
    })
}

/// Reads `DIR/evaluations.csv` (no file: no rows). A last line without its newline was cut
/// short by an interrupted write and is dropped: that evaluation runs again.
///
/// Errors: a usage error naming the file and line for a header of another family or a row that
/// does not parse (other than a cut last line).
pub fn read_rows(dir: &Path, family: &Family) -> Result<Vec<DesignRow>, BenchError> {
    let path = dir.join(EVALUATIONS);
    let text = match std::fs::read(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(usage(format!("cannot read {}: {e}", path.display()))),
    };
    let cut_last_line = !text.ends_with(b"\n");
    let mut r = csv::ReaderBuilder::new()
        .flexible(true)
        .from_reader(text.as_slice());
    let head: Vec<String> = r
        .headers()
        .map_err(|e| usage(format!("{}: {e}", path.display())))?
        .iter()
        .map(str::to_string)
        .collect();
    if head != header(family) {
        return Err(usage(format!(
            "{} has the columns of another search (its header differs from the {} family's)",
            path.display(),
            family.name()
        )));
    }
    let rh = csv::StringRecord::from(record_header());
    let records: Vec<_> = r.records().collect();
    let last = records.len();
    let mut rows = Vec::with_capacity(last);
    for (i, rec) in records.into_iter().enumerate() {
        if cut_last_line && i + 1 == last {
            // Written without its newline: the write was interrupted, whatever it parses as.
            break;
        }
        let parsed = rec.map_err(|e| e.to_string()).and_then(|rec| {
            if rec.len() == head.len() {
                parse_row(family, &rh, &rec)
            } else {
                Err(format!("{} columns, not {}", rec.len(), head.len()))
            }
        });
        match parsed {
            Ok(row) => rows.push(row),
            Err(e) => {
                return Err(usage(format!("{} line {}: {e}", path.display(), i + 2)));
            }
        }
    }
    Ok(rows)
}

/// Appends rows to `evaluations.csv` as they finish, one whole line per write, flushed: an
/// interrupted search loses at most the line being written.
pub struct RowWriter {
    file: Mutex<std::fs::File>,
    path: PathBuf,
}

impl RowWriter {
    /// Starts `DIR/evaluations.csv` afresh with `rows` (those kept by `--resume`, in key order),
    /// written whole and atomically, then opened for appending.
    ///
    /// Errors: a run error when the folder or file cannot be written.
    pub fn start(dir: &Path, family: &Family, rows: &[DesignRow]) -> Result<RowWriter, BenchError> {
        let path = dir.join(EVALUATIONS);
        packbench_core::format::write_atomic(&path, &csv_text(family, rows)?)?;
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(&path)
            .map_err(|e| BenchError::Run(format!("cannot open {}: {e}", path.display())))?;
        Ok(RowWriter {
            file: Mutex::new(file),
            path,
        })
    }

    /// Appends one row.
    ///
    /// Errors: a run error when the file cannot be written.
    pub fn append(&self, row: &DesignRow) -> Result<(), BenchError> {
        let bytes = line(&fields(row)?)?;
        let mut f = self
            .file
            .lock()
            .map_err(|_| BenchError::Run("row writer poisoned".into()))?;
        f.write_all(&bytes)
            .and_then(|_| f.flush())
            .map_err(|e| BenchError::Run(format!("cannot write {}: {e}", self.path.display())))
    }
}

/// Rows by key; where two rows have one key the later wins.
pub fn by_key(rows: Vec<DesignRow>) -> BTreeMap<RowKey, DesignRow> {
    rows.into_iter().map(|r| (r.key(), r)).collect()
}

/// Reads `DIR/design.json`.
///
/// Errors: a usage error naming the file when it cannot be read or parsed.
pub fn read_design_file(dir: &Path) -> Result<DesignFile, BenchError> {
    let path = dir.join(DESIGN_JSON);
    let text = std::fs::read_to_string(&path)
        .map_err(|e| usage(format!("cannot read {}: {e}", path.display())))?;
    serde_json::from_str(&text)
        .map_err(|e| usage(format!("{}: not a design.json: {e}", path.display())))
}

/// Writes `DIR/design.json` atomically.
///
/// Errors: a run error when it cannot be written.
pub fn write_design_file(dir: &Path, file: &DesignFile) -> Result<(), BenchError> {
    let json = serde_json::to_string_pretty(file).map_err(|e| BenchError::Run(e.to_string()))?;
    packbench_core::format::write_atomic(&dir.join(DESIGN_JSON), json.as_bytes())?;
    Ok(())
}

/// Whether `dir` holds a design search (its `design.json`).
pub fn is_design_dir(dir: &Path) -> bool {
    dir.join(DESIGN_JSON).is_file()
}
