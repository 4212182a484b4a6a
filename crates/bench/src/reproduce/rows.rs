//! The rows of a reproduction: `runs.csv`, one line per run — the case's label, then the
//! columns of `compare`'s runs.csv — appended as each run finishes and read back by `--resume`
//! and `merge`; and `reproduce.json`, the reproduction that made them.
//!
//! A row is tied to its run by `(case, seed)`, not by its place in the file, so rows appended
//! in any order (parallel runs) and rows of several folders (shards, reruns) join
//! unambiguously.

use std::io::Write;
use std::path::Path;
use std::sync::Mutex;

use serde::{Deserialize, Serialize};

use super::ReproduceConfig;
use crate::error::{BenchError, usage};
use crate::records::RunRecord;

/// Name of the rows file.
pub const RUNS_CSV: &str = "runs.csv";
/// Name of the reproduction's description.
pub const REPRODUCE_JSON: &str = "reproduce.json";

/// One run of a case.
#[derive(Clone, Debug, PartialEq)]
pub struct ReproduceRow {
    /// The case's label (`σ = 0.10`).
    pub case: String,
    /// The run's row as in `compare`'s runs.csv (its `runtime_s` is the first method's).
    pub record: RunRecord,
    /// Wall time of the whole run in seconds, the chained method (MLS after LS) included.
    pub total_s: f64,
}

/// The leading column of a line.
#[derive(Serialize)]
struct CaseColumn<'a> {
    case: &'a str,
}

/// The last column of a line.
#[derive(Serialize)]
struct TotalColumn {
    total_s: f64,
}

/// `reproduce.json`: the reproduction and the shard this folder holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReproduceFile {
    pub config: ReproduceConfig,
    /// `(i, n)`: shard i of n (`(1, 1)` for a whole run or a merge).
    pub shard: (usize, usize),
}

fn write_error(e: impl std::fmt::Display) -> BenchError {
    BenchError::Run(format!("writing {RUNS_CSV}: {e}"))
}

/// One line of `runs.csv` for `row`, preceded by the header when `header`.
fn line(row: &ReproduceRow, header: bool) -> Result<Vec<u8>, BenchError> {
    let mut w = csv::WriterBuilder::new()
        .has_headers(header)
        .from_writer(Vec::new());
    w.serialize((
        CaseColumn { case: &row.case },
        &row.record,
        TotalColumn {
            total_s: row.total_s,
        },
    ))
    .map_err(write_error)?;
    w.into_inner().map_err(write_error)
}

/// The header line of `runs.csv`.
fn header_line() -> Result<Vec<u8>, BenchError> {
    let empty = ReproduceRow {
        case: String::new(),
        record: RunRecord::default(),
        total_s: 0.0,
    };
    let both = line(&empty, true)?;
    let end = both
        .iter()
        .position(|&b| b == b'\n')
        .map_or(both.len(), |i| i + 1);
    Ok(both[..end].to_vec())
}

/// The whole of `runs.csv` for `rows`, in their order.
pub fn csv_text(rows: &[ReproduceRow]) -> Result<Vec<u8>, BenchError> {
    let mut out = header_line()?;
    for r in rows {
        out.extend(line(r, false)?);
    }
    Ok(out)
}

/// Reads `DIR/runs.csv` (no file: no rows). A last line without its newline was cut short by
/// an interrupted write and is dropped: that run runs again.
///
/// Errors: a usage error naming the file and line for a header or row that does not parse.
pub fn read_rows(dir: &Path) -> Result<Vec<ReproduceRow>, BenchError> {
    let path = dir.join(RUNS_CSV);
    let text = match std::fs::read(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(usage(format!("cannot read {}: {e}", path.display()))),
    };
    let bad = |line: usize, e: &dyn std::fmt::Display| {
        usage(format!("{} line {line}: {e}", path.display()))
    };
    let mut r = csv::ReaderBuilder::new()
        .flexible(true)
        .from_reader(text.as_slice());
    let head = r.headers().map_err(|e| bad(1, &e))?.clone();
    if head.get(0) != Some("case") {
        return Err(usage(format!(
            "{} is not the runs.csv of a reproduction (its first column is not `case`)",
            path.display()
        )));
    }
    let columns = head.len();
    if head.get(columns - 1) != Some("total_s") {
        return Err(usage(format!(
            "{} is not the runs.csv of a reproduction (its last column is not `total_s`)",
            path.display()
        )));
    }
    let record_header: csv::StringRecord = head.iter().skip(1).take(columns - 2).collect();
    let records: Vec<_> = r.records().collect();
    let last = records.len();
    let mut rows = Vec::with_capacity(last);
    for (i, rec) in records.into_iter().enumerate() {
        if !text.ends_with(b"\n") && i + 1 == last {
            break;
        }
        let rec = rec.map_err(|e| bad(i + 2, &e))?;
        if rec.len() != columns {
            return Err(bad(i + 2, &format!("{} columns, not {columns}", rec.len())));
        }
        let rest: csv::StringRecord = rec.iter().skip(1).take(columns - 2).collect();
        let record: RunRecord = rest
            .deserialize(Some(&record_header))
            .map_err(|e| bad(i + 2, &e))?;
        let total_s = rec
            .get(columns - 1)
            .and_then(|t| t.parse().ok())
            .ok_or_else(|| bad(i + 2, &"total_s is not a number"))?;
        rows.push(ReproduceRow {
            case: rec.get(0).unwrap_or_default().to_string(),
            record,
            total_s,
        });
    }
    Ok(rows)
}

/// Appends rows to `runs.csv` as they finish, one whole line per write, flushed: an
/// interrupted run loses at most the line being written.
pub struct Appender {
    file: Mutex<std::fs::File>,
}

impl Appender {
    /// Writes `DIR/runs.csv` afresh with `kept` (atomically), then opens it for appending.
    ///
    /// Errors: a run error when the file cannot be written.
    pub fn start(dir: &Path, kept: &[ReproduceRow]) -> Result<Appender, BenchError> {
        let path = dir.join(RUNS_CSV);
        packbench_core::format::write_atomic(&path, &csv_text(kept)?)?;
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(&path)
            .map_err(write_error)?;
        Ok(Appender {
            file: Mutex::new(file),
        })
    }

    /// Appends one row.
    ///
    /// Errors: a run error when the file cannot be written.
    pub fn append(&self, row: &ReproduceRow) -> Result<(), BenchError> {
        let bytes = line(row, false)?;
        let mut f = self.file.lock().map_err(write_error)?;
        f.write_all(&bytes)
            .and_then(|_| f.flush())
            .map_err(write_error)
    }
}

/// Reads `DIR/reproduce.json`.
///
/// Errors: a usage error naming the file when it cannot be read or parsed.
pub fn read_file(dir: &Path) -> Result<ReproduceFile, BenchError> {
    let path = dir.join(REPRODUCE_JSON);
    let text = std::fs::read_to_string(&path)
        .map_err(|e| usage(format!("cannot read {}: {e}", path.display())))?;
    serde_json::from_str(&text)
        .map_err(|e| usage(format!("{}: not a reproduce.json: {e}", path.display())))
}

/// Writes `DIR/reproduce.json` atomically.
///
/// Errors: a run error when it cannot be written.
pub fn write_file(dir: &Path, file: &ReproduceFile) -> Result<(), BenchError> {
    let json = serde_json::to_string_pretty(file).map_err(|e| BenchError::Run(e.to_string()))?;
    packbench_core::format::write_atomic(&dir.join(REPRODUCE_JSON), json.as_bytes())?;
    Ok(())
}

/// Whether `dir` holds a reproduction (its `reproduce.json`).
pub fn is_reproduce_dir(dir: &Path) -> bool {
    dir.join(REPRODUCE_JSON).is_file()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_round_trip_and_a_cut_last_line_is_dropped() {
        let dir = std::env::temp_dir().join(format!("packbench-rows-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let row = |case: &str, seed| ReproduceRow {
            case: case.into(),
            record: RunRecord {
                method: "ls".into(),
                seed,
                d: 3,
                n: 100,
                phi: Some(0.61),
                refined_phi: Some(0.64),
                termination: "pressure_cap".into(),
                ..RunRecord::default()
            },
            total_s: 2.5,
        };
        let rows = vec![row("σ = 0.00", 1), row("σ = 0.30, \"quoted\"", 2)];
        let w = Appender::start(&dir, &rows[..1]).unwrap();
        w.append(&rows[1]).unwrap();
        assert_eq!(read_rows(&dir).unwrap(), rows);
        let mut text = std::fs::read(dir.join(RUNS_CSV)).unwrap();
        text.pop();
        std::fs::write(dir.join(RUNS_CSV), &text).unwrap();
        assert_eq!(read_rows(&dir).unwrap(), rows[..1]);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
