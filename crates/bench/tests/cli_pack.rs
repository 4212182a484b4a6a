//! `packbench pack`: outputs, sidecar contents, method flags and their errors.

use std::process::{Command, Output};

fn packbench(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_packbench"))
        .args(args)
        .output()
        .expect("runs")
}

fn tmp(name: &str) -> String {
    let dir = std::env::temp_dir().join(format!("packbench-pack-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name).to_str().unwrap().to_string()
}

#[test]
fn pack_writes_the_packing_and_a_sidecar_with_metrics_and_trace() {
    let init = tmp("init.txt");
    assert!(
        packbench(&[
            "init", "--N", "40", "--Ndim", "2", "--seed", "4", "--output", &init
        ])
        .status
        .success()
    );
    let out = tmp("fire");
    let o = packbench(&[
        "pack", "--method", "fire", "--file", &init, "--box", "1,1", "--seed", "4", "--quiet",
        "--output", &out,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(format!("{out}.txt")).unwrap();
    assert_eq!(text.lines().count(), 40);
    let side: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(format!("{out}.json")).unwrap()).unwrap();
    for key in [
        "scene",
        "parameters",
        "metrics",
        "runtime_s",
        "steps",
        "termination",
        "trace",
        "container",
    ] {
        assert!(side.get(key).is_some(), "sidecar lacks {key}");
    }
    let phi = side["metrics"]["phi"].as_f64().unwrap();
    assert!(phi > 0.75 && phi < 0.91, "2D jammed disks, phi {phi}");
    // analyze finds the container in the sidecar and agrees.
    let a = packbench(&["analyze", &format!("{out}.txt")]);
    let m: serde_json::Value = serde_json::from_slice(&a.stdout).unwrap();
    assert_eq!(m["phi"].as_f64().unwrap(), phi);
}

#[test]
fn seq_fill_needs_no_file_and_writes_its_products() {
    let out = tmp("bed");
    let o = packbench(&[
        "pack",
        "--method",
        "seq-fill",
        "--dist",
        "weibull",
        "--scale",
        "31.4",
        "--shape",
        "3.55",
        "--brick",
        "120,120,120",
        "--seed",
        "2",
        "--quiet",
        "--output",
        &out,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for suffix in [".txt", ".json", "_contacts.csv", "_faces.csv", "_radii.png"] {
        assert!(
            std::path::Path::new(&format!("{out}{suffix}")).exists(),
            "{suffix}"
        );
    }
}

#[test]
fn method_flags_are_checked_against_the_method() {
    for (args, want) in [
        (
            vec!["--method", "adam", "--rate", "1"],
            "--rate does not apply to method adam",
        ),
        (
            vec!["--method", "fire", "--qp"],
            "--qp applies to closest-jammed",
        ),
        (vec!["--method", "nope"], "unknown method `nope`"),
        (
            vec!["--method", "adam", "--set", "nope=1"],
            "method adam has no parameter `nope`",
        ),
        (
            vec!["--method", "adam", "--set", "delta_phi0"],
            "must look like key=value",
        ),
    ] {
        let mut a = vec!["pack", "--N", "5"];
        a.extend(args);
        let o = packbench(&a);
        assert_eq!(o.status.code(), Some(2), "{a:?}");
        assert!(
            String::from_utf8_lossy(&o.stderr).contains(want),
            "{a:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}
