//! Shards on a cluster without the cluster: `compare --resume-missing` finishes what a stopped
//! shard left and keeps what it finished, and `merge` takes reruns of some runs.
//! (`tests/slurm/run.sh` runs the same under a real Slurm.)

use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
use common::packbench;
use packbench::records::{RunRecord, RunsFile};

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("packbench-shards-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let d = dir.join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// `packbench compare` of a small 2D comparison (2 methods × 3 seeds) into `out`.
fn run_compare(out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "compare",
        "--N",
        "20",
        "--Ndim",
        "2",
        "--seeds",
        "3",
        "--methods",
        "fire,ls",
        "--jobs",
        "1",
        "--quiet",
        "--out",
    ];
    args.push(out.to_str().unwrap());
    args.extend_from_slice(extra);
    packbench(&args)
}

/// [`run_compare`], which must succeed; its stderr.
fn compare(out: &Path, extra: &[&str]) -> String {
    let o = run_compare(out, extra);
    let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{stderr}");
    stderr
}

fn read(dir: &Path) -> RunsFile {
    serde_json::from_str(&std::fs::read_to_string(dir.join("runs.json")).unwrap()).unwrap()
}

fn write(dir: &Path, f: &RunsFile) {
    std::fs::write(dir.join("runs.json"), serde_json::to_string(f).unwrap()).unwrap();
}

/// Rows with the runtime zeroed (the one column a rerun may change).
fn without_runtime(rows: &[RunRecord]) -> Vec<RunRecord> {
    rows.iter()
        .map(|r| RunRecord {
            runtime_s: 0.0,
            ..r.clone()
        })
        .collect()
}

/// Marks row `i` as a time limit leaves it: stopped with a packing of lower φ, or never started.
fn stop(f: &mut RunsFile, i: usize, termination: &str) {
    let r = &mut f.runs[i];
    r.termination = termination.into();
    r.phi = (termination == "interrupted").then_some(0.5);
    r.runtime_s = 0.0;
}

fn packing_of(dir: &Path, r: &RunRecord) -> PathBuf {
    dir.join("packings")
        .join(format!("{}_seed{}.txt", r.method, r.seed))
}

#[test]
fn resume_missing_reruns_only_the_stopped_runs_and_keeps_the_finished_ones() {
    let whole = tmp("whole");
    compare(&whole, &[]);
    let reference = read(&whole);

    // Shard 2/2 as a time limit leaves it: its first run finished (runtime marked so that a
    // rerun would show), the second stopped with a worse packing, the third never started.
    let shard = tmp("shard2");
    compare(&shard, &["--shard", "2/2"]);
    let mut f = read(&shard);
    assert_eq!(f.runs.len(), 3);
    f.runs[0].runtime_s = 12345.0;
    stop(&mut f, 1, "interrupted");
    stop(&mut f, 2, "not_run");
    std::fs::write(packing_of(&shard, &f.runs[1]), "stale").unwrap();
    std::fs::remove_file(packing_of(&shard, &f.runs[2])).unwrap();
    write(&shard, &f);

    let said = compare(&shard, &["--shard", "2/2", "--resume-missing"]);
    assert!(
        said.contains("3 runs (1 kept from the earlier run)"),
        "{said}"
    );
    let done = read(&shard);
    assert_eq!(
        done.runs[0].runtime_s, 12345.0,
        "a finished run was run again"
    );
    // The reruns give what the whole comparison gave for the same runs (odd run indices).
    let odd: Vec<RunRecord> = reference.runs.iter().skip(1).step_by(2).cloned().collect();
    assert_eq!(without_runtime(&done.runs), without_runtime(&odd));
    for r in &done.runs {
        let text = std::fs::read_to_string(packing_of(&shard, r)).unwrap();
        assert!(text.lines().count() >= 20, "{}: {text}", r.method);
    }

    // Nothing left to do: every row is kept, nothing runs.
    let said = compare(&shard, &["--shard", "2/2", "--resume-missing"]);
    assert!(said.contains("(3 kept from the earlier run)"), "{said}");
    assert_eq!(read(&shard).runs, done.runs);

    // A folder without runs.json (a job killed before writing it) is a fresh start.
    let fresh = tmp("fresh");
    let said = compare(&fresh, &["--shard", "1/2", "--resume-missing"]);
    assert!(said.contains("(0 kept from the earlier run)"), "{said}");
    assert_eq!(read(&fresh).runs.len(), 3);
}

#[test]
fn resume_missing_refuses_a_folder_of_another_comparison_or_shard() {
    let shard = tmp("other");
    compare(&shard, &["--shard", "1/2"]);
    for extra in [
        ["--shard", "2/2", "--resume-missing", "--seed", "1"],
        ["--shard", "1/2", "--resume-missing", "--seed", "5"],
    ] {
        let o = run_compare(&shard, &extra);
        assert_eq!(o.status.code(), Some(2), "{extra:?}");
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(
            e.contains("--resume-missing continues only the same one"),
            "{e}"
        );
    }
}

#[test]
fn merge_takes_the_rerun_of_a_stopped_run_and_refuses_disagreeing_results() {
    let whole = tmp("m_whole");
    compare(&whole, &[]);
    let (s1, s2) = (tmp("m_s1"), tmp("m_s2"));
    compare(&s1, &["--shard", "1/2"]);
    compare(&s2, &["--shard", "2/2"]);

    // Shard 1 stopped by a time limit, and a rerun of that shard in another folder.
    let stopped = tmp("m_stopped");
    compare(&stopped, &["--shard", "1/2"]);
    let mut f = read(&stopped);
    stop(&mut f, 1, "interrupted");
    stop(&mut f, 2, "not_run");
    write(&stopped, &f);

    let merged = tmp("m_merged");
    let dirs = |ds: &[&Path]| -> Vec<String> {
        ds.iter().map(|d| d.to_str().unwrap().to_string()).collect()
    };
    let run_merge = |ds: &[&Path]| {
        let mut args = vec!["merge".to_string()];
        args.extend(dirs(ds));
        args.extend(["--out".to_string(), merged.to_str().unwrap().to_string()]);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        packbench(&args)
    };

    // The stopped shard alone leaves its unfinished rows, and says so.
    let o = run_merge(&[&stopped, &s2]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("2 run(s) unfinished"));
    let rows = read(&merged).runs;
    assert_eq!(rows[2].termination, "interrupted");
    assert_eq!(rows[4].termination, "not_run");

    // With the rerun (in either order) the merge is the whole comparison.
    for order in [[stopped.as_path(), &s1, &s2], [s1.as_path(), &stopped, &s2]] {
        let o = run_merge(&order);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{stderr}");
        assert!(!stderr.contains("unfinished"), "{stderr}");
        assert_eq!(
            without_runtime(&read(&merged).runs),
            without_runtime(&read(&whole).runs)
        );
        assert!(packing_of(&merged, &read(&merged).runs[4]).exists());
    }

    // A run missing from every folder, or two finished results that differ, are refused.
    let o = run_merge(&[&s1]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no folder holds the run"));
    let forged = tmp("m_forged");
    compare(&forged, &["--shard", "2/2"]);
    let mut f = read(&forged);
    f.runs[0].phi = f.runs[0].phi.map(|p| p + 1e-12);
    write(&forged, &f);
    let o = run_merge(&[&s1, &s2, &forged]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("hold different results"));
}
