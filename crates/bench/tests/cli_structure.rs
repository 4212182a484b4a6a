//! Command-line tests of `packbench analyze --structure`, `predict` and the structure plots.

mod common;

use common::packbench;

fn json(o: &std::process::Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).expect("JSON on stdout")
}

fn tmp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("packbench-cli-structure-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// FCC at contact, 3 × 3 × 3 cubic cells of unit spheres, as plain text, and its box.
fn fcc_file() -> (String, String) {
    let a = 2f64.sqrt();
    let mut text = String::new();
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                for b in [
                    [0.0, 0.0, 0.0],
                    [0.5, 0.5, 0.0],
                    [0.5, 0.0, 0.5],
                    [0.0, 0.5, 0.5],
                ] {
                    let p = [i as f64 + b[0], j as f64 + b[1], k as f64 + b[2]].map(|v| v * a);
                    text += &format!("{} {} {} 1\n", p[0], p[1], p[2]);
                }
            }
        }
    }
    let file = tmp("fcc.txt");
    std::fs::write(&file, text).unwrap();
    let l = 3.0 * a;
    (file.to_str().unwrap().to_owned(), format!("{l},{l},{l}"))
}

#[test]
fn analyze_structure_reports_fcc_order_beside_the_metrics() {
    let (file, bx) = fcc_file();
    let m = json(&packbench(&["analyze", &file, "--box", &bx, "--structure"]));
    assert_eq!(m["n"], 108);
    let s = &m["structure"];
    assert!((s["q6"].as_f64().unwrap() - 0.574_524).abs() < 1e-4);
    assert!((s["q4"].as_f64().unwrap() - 0.190_941).abs() < 1e-4);
    assert_eq!(s["crystal_fraction"].as_f64(), Some(1.0));
    // A perfect crystal has no density fluctuation at the smallest wave vectors: S(k→0) = 0
    // to rounding (4e-30 here).
    let s_k0 = s["structure_factor"]["s_k0"]
        .as_f64()
        .expect("s_k0 is a number");
    assert!((0.0..1e-20).contains(&s_k0), "S(k→0) = {s_k0}");
    assert_eq!(s["rcp_prediction"]["desmond_weeks"].as_f64(), Some(0.634));
    assert!((s["rcp_prediction"]["farr_groot"].as_f64().unwrap() - 0.6435).abs() < 1e-12);
    // Without --structure the output keeps exactly the metrics.
    let plain = json(&packbench(&["analyze", &file, "--box", &bx]));
    assert!(plain.get("structure").is_none());
    // The force balance is solved once with --structure (for P(f)) and is the same number.
    assert!(plain["force_balance"].as_f64().is_some(), "{plain}");
    assert_eq!(m["force_balance"], plain["force_balance"]);
    assert_eq!(m["structure"]["forces"]["residual"], plain["force_balance"]);
}

#[test]
fn predict_follows_the_size_distribution() {
    let mono = json(&packbench(&["predict", "--dist", "mono"]));
    assert_eq!(mono["desmond_weeks"].as_f64(), Some(0.634));
    assert!((mono["farr_groot"].as_f64().unwrap() - 0.6435).abs() < 1e-12);
    let ln = json(&packbench(&[
        "predict",
        "--dist",
        "lognormal-mean1",
        "--sigma",
        "0.2",
        "--N",
        "20000",
    ]));
    let delta = ln["polydispersity"].as_f64().unwrap();
    assert!((delta - 0.2).abs() < 0.01, "δ = {delta}");
    assert!(ln["skewness"].as_f64().unwrap() > 0.0);
    assert!(ln["desmond_weeks"].as_f64().unwrap() > 0.634 + 0.0658 * delta);
    assert_eq!(ln["desmond_weeks_in_range"], true);
    let fg = ln["farr_groot"].as_f64().unwrap();
    assert!(fg > 0.65 && fg < 0.665, "Farr–Groot {fg}");
    assert!(
        ln["desmond_weeks_range"]
            .as_str()
            .unwrap()
            .contains("δ ≤ 0.4")
    );
    let disks = json(&packbench(&[
        "predict",
        "--dist",
        "bidisperse",
        "--d1",
        "1",
        "--d2",
        "1.4",
        "--p",
        "0.5",
        "--Ndim",
        "2",
    ]));
    assert!(disks["desmond_weeks"].is_null() && disks["farr_groot"].is_null());
    let bad = packbench(&["predict", "--dist", "bidisperse", "--d1", "1"]);
    assert_eq!(bad.status.code(), Some(2));
}

#[test]
fn structure_plots_are_written() {
    let (file, bx) = fcc_file();
    for kind in ["sk", "q6", "forces", "gaps"] {
        let out = tmp(&format!("{kind}.svg"));
        let o = packbench(&[
            "plot",
            &file,
            "--box",
            &bx,
            "--kind",
            kind,
            "--output",
            out.to_str().unwrap(),
        ]);
        assert!(
            o.status.success(),
            "{kind}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(std::fs::metadata(&out).unwrap().len() > 1000, "{kind}");
    }
}
