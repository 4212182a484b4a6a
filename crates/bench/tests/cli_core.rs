//! Command-line tests of `packbench init`, `analyze` and `export`.

use std::io::Write;
use std::process::{Command, Output, Stdio};

mod common;
use common::packbench;

fn packbench_stdin(args: &[&str], input: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_packbench"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawns");
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    child.wait_with_output().unwrap()
}

fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8(o.stderr.clone()).unwrap()
}

fn rows(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
        .collect()
}

/// φ of plain-text rows in a periodic unit cube (3D).
fn phi_unit_cube(rows: &[Vec<f64>]) -> f64 {
    rows.iter()
        .map(|r| std::f64::consts::PI / 6.0 * r[3].powi(3))
        .sum()
}

fn tmp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("packbench-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

const INIT: &[&str] = &[
    "init", "--N", "500", "--Ndim", "3", "--phi", "0.05", "--box", "1,1,1", "--seed", "1",
];

#[test]
fn init_mono_prints_500_rows_at_phi_0_05() {
    let mut args = INIT.to_vec();
    args.extend(["--dist", "mono", "--d", "1.0"]);
    let o = packbench(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = rows(&stdout(&o));
    assert_eq!(r.len(), 500);
    assert!(
        r.iter()
            .all(|row| row.len() == 4 && row.iter().all(|v| v.is_finite()))
    );
    assert!((phi_unit_cube(&r) - 0.05).abs() < 1e-12);
}

#[test]
fn init_works_for_every_distribution() {
    let dists: &[&[&str]] = &[
        &["--dist", "mono", "--d", "1"],
        &[
            "--dist",
            "bidisperse",
            "--d1",
            "1",
            "--d2",
            "1.4",
            "--p",
            "0.5",
        ],
        &["--dist", "gaussian", "--mu", "1", "--sigma", "0.1"],
        &[
            "--dist",
            "biGaussian",
            "--mu1",
            "1",
            "--sigma1",
            "0.1",
            "--mu2",
            "2",
            "--sigma2",
            "0.2",
            "--p",
            "0.5",
        ],
        &["--dist", "lognormal", "--mu", "0", "--sigma", "0.2"],
        &["--dist", "lognormal-mean1", "--sigma", "0.3"],
        &["--dist", "flat", "--d_min", "1", "--d_max", "2"],
        &[
            "--dist",
            "powerlaw",
            "--d_min",
            "1",
            "--d_max",
            "15",
            "--exponent",
            "-3",
        ],
        &["--dist", "exponential", "--d_min", "1", "--d_max", "4"],
        &["--dist", "weibull", "--scale", "31.4", "--shape", "3.55"],
        &["--dist", "gamma", "--shape", "2", "--scale", "14"],
        &["--dist", "custom", "--custom_list", "1,1.5,2"],
    ];
    for d in dists {
        let mut args = INIT.to_vec();
        args.extend_from_slice(d);
        let o = packbench(&args);
        assert!(o.status.success(), "{d:?}: {}", stderr(&o));
        let r = rows(&stdout(&o));
        assert_eq!(r.len(), 500, "{d:?}");
        assert!((phi_unit_cube(&r) - 0.05).abs() < 1e-12, "{d:?}");
    }
}

#[test]
fn scene_file_and_flags_give_the_same_packing() {
    let scene = tmp("scene.toml");
    let mut args = INIT.to_vec();
    args.extend([
        "--dist",
        "lognormal-mean1",
        "--sigma",
        "0.2",
        "--write-scene",
        scene.to_str().unwrap(),
    ]);
    let by_flags = packbench(&args);
    assert!(by_flags.status.success(), "{}", stderr(&by_flags));
    let by_file = packbench(&["init", "--scene", scene.to_str().unwrap()]);
    assert!(by_file.status.success(), "{}", stderr(&by_file));
    assert_eq!(stdout(&by_flags), stdout(&by_file));
}

#[test]
fn init_pipes_into_analyze() {
    let init = packbench(INIT);
    let o = packbench_stdin(&["analyze", "-"], &stdout(&init));
    assert!(o.status.success(), "{}", stderr(&o));
    let m: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert!((m["phi"].as_f64().unwrap() - 0.05).abs() < 1e-12);
    assert_eq!(m["n"], 500);
    assert_eq!(m["dim"], 3);
}

#[test]
fn analyze_knows_the_crystals() {
    // Hexagonal crystal, 6 × 6 unit disks.
    let h = 3f64.sqrt() / 2.0;
    let mut text = String::new();
    for j in 0..6 {
        for i in 0..6 {
            text += &format!(
                "{} {} 1\n",
                i as f64 + 0.5 * (j % 2) as f64 + 0.25,
                j as f64 * h + 0.1
            );
        }
    }
    let file = tmp("hex.txt");
    std::fs::write(&file, &text).unwrap();
    let o = packbench(&[
        "analyze",
        file.to_str().unwrap(),
        "--box",
        &format!("6,{}", 6.0 * h),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let m: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert!((m["phi"].as_f64().unwrap() - 0.9069).abs() < 1e-4);
    assert_eq!(m["z_nonrattler"].as_f64().unwrap(), 6.0);
    // FCC, 2 × 2 × 2 cubic cells of unit spheres.
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
                    let p = [
                        i as f64 + b[0] + 0.1,
                        j as f64 + b[1] + 0.1,
                        k as f64 + b[2] + 0.1,
                    ];
                    text += &format!("{} {} {} 1\n", p[0] * a, p[1] * a, p[2] * a);
                }
            }
        }
    }
    let file = tmp("fcc.txt");
    std::fs::write(&file, &text).unwrap();
    let l = format!("{0},{0},{0}", 2.0 * a);
    let o = packbench(&["analyze", file.to_str().unwrap(), "--box", &l]);
    let m: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert!((m["phi"].as_f64().unwrap() - 0.7405).abs() < 1e-4);
    assert_eq!(m["z_nonrattler"].as_f64().unwrap(), 12.0);
    assert!(m["force_balance"].as_f64().unwrap() < 1e-8);
}

#[test]
fn export_writes_every_format() {
    let init = packbench(&["init", "--N", "20", "--Ndim", "3", "--seed", "2"]);
    let file = tmp("small.txt");
    std::fs::write(&file, stdout(&init)).unwrap();
    let export = |format: &str| {
        stdout(&packbench(&[
            "export",
            file.to_str().unwrap(),
            "--format",
            format,
            "--walls",
            "1,0,0",
        ]))
    };
    let xyz = export("xyz");
    assert!(
        xyz.starts_with("20\nLattice=\"1 0 0 0 1 0 0 0 1\""),
        "{xyz}"
    );
    assert!(xyz.lines().nth(1).unwrap().ends_with("pbc=\"F T T\""));
    assert_eq!(xyz.lines().count(), 22);
    let lmp = export("lammps");
    assert!(lmp.contains("20 atoms") && lmp.contains("Atoms # sphere"));
    assert!(lmp.contains("#   boundary f p p\n"));
    let dump = export("lammps-dump");
    assert!(
        dump.contains("ITEM: BOX BOUNDS ff pp pp\n")
            && dump.contains("ITEM: NUMBER OF ATOMS\n20\n")
    );
    let vtp = export("vtp");
    assert!(vtp.contains("NumberOfPoints=\"20\" NumberOfVerts=\"20\""));
    assert!(vtp.contains("Name=\"Radius\"") && vtp.contains("Name=\"Periodic\""));
    assert!(
        export("vtp-box").contains("NumberOfPoints=\"8\" NumberOfVerts=\"0\" NumberOfLines=\"12\"")
    );
    let vtk = export("vtk");
    assert!(
        vtk.contains("POINTS 20 double")
            && vtk.contains("POINT_DATA 20\nFIELD FieldData 2\nRadius 1 20 double\n")
    );
    let bad = packbench(&["export", file.to_str().unwrap(), "--format", "pdb"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(stderr(&bad).contains(
        "unknown export format `pdb`; use one of xyz, lammps, lammps-dump, vtp, vtp-box, vtk"
    ));
    let init4 = packbench(&["init", "--N", "5", "--Ndim", "4", "--seed", "2"]);
    let file4 = tmp("small4.txt");
    std::fs::write(&file4, stdout(&init4)).unwrap();
    let four = packbench(&["export", file4.to_str().unwrap(), "--format", "vtp"]);
    assert_eq!(four.status.code(), Some(2), "{}", stderr(&four));
    assert!(stderr(&four).contains("a 4-dimensional packing cannot be exported"));
}

/// Every kind of bad input: exit code 2, one sentence naming what and where, no output file.
#[test]
fn bad_input_is_refused_clearly_and_touches_nothing() {
    let out = tmp("untouched.txt");
    let out_s = out.to_str().unwrap().to_string();
    let cases: Vec<(&str, Vec<String>, &str)> = vec![
        (
            "0 0 0.1\n0.5 nan 0.1\n",
            vec![],
            ":2:5: `nan` is not a finite number",
        ),
        (
            "0 0 0.1\n0.5 0.5 inf\n",
            vec![],
            ":2:9: `inf` is not a finite number",
        ),
        (
            "0 0 0.1\n0.5 0.5 -0.1\n",
            vec![],
            ":2:9: diameter -0.1 must be positive",
        ),
        (
            "0 0 0.1\n0.5 0.5 0.1 0.2\n",
            vec![],
            ":2:13: 4 columns here but 3",
        ),
        ("0.5 0.1\n", vec![], "d ≥ 2"),
        (
            "0.5 0.5 0.1\n",
            vec!["--box".into(), "1,1,1".into()],
            "--box has 3 lengths but the packing is 2-dimensional",
        ),
        (
            "0.5 0.5 0.1\n1.5 0.5 0.1\n",
            vec!["--walls".into(), "1,1".into()],
            ":2:1: particle at (1.5, 0.5) lies outside",
        ),
        ("", vec![], "no particles found"),
    ];
    for (text, extra, want) in cases {
        let file = tmp("bad.txt");
        std::fs::write(&file, text).unwrap();
        let mut args = vec![
            "export".to_string(),
            file.to_str().unwrap().into(),
            "--format".into(),
            "xyz".into(),
        ];
        args.extend(extra);
        args.extend(["--output".into(), out_s.clone()]);
        let o = packbench(&args.iter().map(|s| s.as_str()).collect::<Vec<_>>());
        assert_eq!(o.status.code(), Some(2), "{text:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(want), "{text:?}: {}", stderr(&o));
        assert_eq!(stderr(&o).lines().count(), 1);
        assert!(!out.exists());
    }
    let flag_cases: &[(&[&str], &str)] = &[
        (&["--phi", "0"], "phi = 0 must lie strictly between 0 and 1"),
        (&["--phi", "1"], "phi = 1 must lie strictly between 0 and 1"),
        (&["--dist", "zipf"], "unknown distribution `zipf`"),
        (
            &["--dist", "powerlaw", "--d_min", "1"],
            "--dist powerlaw needs --d_max",
        ),
        (&["--Ndim", "1"], "at least 2 dimensions"),
        (
            &["--box", "1,1"],
            "--box has 2 lengths but the packing is 3-dimensional",
        ),
        (
            &["--dist", "mono", "--d", "-1"],
            "d = -1 must be a positive finite number",
        ),
    ];
    for (flags, want) in flag_cases {
        let mut args = vec![
            "init", "--N", "10", "--Ndim", "3", "--seed", "1", "--output", &out_s,
        ];
        args.extend_from_slice(flags);
        if flags.contains(&"--Ndim") {
            args.drain(3..5);
        }
        let o = packbench(&args);
        assert_eq!(o.status.code(), Some(2), "{flags:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(want), "{flags:?}: {}", stderr(&o));
        assert!(!out.exists());
    }
}
