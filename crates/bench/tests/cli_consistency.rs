//! What a newcomer meets in the first hour, from the command line: outputs that agree with
//! themselves, undefined quantities written as null, contradictory flags refused, a seed named
//! only when something is random, and θ with its sign, error and note.

mod common;
use common::packbench;

use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("packbench-consistency-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn json(stdout: &[u8]) -> serde_json::Value {
    serde_json::from_slice(stdout).expect("JSON on stdout")
}

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A dilute start has no contact network: `analyze` writes its z' and iso_gap as null.
#[test]
fn a_packing_of_rattlers_has_null_iso_gap() {
    let file = tmp("dilute.txt");
    let init = packbench(&[
        "init", "--N", "30", "--Ndim", "3", "--phi", "0.05", "--seed", "1",
    ]);
    assert!(init.status.success(), "{}", stderr(&init));
    std::fs::write(&file, &init.stdout).unwrap();
    let out = packbench(&["analyze", file.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let m = json(&out.stdout);
    assert_eq!(m["rattlers"], 30);
    assert!(m["iso_gap"].is_null() && m["z_nonrattler"].is_null(), "{m}");
    assert_eq!(m["isostatic"], false);
}

/// Two particles at one centre: `analyze` refuses them as `pack` does, naming the file.
#[test]
fn analyze_refuses_coincident_centres_as_pack_does() {
    let file = tmp("coincident.txt");
    std::fs::write(&file, "0.2 0.2 0.1\n0.7 0.7 0.1\n0.2 0.2 0.1\n").unwrap();
    let name = file.to_str().unwrap();
    let analyze = packbench(&["analyze", name, "--box", "1,1"]);
    assert_eq!(analyze.status.code(), Some(2), "{}", stderr(&analyze));
    assert!(stderr(&analyze).contains("particles 1 and 3 have the same centre"));
    assert!(stderr(&analyze).contains(name));
    let pack = packbench(&["pack", "--method", "fire", "--file", name, "--box", "1,1"]);
    assert_eq!(pack.status.code(), Some(2), "{}", stderr(&pack));
    assert!(stderr(&pack).contains("same centre"));
}

/// --walls that a shell or a hemisphere-cut brick would silently override are refused.
#[test]
fn contradictory_container_flags_are_refused() {
    let cases: [&[&str]; 3] = [
        &["--walls", "-3,0,0", "--shell", "0.2,0.4"],
        &["--hemispheres", "0.3,0.3", "--walls", "0,0,0"],
        &["--hemispheres", "0.3,0.3", "--shell", "0.2,0.4"],
    ];
    for flags in cases {
        let mut args = vec!["init", "--N", "10", "--Ndim", "3", "--seed", "1"];
        args.extend_from_slice(flags);
        let out = packbench(&args);
        assert_eq!(out.status.code(), Some(2), "{flags:?}: {}", stderr(&out));
        let why = stderr(&out);
        assert!(
            why.contains("--walls") || why.contains("cannot be used with"),
            "{flags:?}: {why}"
        );
    }
    // The consistent forms still work.
    let ok = packbench(&[
        "init", "--N", "10", "--Ndim", "3", "--seed", "1", "--shell", "0.2,0.4", "--walls", "1,1,0",
    ]);
    assert!(ok.status.success(), "{}", stderr(&ok));
}

/// A deterministic method from a file draws nothing: no seed is named or recorded; a drawn
/// start is named.
#[test]
fn a_seed_is_named_only_when_something_is_random() {
    let start = tmp("seedless_start");
    let drawn = packbench(&[
        "pack",
        "--method",
        "adam",
        "--N",
        "40",
        "--Ndim",
        "2",
        "--output",
        start.to_str().unwrap(),
    ]);
    assert!(drawn.status.success(), "{}", stderr(&drawn));
    assert!(stderr(&drawn).contains("no --seed given"));
    let out = tmp("seedless_exact");
    let exact = packbench(&[
        "pack",
        "--method",
        "calippso",
        "--file",
        &format!("{}.txt", start.display()),
        "--output",
        out.to_str().unwrap(),
    ]);
    assert!(exact.status.success(), "{}", stderr(&exact));
    assert!(!stderr(&exact).contains("--seed"), "{}", stderr(&exact));
    assert!(common::sidecar(out.to_str().unwrap())["seed"].is_null());
}

/// `animate` of a run without snapshots says how to record one instead of a one-frame GIF.
#[test]
fn animate_without_snapshots_says_how_to_record_them() {
    let run = tmp("still");
    let out = packbench(&[
        "pack",
        "--method",
        "adam",
        "--N",
        "20",
        "--Ndim",
        "2",
        "--seed",
        "1",
        "--output",
        run.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let gif = packbench(&["animate", &format!("{}.json", run.display())]);
    assert_eq!(gif.status.code(), Some(2), "{}", stderr(&gif));
    assert!(stderr(&gif).contains("--save-interval"), "{}", stderr(&gif));
}

/// `analyze --voronoi --per-particle` gives each particle its cell volume and local φ; the
/// cells tile the box, and each local φ is the particle's volume over its cell's.
#[test]
fn per_particle_voronoi_cells_tile_the_box() {
    let file = tmp("cells.txt");
    let init = packbench(&[
        "init", "--N", "50", "--Ndim", "2", "--phi", "0.4", "--seed", "2",
    ]);
    std::fs::write(&file, &init.stdout).unwrap();
    let text = String::from_utf8(init.stdout).unwrap();
    let out = packbench(&[
        "analyze",
        file.to_str().unwrap(),
        "--voronoi",
        "--per-particle",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let r = json(&out.stdout);
    let cells = &r["per_particle"];
    let volumes: Vec<f64> = serde_json::from_value(cells["cell_volume"].clone()).unwrap();
    let local: Vec<f64> = serde_json::from_value(cells["local_phi"].clone()).unwrap();
    assert_eq!((volumes.len(), local.len()), (50, 50));
    // The unit periodic box: the cells' areas sum to 1.
    assert!(
        (volumes.iter().sum::<f64>() - 1.0).abs() < 1e-9,
        "{volumes:?}"
    );
    for (k, line) in text.lines().enumerate() {
        let d: f64 = line.split_whitespace().last().unwrap().parse().unwrap();
        let area = std::f64::consts::PI * d * d / 4.0;
        assert!((local[k] - area / volumes[k]).abs() < 1e-9, "particle {k}");
    }
    let alone = packbench(&["analyze", file.to_str().unwrap(), "--per-particle"]);
    assert_eq!(alone.status.code(), Some(2));
}

/// θ of an exact 3D packing (adam, then calippso) is positive, between the buckler and the
/// extended exponents (θ_ℓ = 0.17462, θ_e = 0.42311; Charbonneau, Corwin, Parisi & Zamponi
/// 2015) within three standard errors, with its window and error; the forces are unique and
/// bucklers are counted. A soft-sphere packing's forces are flagged as one solution of many.
#[test]
fn theta_is_positive_with_its_error_for_an_exact_packing() {
    let adam = tmp("theta_adam");
    let a = packbench(&[
        "pack",
        "--method",
        "adam",
        "--N",
        "400",
        "--Ndim",
        "3",
        "--seed",
        "3",
        "--output",
        adam.to_str().unwrap(),
    ]);
    assert!(a.status.success(), "{}", stderr(&a));
    let exact = tmp("theta_exact");
    let c = packbench(&[
        "pack",
        "--method",
        "calippso",
        "--file",
        &format!("{}.txt", adam.display()),
        "--output",
        exact.to_str().unwrap(),
    ]);
    assert!(c.status.success(), "{}", stderr(&c));
    let forces = |name: &PathBuf| {
        let out = packbench(&["analyze", &format!("{}.txt", name.display()), "--structure"]);
        assert!(out.status.success(), "{}", stderr(&out));
        json(&out.stdout)["structure"]["forces"].clone()
    };
    let f = forces(&exact);
    assert_eq!(f["unique"], true, "{f}");
    let theta = f["theta"].as_f64().expect("θ fitted");
    let error = f["theta_error"].as_f64().unwrap();
    assert!(error > 0.0 && error < 0.2, "{f}");
    assert!(
        (0.17462 - 3.0 * error..=0.42311 + 3.0 * error).contains(&theta),
        "θ = {theta} ± {error}"
    );
    assert!(f["bucklers"].as_u64().unwrap() > 0, "{f}");
    assert_eq!(f["fit_window"], serde_json::json!([0.01, 0.3]));
    let soft = forces(&adam);
    assert_eq!(soft["unique"], false, "{soft}");
    assert!(
        soft["note"]
            .as_str()
            .unwrap()
            .contains("one solution of many")
    );
}
