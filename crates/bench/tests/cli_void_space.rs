//! Command-line tests of the void space (issue "pore space and Voronoi cells"): `analyze
//! --voronoi/--pores` on a crystal and a jammed packing, `plot --kind pores`, `compare --pores`
//! and the exit-2 sentences of bad input.

mod common;
use common::packbench;

fn tmp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("packbench-void-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn json(o: &std::process::Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

#[test]
fn analyze_pores_knows_the_fcc_holes() {
    // FCC, 2 × 2 × 2 cubic cells of unit spheres (side √2).
    let a = 2f64.sqrt();
    let mut text = String::new();
    for i in 0..2 {
        for j in 0..2 {
            for k in 0..2 {
                for b in [
                    [0.0, 0.0, 0.0],
                    [0.5, 0.5, 0.0],
                    [0.5, 0.0, 0.5],
                    [0.0, 0.5, 0.5],
                ] {
                    let p = [i as f64 + b[0], j as f64 + b[1], k as f64 + b[2]];
                    text += &format!("{} {} {} 1\n", p[0] * a, p[1] * a, p[2] * a);
                }
            }
        }
    }
    let file = tmp("fcc.txt");
    std::fs::write(&file, &text).unwrap();
    let l = format!("{0},{0},{0}", 2.0 * a);
    let m = json(&packbench(&[
        "analyze",
        file.to_str().unwrap(),
        "--box",
        &l,
        "--no-force-balance",
        "--pores",
        "--pore-samples",
        "2000",
        "--chord-lines",
        "100",
    ]));
    let v = &m["voronoi"];
    assert!((v["mean_volume"].as_f64().unwrap() - a * a * a / 4.0).abs() < 1e-12);
    assert_eq!(v["faces_mean"].as_f64().unwrap(), 12.0);
    // The octahedral hole holds a sphere of radius (√2 − 1) R, R = 1/2.
    let di = m["pores"]["included_sphere_diameter"].as_f64().unwrap();
    assert!((di - (2f64.sqrt() - 1.0)).abs() < 1e-9, "D_i = {di}");
    assert!(m["chords"]["void"]["mean"].as_f64().unwrap() > 0.0);
    // --voronoi alone adds no pores.
    let m = json(&packbench(&[
        "analyze",
        file.to_str().unwrap(),
        "--box",
        &l,
        "--no-force-balance",
        "--voronoi",
    ]));
    assert!(m.get("voronoi").is_some() && m.get("pores").is_none());
}

#[test]
fn jammed_packing_obeys_the_chord_identity_and_draws() {
    let out = tmp("jammed");
    let out = out.to_str().unwrap();
    let o = packbench(&[
        "pack",
        "--method",
        "adam",
        "--N",
        "400",
        "--Ndim",
        "3",
        "--seed",
        "3",
        "--quiet",
        "--no-force-balance",
        "--output",
        out,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let file = format!("{out}.txt");
    let m = json(&packbench(&[
        "analyze",
        &file,
        "--no-force-balance",
        "--pores",
        "--pore-samples",
        "3000",
        "--chord-lines",
        "1500",
    ]));
    let c = &m["chords"];
    let (mean, err, predicted) = (
        c["void"]["mean"].as_f64().unwrap(),
        c["void"]["mean_error"].as_f64().unwrap(),
        c["void_mean_predicted"].as_f64().unwrap(),
    );
    assert!(
        (mean - predicted).abs() < 5.0 * err,
        "{mean} ± {err} against {predicted}"
    );
    // A jammed packing's free sphere is smaller than its largest included sphere.
    let p = &m["pores"];
    let (di, df) = (
        p["included_sphere_diameter"].as_f64().unwrap(),
        p["free_sphere_diameter"].as_f64().unwrap(),
    );
    assert!(df > 0.0 && df < di, "D_f {df}, D_i {di}");
    let phi = m["voronoi"]["local_phi_mean"].as_f64().unwrap();
    assert!(phi > 0.6 && phi < 0.7, "{phi}");
    for kind in ["voronoi", "pores", "chords"] {
        let png = tmp(&format!("{kind}.png"));
        let o = packbench(&[
            "plot",
            &file,
            "--kind",
            kind,
            "--output",
            png.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(std::fs::metadata(&png).unwrap().len() > 1000);
    }
}

#[test]
fn compare_pores_writes_the_table() {
    let out = tmp("cmp");
    let o = packbench(&[
        "compare",
        "--methods",
        "adam",
        "--N",
        "60",
        "--Ndim",
        "3",
        "--dist",
        "mono",
        "--seeds",
        "2",
        "--pores",
        "--quiet",
        "--jobs",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("pores.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3, "{csv}");
    assert!(csv.starts_with("method,seed,phi,local_phi_mean"));
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## Void space"));
    assert!(out.join("figures/void_space_pore_sizes.png").exists());
}

#[test]
fn bad_input_exits_2_with_a_sentence() {
    let cases = [
        ("same.txt", "1 1 1 1\n1 1 1 1\n", "same centre"),
        ("deep.txt", "1 1 1 1\n1.5 1 1 1\n", "overlap"),
    ];
    for (name, text, words) in cases {
        let file = tmp(name);
        std::fs::write(&file, text).unwrap();
        let o = packbench(&[
            "analyze",
            file.to_str().unwrap(),
            "--box",
            "3,3,3",
            "--no-force-balance",
            "--pores",
        ]);
        assert_eq!(o.status.code(), Some(2), "{name}");
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(e.contains(words) && !e.contains("panicked"), "{name}: {e}");
    }
    let file = tmp("d4.txt");
    std::fs::write(&file, "1 1 1 1 1\n").unwrap();
    let o = packbench(&[
        "analyze",
        file.to_str().unwrap(),
        "--box",
        "3,3,3,3",
        "--voronoi",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("2 and 3 dimensions"));
}
