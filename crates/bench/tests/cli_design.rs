//! `packbench design` from the command line: known answers (a bound, a target inside a
//! monotone family), the same history from the same seed, `--resume` giving the rows of one
//! uninterrupted run, islands joined by `merge`, and bad input refused before any packing; the
//! same for the surrogate optimiser (`--optimizer ego`) in a build with the `ego` feature, and
//! its refusal in a build without. Small N in 3D so each search takes seconds in release.

mod common;

use std::path::{Path, PathBuf};

use common::packbench;

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("packbench_design_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Runs `packbench design ARGS --out OUT --quiet`, which must succeed; its stderr.
fn design(out: &Path, args: &[&str]) -> String {
    let mut all: Vec<&str> = vec!["design"];
    all.extend_from_slice(args);
    let o = out.display().to_string();
    all.extend_from_slice(&["--out", &o, "--quiet", "--jobs", "2"]);
    let r = packbench(&all);
    let err = String::from_utf8_lossy(&r.stderr).to_string();
    assert!(r.status.success(), "design {args:?} failed: {err}");
    err
}

/// The rows of `DIR/evaluations.csv` as cells, the runtime column blanked (wall time is the
/// one column that differs between identical runs).
fn rows(dir: &Path) -> Vec<Vec<String>> {
    let mut r = csv::Reader::from_path(dir.join("evaluations.csv")).unwrap();
    let head = r.headers().unwrap().clone();
    let t = head.iter().position(|h| h == "runtime_s").unwrap();
    r.records()
        .map(|rec| {
            let mut v: Vec<String> = rec.unwrap().iter().map(str::to_string).collect();
            v[t].clear();
            v
        })
        .collect()
}

fn best(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("best.json")).unwrap()).unwrap()
}

/// Bidisperse spheres at equal numbers with the size ratio between 1 and 1.4: the search
/// scene of the bound and determinism tests.
const BIDISPERSE: &[&str] = &[
    "--family",
    "bidisperse",
    "--param",
    "ratio=1:1.4",
    "--param",
    "p=0.5",
    "--N",
    "128",
    "--Ndim",
    "3",
];

/// The bidisperse ratio search with `optimizer` flags (none: the default), two seeds per
/// candidate, 64 packings (room for IPOP's restarts and the incumbent's re-evaluations) and
/// two confirmations, written to `out`: its best.
fn bidisperse_bound_search(out: &Path, optimizer: &[&str]) -> serde_json::Value {
    let mut args = BIDISPERSE.to_vec();
    args.extend_from_slice(optimizer);
    args.extend_from_slice(&[
        "--seeds-per-candidate",
        "2",
        "--budget",
        "64",
        "--confirm",
        "2",
    ]);
    design(out, &args);
    best(out)
}

#[test]
fn bidisperse_phi_rises_with_the_ratio_so_the_best_sits_at_the_upper_bound() {
    let out = tmp("bound");
    let b = bidisperse_bound_search(&out, &[]);
    let ratio = b["values"][0].as_f64().unwrap();
    assert_eq!(b["names"][0], "ratio");
    // At the bound or within 2.5 % of the span from it: at N = 128 and two seeds a candidate's
    // φ_J scatters by ~0.003, more than φ_J gains over the last hundredth of the ratio.
    assert!((1.39..=1.4).contains(&ratio), "best {b}");
    for f in [
        "evaluations.csv",
        "best.json",
        "best_diameters.txt",
        "report.md",
        "figures/history.png",
        "figures/distribution.png",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    // The packed diameters of the best distribution are the two sizes at equal numbers.
    let d: Vec<f64> = std::fs::read_to_string(out.join("best_diameters.txt"))
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.parse().unwrap())
        .collect();
    assert_eq!(d.len(), 128);
    assert!(d.iter().all(|&x| x == 1.0 || x == ratio));
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn a_target_inside_a_monotone_family_is_hit_within_the_seed_spread() {
    let out = tmp("target");
    design(
        &out,
        &[
            "--family",
            "lognormal",
            "--param",
            "sigma=0:0.4",
            "--objective",
            "target",
            "--target",
            "0.655",
            "--N",
            "128",
            "--Ndim",
            "3",
            "--seeds-per-candidate",
            "2",
            "--budget",
            "40",
            "--confirm",
            "4",
        ],
    );
    let b = best(&out);
    let mean = b["confirm_mean"].as_f64().unwrap();
    let std = b["confirm_std"].as_f64().unwrap();
    let sigma = b["values"][0].as_f64().unwrap();
    assert!(
        (mean - 0.655).abs() <= 3.0 * std + 0.003,
        "confirmed φ_J {mean} ± {std} at σ = {sigma}"
    );
    assert!(
        sigma > 0.0 && sigma < 0.4,
        "σ = {sigma} should lie inside the family"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// A short search: 2 generations of 4 candidates × 1 seed, 2 confirmations, N = 48.
const SHORT: &[&str] = &[
    "--family",
    "lognormal",
    "--N",
    "48",
    "--Ndim",
    "3",
    "--seeds-per-candidate",
    "1",
    "--budget",
    "8",
    "--confirm",
    "2",
    "--screen",
    "none",
];

#[test]
fn the_same_seed_gives_the_same_history_and_another_seed_another() {
    let (a, b, c) = (tmp("seed_a"), tmp("seed_b"), tmp("seed_c"));
    design(&a, SHORT);
    design(&b, SHORT);
    let mut other = SHORT.to_vec();
    other.extend_from_slice(&["--seed", "5"]);
    design(&c, &other);
    let ra = rows(&a);
    assert_eq!(ra.len(), 8 + 2);
    assert_eq!(ra, rows(&b));
    assert_ne!(ra, rows(&c));
    for d in [a, b, c] {
        let _ = std::fs::remove_dir_all(&d);
    }
}

#[test]
fn a_stopped_search_resumed_gives_the_rows_of_one_uninterrupted_run() {
    let (whole, part) = (tmp("whole"), tmp("part"));
    design(&whole, SHORT);
    design(&part, SHORT);
    // Stop it after 5 of its 10 rows, the last of them cut mid-line by the interruption.
    let text = std::fs::read_to_string(part.join("evaluations.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let mut cut = lines[..6].join("\n");
    cut.push('\n');
    cut.push_str(&lines[6][..lines[6].len() / 2]);
    std::fs::write(part.join("evaluations.csv"), cut).unwrap();
    let said = design(&part, &[SHORT, &["--resume"]].concat());
    assert!(said.contains("5 rows kept"), "{said}");
    assert_eq!(rows(&part), rows(&whole));
    assert_eq!(best(&part)["values"], best(&whole)["values"]);
    // Without --resume a folder holding a search is refused, and another search is refused
    // with it.
    let again = packbench(
        &[
            &["design"],
            SHORT,
            &["--out", part.to_str().unwrap(), "--quiet"],
        ]
        .concat(),
    );
    assert_eq!(again.status.code(), Some(2));
    let other = packbench(
        &[
            &["design"],
            SHORT,
            &[
                "--out",
                part.to_str().unwrap(),
                "--quiet",
                "--resume",
                "--seed",
                "9",
            ],
        ]
        .concat(),
    );
    assert_eq!(other.status.code(), Some(2));
    for d in [whole, part] {
        let _ = std::fs::remove_dir_all(&d);
    }
}

#[test]
fn islands_split_the_budget_and_merge_joins_them() {
    let (half, s1, s2, merged) = (tmp("half"), tmp("s1"), tmp("s2"), tmp("merged"));
    let mut sharded = SHORT.to_vec();
    let at = sharded.iter().position(|a| *a == "8").unwrap();
    sharded[at] = "16";
    design(&s1, &[&sharded[..], &["--shard", "1/2"]].concat());
    design(&s2, &[&sharded[..], &["--shard", "2/2"]].concat());
    // Island 1 of 2 with budget 16 is the unsplit search with budget 8.
    design(&half, SHORT);
    assert_eq!(rows(&s1), rows(&half));
    assert_ne!(rows(&s2).len(), 0);
    let o = packbench(&[
        "merge",
        s1.to_str().unwrap(),
        s2.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let m = rows(&merged);
    assert_eq!(m.len(), rows(&s1).len() + rows(&s2).len());
    assert!(m.iter().any(|r| r[1] == "1") && m.iter().any(|r| r[1] == "2"));
    assert!(merged.join("report.md").is_file());
    // An island missing is refused.
    let o = packbench(&[
        "merge",
        s1.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    for d in [half, s1, s2, merged] {
        let _ = std::fs::remove_dir_all(&d);
    }
}

#[test]
fn bad_input_exits_2_with_one_sentence_before_any_packing() {
    let base = ["--N", "48", "--Ndim", "3"];
    let cases: &[(&[&str], &str)] = &[
        (&["--family", "cauchy"], "unknown family"),
        (
            &["--family", "lognormal", "--param", "mu=0:1"],
            "no parameter `mu`",
        ),
        (
            &["--family", "bidisperse", "--param", "ratio=1.4:1"],
            "reversed",
        ),
        (
            &[
                "--family",
                "bidisperse",
                "--param",
                "ratio=1.4",
                "--param",
                "p=0.5",
            ],
            "every parameter fixed",
        ),
        (
            &[
                "--family",
                "lognormal",
                "--objective",
                "target",
                "--target",
                "1.3",
            ],
            "impossible",
        ),
        (
            &["--family", "lognormal", "--objective", "target"],
            "needs --target",
        ),
        (
            &["--family", "lognormal", "--objective", "densest"],
            "unknown objective",
        ),
        (&["--family", "mixture", "--components", "0"], "components"),
        (&["--family", "lognormal", "--budget", "2"], "too small"),
        (&["--family", "lognormal", "--method", "nope"], "nope"),
        (&["--family", "lognormal", "--sigma", "0.2"], "drop"),
        (
            &["--family", "lognormal", "--optimizer", "simplex"],
            "unknown optimizer",
        ),
        (
            &["--family", "lognormal", "--optimizer", "bracket"],
            "for a target",
        ),
    ];
    for (args, says) in cases {
        let out = tmp("bad");
        let o = out.display().to_string();
        let all = [&["design"], &base[..], args, &["--out", &o, "--quiet"]].concat();
        let r = packbench(&all);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
}

#[cfg(not(feature = "ego"))]
#[test]
fn the_surrogate_optimiser_is_refused_naming_the_feature_that_builds_it() {
    let out = tmp("no_ego");
    let o = out.display().to_string();
    let r = packbench(&[
        "design",
        "--family",
        "lognormal",
        "--N",
        "48",
        "--optimizer",
        "ego",
        "--out",
        &o,
        "--quiet",
    ]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(2), "{err}");
    assert!(
        err.contains("`ego` cargo feature")
            && err.contains("cargo build --release --features ego -p packbench"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(!out.exists());
}

#[cfg(feature = "ego")]
#[test]
fn the_surrogate_optimiser_finds_the_upper_bound_of_the_bidisperse_ratio() {
    let out = tmp("ego_bound");
    let b = bidisperse_bound_search(&out, &["--optimizer", "ego"]);
    let ratio = b["values"][0].as_f64().unwrap();
    // The same tolerance as CMA-ES's test above: seed noise at N = 128 hides the last hundredth.
    assert!((1.39..=1.4).contains(&ratio), "best {b}");
    let design_json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("design.json")).unwrap()).unwrap();
    assert_eq!(design_json["config"]["optimizer"], "ego");
    let _ = std::fs::remove_dir_all(&out);
}

#[cfg(feature = "ego")]
#[test]
fn the_surrogate_search_repeats_itself_and_resumes_to_the_same_rows() {
    let (a, b, part) = (tmp("ego_a"), tmp("ego_b"), tmp("ego_part"));
    let ego = [SHORT, &["--optimizer", "ego"]].concat();
    design(&a, &ego);
    design(&b, &ego);
    let ra = rows(&a);
    assert_eq!(ra.len(), 8 + 2);
    assert_eq!(ra, rows(&b));
    // Another optimiser on the same search makes other candidates after the first generation.
    let cma = tmp("ego_cma");
    design(&cma, SHORT);
    assert_ne!(ra, rows(&cma));
    // Stopped after 5 rows, resumed: the rows of the uninterrupted run.
    design(&part, &ego);
    let text = std::fs::read_to_string(part.join("evaluations.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    std::fs::write(part.join("evaluations.csv"), lines[..6].join("\n") + "\n").unwrap();
    let said = design(&part, &[&ego[..], &["--resume"]].concat());
    assert!(said.contains("5 rows kept"), "{said}");
    assert_eq!(rows(&part), ra);
    // A CMA-ES search does not resume a surrogate one.
    let other = packbench(
        &[
            &["design"],
            SHORT,
            &["--out", part.to_str().unwrap(), "--quiet", "--resume"],
        ]
        .concat(),
    );
    assert_eq!(other.status.code(), Some(2));
    for d in [a, b, part, cma] {
        let _ = std::fs::remove_dir_all(&d);
    }
}
