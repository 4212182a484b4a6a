//! Tests of the comparison side (issue "bench"): the registry, runs.csv, shards and failures.

use std::process::{Command, Output};

mod common;
use common::packbench;

fn tmp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("packbench-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

const DOCUMENTED: &str = "method,seed,d,n,phi,z_nonrattler,rattlers,iso_gap,isostatic,max_overlap,force_balance,runtime_s,steps,termination";

#[test]
fn every_registered_method_is_consistent() {
    let registry = packbench::methods::registry();
    let mut names: Vec<&str> = registry.iter().map(|m| m.name()).collect();
    assert!(names.contains(&"adam"), "{names:?}");
    names.sort();
    names.dedup();
    assert_eq!(names.len(), registry.len(), "method names are unique");
    for m in &registry {
        let params = m.default_params();
        let knob = m.accuracy_knob();
        assert!(
            params.contains_key(knob),
            "{}: knob {knob} is not a parameter",
            m.name()
        );
        for f in m.flags() {
            match f.value {
                packbench::methods::FlagValue::RunsVariant(v) => {
                    assert!(packbench::methods::find(v).is_ok(), "--{} runs {v}", f.name)
                }
                _ => assert!(
                    params.contains_key(f.key),
                    "{}: --{} sets {}, which is not a parameter",
                    m.name(),
                    f.name,
                    f.key
                ),
            }
        }
    }
    let e = packbench::methods::find("nope").err().unwrap().to_string();
    assert!(e.contains("unknown method `nope`"), "{e}");
}

fn compare(out: &std::path::Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "compare",
        "--N",
        "24",
        "--Ndim",
        "2",
        "--seeds",
        "2",
        "--methods",
        "fire,ls",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    packbench(&args)
}

/// Rows without the runtime column.
fn rows_without_runtime(csv_text: &str) -> Vec<Vec<String>> {
    let mut r = csv::Reader::from_reader(csv_text.as_bytes());
    let headers = r.headers().unwrap().clone();
    let rt = headers.iter().position(|h| h == "runtime_s").unwrap();
    r.records()
        .map(|rec| {
            rec.unwrap()
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != rt)
                .map(|(_, v)| v.to_string())
                .collect()
        })
        .collect()
}

#[test]
fn runs_csv_has_the_documented_columns_and_merged_shards_equal_the_whole_run() {
    let whole = tmp("whole");
    let o = compare(&whole, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv_whole = std::fs::read_to_string(whole.join("runs.csv")).unwrap();
    assert!(csv_whole.starts_with(DOCUMENTED), "{csv_whole}");
    assert_eq!(csv_whole.lines().count(), 1 + 4);
    for f in [
        "runs.json",
        "report.md",
        "figures/phi_by_method.png",
        "figures/runtime_vs_phi.svg",
        "figures/packing_fire.png",
    ] {
        assert!(whole.join(f).exists(), "{f} missing");
    }
    let (s1, s2, merged) = (tmp("s1"), tmp("s2"), tmp("merged"));
    assert!(compare(&s1, &["--shard", "1/2"]).status.success());
    assert!(compare(&s2, &["--shard", "2/2"]).status.success());
    let o = packbench(&[
        "merge",
        s2.to_str().unwrap(),
        s1.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv_merged = std::fs::read_to_string(merged.join("runs.csv")).unwrap();
    assert_eq!(
        rows_without_runtime(&csv_whole),
        rows_without_runtime(&csv_merged)
    );
    assert!(merged.join("figures/packing_ls.png").exists());
    let o = packbench(&[
        "merge",
        s1.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn a_failing_method_is_a_failed_row_and_the_others_go_on() {
    let out = tmp("failing");
    let o = packbench(&[
        "compare",
        "--N",
        "24",
        "--Ndim",
        "2",
        "--seeds",
        "2",
        "--box",
        "1,1",
        "--walls",
        "-2,0",
        "--methods",
        "ls,fire",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut r = csv::Reader::from_path(out.join("runs.csv")).unwrap();
    let error = r
        .headers()
        .unwrap()
        .iter()
        .position(|h| h == "error")
        .unwrap();
    let rows: Vec<csv::StringRecord> = r.records().map(|x| x.unwrap()).collect();
    assert_eq!(rows.len(), 4);
    for row in &rows {
        match &row[0] {
            // LS models flat walls only: it fails in a circle, as a row of its own.
            "ls" => {
                assert_eq!(&row[13], "failed");
                assert!(!row[error].is_empty(), "the error column names the reason");
            }
            "fire" => assert!(
                row[4].parse::<f64>().unwrap() > 0.7,
                "fire still packs: {row:?}"
            ),
            other => panic!("unexpected method {other}"),
        }
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("**ls**: 2 run(s) failed"), "{report}");
}

/// Whether process `pid` has installed a SIGINT handler (bit 2 of SigCgt in /proc).
fn catches_sigint(pid: u32) -> bool {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("SigCgt:"))
        .and_then(|m| u64::from_str_radix(m.trim(), 16).ok())
        .is_some_and(|mask| mask & 0b10 != 0)
}

#[test]
fn an_interrupted_compare_records_unstarted_runs_as_not_run() {
    let out = tmp("interrupted");
    let mut child = common::spawn_packbench(
        "compare --N 100 --Ndim 3 --seeds 3 --methods mls --set mls.rate_final=1e-12 \
         --jobs 1 --quiet --out",
        out.to_str().unwrap(),
    );
    let waited = std::time::Instant::now();
    while !catches_sigint(child.id()) {
        assert!(child.try_wait().unwrap().is_none(), "compare ended early");
        assert!(waited.elapsed().as_secs() < 60, "no SIGINT handler");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    // The handler is installed just before the first run starts; the run is under way once
    // the process has worked for half a second of CPU (its set-up takes milliseconds).
    common::wait_for_cpu(&mut child, 0.5);
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    assert!(kill.expect("kill runs").success());
    let o = child.wait_with_output().expect("waits");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut r = csv::Reader::from_path(out.join("runs.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let col = |name: &str| h.iter().position(|x| x == name).unwrap();
    let (term, phi, error) = (col("termination"), col("phi"), col("error"));
    let rows: Vec<csv::StringRecord> = r.records().map(|x| x.unwrap()).collect();
    assert_eq!(rows.len(), 3);
    // The run under way stops with its packing so far; the two after it never start.
    assert_eq!(&rows[0][term], "interrupted");
    assert!(rows[0][phi].parse::<f64>().unwrap() > 0.0);
    for row in &rows[1..] {
        assert_eq!(&row[term], "not_run", "{row:?}");
        assert!(row[phi].is_empty() && row[error].contains("interrupted"));
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("**mls**: 2 run(s) not run"), "{report}");
    // The last line says so too, and how to go on.
    let said = String::from_utf8_lossy(&o.stderr);
    assert!(
        said.contains("3 of them interrupted or not run (continue with --resume-missing)"),
        "{said}"
    );
}

#[test]
fn sweep_writes_its_table_and_pareto_figure() {
    let out = tmp("sweep");
    let o = packbench(&[
        "sweep",
        "--method",
        "fire",
        "--values",
        "1e-3,1e-5",
        "--N",
        "24",
        "--Ndim",
        "2",
        "--seeds",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.join("figures/pareto.png").exists());
    let csv_text = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert_eq!(csv_text.lines().count(), 3);
    let bad = packbench(&[
        "sweep",
        "--method",
        "fire",
        "--knob",
        "nope",
        "--values",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(bad.status.code(), Some(2));
}

/// 30 disks placed overlapping at φ = 0.8 (random sequential addition, the default
/// placement, refuses a φ that high): five steps cannot relax their overlaps.
const CROWDED_START: &[&str] = &[
    "--N",
    "30",
    "--Ndim",
    "2",
    "--phi",
    "0.8",
    "--placement",
    "random",
];

/// A run that ends at its step budget with overlaps above 1e-3 made no packing: the sweep's
/// table counts it as failed (a start at φ = 0.8 cannot be relaxed in five steps).
#[test]
fn sweep_counts_runs_left_overlapping_at_their_budget_as_failed() {
    let out = tmp("sweep_failed");
    let o = packbench(
        &[
            &["sweep", "--method", "adam", "--values", "1e-3,1e-4"],
            CROWDED_START,
            &["--seeds", "1", "--set", "max_steps=5", "--quiet"],
            &["--out", out.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(out.join("sweep.md")).unwrap();
    let rows: Vec<&str> = md.lines().filter(|l| l.starts_with("| 1e-")).collect();
    assert_eq!(rows.len(), 2, "{md}");
    for row in rows {
        assert!(row.ends_with("| 1 |"), "{row}");
    }
    let csv_text = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert_eq!(
        csv_text.matches("max_steps_with_overlaps").count(),
        2,
        "{csv_text}"
    );
}

/// compare's report counts the same runs as failed as sweep does: a run left at its step
/// budget with overlaps has a packing file but made no packing, and its φ enters no mean.
#[test]
fn compare_counts_runs_left_overlapping_at_their_budget_as_failed() {
    let out = tmp("compare_failed");
    let o = packbench(
        &[
            &["compare", "--methods", "adam,fire"],
            CROWDED_START,
            &[
                "--seeds",
                "2",
                "--set",
                "adam.max_steps=5",
                "--jobs",
                "1",
                "--quiet",
            ],
            &["--out", out.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv_text = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    assert_eq!(
        csv_text.matches("max_steps_with_overlaps").count(),
        2,
        "{csv_text}"
    );
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    // Cells of a method's row: method, N (none packed: "—"), runs, failed, then φ.
    let cells = |m: &str| -> Vec<String> {
        let line = report.lines().find(|l| l.starts_with(&format!("| {m} |")));
        let line = line.unwrap_or_else(|| panic!("no {m} row in {report}"));
        line.split('|').map(|c| c.trim().to_string()).collect()
    };
    let adam = cells("adam");
    // No mean of packings that were not made.
    assert_eq!(&adam[2..6], ["—", "2", "2", "—"], "{adam:?}");
    let fire = cells("fire");
    assert_eq!(&fire[3..5], ["2", "0"], "{fire:?}");
    assert!(fire[5].starts_with("0."), "{fire:?}");
    assert!(report.contains("**adam**: 2 run(s) failed"), "{report}");
}

/// `sweep --method ls --refine mls` (Baranau & Tallarek 2014 Fig. 2a–b): every LS packing is carried on by
/// MLS, which only grows the spheres, so φ after MLS is never below the LS φ; the rate axis is
/// drawn as 1/γ.
#[test]
fn sweep_refines_each_ls_packing_with_mls() {
    let out = tmp("sweep_refine");
    let o = packbench(&[
        "sweep",
        "--method",
        "ls",
        "--values",
        "10,0.1",
        "--refine",
        "mls",
        "--N",
        "30",
        "--Ndim",
        "2",
        "--seeds",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    let log = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{log}");
    // stderr is a pipe here, as in a batch job: one line per finished run instead of a bar.
    assert!(
        log.contains("sweep run 1/2: ls at ") && log.contains("sweep run 2/2: ls at "),
        "{log}"
    );
    let mut rows = csv::Reader::from_path(out.join("sweep.csv")).unwrap();
    let header = rows.headers().unwrap().clone();
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (phi, refined) = (col("phi"), col("refined_phi"));
    let (why, gap) = (col("refined_termination"), col("refined_iso_gap"));
    let mut n = 0;
    for r in rows.records() {
        let r = r.unwrap();
        let (a, b): (f64, f64) = (r[phi].parse().unwrap(), r[refined].parse().unwrap());
        assert!(b >= a - 1e-12, "LS φ {a}, after MLS {b}");
        // Thirty equal disks, this sweep over seeds 1–5: LS 0.800–0.838, after MLS 0.821–0.845
        // with iso_gap 0 or −1 (MLS ends nearly isostatic).
        assert!((0.78..0.86).contains(&a), "LS φ {a}");
        assert!((0.80..0.87).contains(&b), "φ after MLS {b}");
        // The refiner's own stop reason and the core's analysis of its packing are recorded.
        assert!(!r[why].is_empty() && r[why] != *"failed", "{r:?}");
        let iso_gap: i64 = r[gap].parse().unwrap();
        assert!(
            (-1..=0).contains(&iso_gap),
            "iso_gap after MLS {iso_gap}: {r:?}"
        );
        n += 1;
    }
    assert_eq!(n, 2);
    let md = std::fs::read_to_string(out.join("sweep.md")).unwrap();
    assert!(
        md.contains("φ after mls") && md.contains("against 1/γ"),
        "{md}"
    );
}

/// `compare --refine exact` at small N is ADAM → calippso: every row names the chain, the
/// refined packing is exactly jammed by the core's analysis, and the report says which chain
/// ran and how long it took.
#[test]
fn compare_refine_exact_names_the_chain_it_ran() {
    let out = tmp("compare_refine_exact");
    let o = packbench(&[
        "compare",
        "--methods",
        "adam",
        "--refine",
        "exact",
        "--N",
        "30",
        "--Ndim",
        "2",
        "--seeds",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut rows = csv::Reader::from_path(out.join("runs.csv")).unwrap();
    let header = rows.headers().unwrap().clone();
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (by, gap, fb) = (
        col("refined_by"),
        col("refined_iso_gap"),
        col("refined_force_balance"),
    );
    let (seconds, why) = (col("refined_runtime_s"), col("refined_termination"));
    let mut n = 0;
    for r in rows.records() {
        let r = r.unwrap();
        assert_eq!(&r[by], "calippso", "{r:?}");
        assert_eq!(&r[why], "converged", "{r:?}");
        assert_eq!(&r[gap], "0", "{r:?}");
        assert!(r[fb].parse::<f64>().unwrap() < 1e-9, "{r:?}");
        assert!(r[seconds].parse::<f64>().unwrap() > 0.0, "{r:?}");
        n += 1;
    }
    assert_eq!(n, 2);
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## Refinement with `exact`"), "{report}");
    assert!(report.contains("MLS then calippso above"), "{report}");
    let row = report
        .lines()
        .find(|l| l.starts_with("| adam | calippso |"))
        .unwrap();
    assert!(row.contains("| 2 / 2 |"), "{row}");
}

/// `--refine` names a method or `exact`; anything else is a usage error that lists both.
#[test]
fn compare_refine_refuses_a_method_that_does_not_jam() {
    let o = packbench(&[
        "compare",
        "--methods",
        "adam",
        "--refine",
        "ls",
        "--N",
        "10",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--refine ls") && err.contains("exact"),
        "{err}"
    );
}
