//! `packbench pack`: outputs, sidecar contents, method flags and their errors.

use std::process::Command;

mod common;
use common::{packbench, sidecar};
use packbench_core::Container;
use packbench_core::format::{read_packing, write_text};

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
    let side = sidecar(&out);
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
    // Forty equal disks jammed by FIRE from `init --seed S` starts: 0.820–0.842 over seeds 1–12
    // (0.834 ± 0.006; equal disks order in patches, short of the hexagonal 0.9069).
    let phi = side["metrics"]["phi"].as_f64().unwrap();
    assert!((0.81..0.86).contains(&phi), "2D jammed disks, phi {phi}");
    assert!(
        side["metrics"]["max_overlap"].as_f64().unwrap() <= 1e-3,
        "{}",
        side["metrics"]
    );
    assert!(side["metrics"]["force_balance"].is_number());
    // --no-force-balance leaves the residual out and changes nothing else.
    let quick = tmp("fire_quick");
    let o = packbench(&[
        "pack",
        "--method",
        "fire",
        "--file",
        &init,
        "--box",
        "1,1",
        "--seed",
        "4",
        "--quiet",
        "--no-force-balance",
        "--output",
        &quick,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let q = sidecar(&quick);
    assert!(q["metrics"]["force_balance"].is_null());
    assert_eq!(q["metrics"]["phi"], side["metrics"]["phi"]);
    // analyze finds the container in the sidecar and agrees.
    let a = packbench(&["analyze", &format!("{out}.txt")]);
    let m: serde_json::Value = serde_json::from_slice(&a.stdout).unwrap();
    assert_eq!(m["phi"].as_f64().unwrap(), phi);
}

/// `plot --kind trace` draws the traces of runs from their JSON outputs (or from their
/// packings, whose JSON it finds), `gr` overlays packings, and misuse is refused clearly.
#[test]
fn plot_draws_run_traces_and_overlays() {
    let init = tmp("plot_init.txt");
    let init_args = [
        "init", "--N", "60", "--Ndim", "3", "--seed", "3", "--output", &init,
    ];
    assert!(packbench(&init_args).status.success());
    let (ls, fire) = (tmp("plot_ls"), tmp("plot_fire"));
    for (method, out) in [("ls", &ls), ("fire", &fire)] {
        let o = packbench(&[
            "pack", "--method", method, "--file", &init, "--seed", "3", "--quiet", "--output", out,
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let png_magic = |path: &str| std::fs::read(path).unwrap().starts_with(b"\x89PNG");
    let trace = tmp("trace.png");
    let (ls_json, fire_txt) = (format!("{ls}.json"), format!("{fire}.txt"));
    let o = packbench(&[
        "plot", &ls_json, &fire_txt, "--kind", "trace", "--output", &trace,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(png_magic(&trace));
    let gr = tmp("gr.svg");
    let ls_txt = format!("{ls}.txt");
    let o = packbench(&["plot", &ls_txt, &fire_txt, "--kind", "gr", "--output", &gr]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(std::fs::read_to_string(&gr).unwrap().contains("<svg"));
    let refused = [
        (vec!["plot", &ls_txt, &fire_txt], "draws one packing"),
        (
            vec!["plot", &ls_json, "--kind", "trace", "--value", "nope"],
            "no quantity `nope`",
        ),
        (vec!["plot", &init, "--kind", "trace"], "pack --output"),
        (
            vec!["plot", &ls_txt, "--kind", "histogram"],
            "unknown --kind",
        ),
    ];
    for (args, says) in refused {
        let o = packbench(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
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
        (
            vec!["--method", "calippso", "--open-tensile-bonds"],
            "--open-tensile-bonds does not apply to method calippso",
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
        // A parameter the method refuses is bad input (exit 2), with the method's sentence.
        (
            vec!["--method", "adam", "--set", "delta_phi_tol=-1"],
            "adam: invalid parameter: delta_phi_tol",
        ),
        (
            vec!["--method", "ls", "--rate", "fast"],
            "--rate takes a finite number, not `fast`",
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

/// `--open-tensile-bonds` runs closest-jammed's active-set QP form, which ends exactly jammed.
#[test]
fn open_tensile_bonds_flag_runs_the_active_set_qp_form() {
    let out = tmp("cj_open");
    let o = packbench(&[
        "pack",
        "--method",
        "closest-jammed",
        "--open-tensile-bonds",
        "--N",
        "30",
        "--Ndim",
        "3",
        "--phi",
        "0.3",
        "--seed",
        "4",
        "--quiet",
        "--output",
        &out,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let side = sidecar(&out);
    assert_eq!(side["parameters"]["open_tensile_bonds"], true);
    assert_eq!(side["termination"], "jammed");
    assert_eq!(side["metrics"]["iso_gap"], 0);
    assert!(side["metrics"]["max_overlap"].as_f64().unwrap() <= 1e-9);
    assert!(side["metrics"]["force_balance"].as_f64().unwrap() <= 1e-8);
}

/// A packing at contact whose overlaps are rounding (here 1e-13, as an MLS packing at pressure
/// 1e12 has 1e-15) keeps its contacts: it is not shrunk by the 1e-3 margin of overlapping
/// random starts, so closest-jammed starts with every contact bonded and has nothing to grow.
#[test]
fn a_packing_at_contact_is_not_shrunk_before_exact_jamming() {
    let first = tmp("cj_first");
    let pack = |extra: &[&str], output: &str| {
        let mut args = vec![
            "pack",
            "--method",
            "closest-jammed",
            "--seed",
            "4",
            "--quiet",
        ];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--output", output]);
        let o = packbench(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        sidecar(output)
    };
    let jammed = pack(&["--N", "30", "--Ndim", "3", "--phi", "0.3"], &first);
    assert_eq!(jammed["termination"], "jammed");
    // Every diameter 1e-13 larger: the contacts overlap by rounding.
    let file = format!("{first}.txt");
    let text = std::fs::read_to_string(&file).unwrap();
    let unit_box = Container::periodic_box(&[1.0; 3]).unwrap();
    let mut swollen = read_packing(&file, &text, &unit_box).unwrap();
    swollen.scale_diameters(1.0 + 1e-13);
    let start = tmp("cj_swollen.txt");
    std::fs::write(&start, write_text(&swollen)).unwrap();
    let again = pack(&["--file", &start], &tmp("cj_again"));
    assert_eq!(again["termination"], "jammed");
    assert!(again["steps"].as_u64().unwrap() < 10, "{}", again["steps"]);
    let phi = |s: &serde_json::Value| s["metrics"]["phi"].as_f64().unwrap();
    assert!((phi(&again) - phi(&jammed)).abs() < 1e-9);
    assert_eq!(again["metrics"]["iso_gap"], 0);
}

/// A stop request (Ctrl-C's SIGINT, or SIGTERM from Slurm or `kill`) makes a long run save its
/// packing so far, even when it arrives twice at once, as GNU `timeout` delivers it to a
/// background job (once to the child, once to its process group).
#[test]
fn a_stop_request_saves_the_packing_so_far() {
    for signal in ["INT", "TERM"] {
        let out = tmp(&format!("stopped_{signal}"));
        let mut child = common::spawn_packbench(
            "pack --method mls --N 300 --Ndim 3 --dist mono --d 1 --placement poisson \
             --phi 0.05 --seed 1 --set rate_final=1e-12 --save-interval 1 --quiet --output",
            &out,
        );
        // The first snapshot proves the run loop (and so the handler) has started.
        let dir = std::path::Path::new(&out).parent().unwrap().to_path_buf();
        let prefix = format!("stopped_{signal}_step");
        let snapshot_written = || {
            std::fs::read_dir(&dir).unwrap().any(|e| {
                e.unwrap()
                    .file_name()
                    .to_string_lossy()
                    .starts_with(&prefix)
            })
        };
        let waited = std::time::Instant::now();
        while !snapshot_written() {
            assert!(
                child.try_wait().unwrap().is_none(),
                "the run ended before its first snapshot"
            );
            assert!(waited.elapsed().as_secs() < 120, "no snapshot written");
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        let pid = child.id().to_string();
        for _ in 0..2 {
            let kill = Command::new("kill")
                .args([&format!("-{signal}"), &pid])
                .status();
            assert!(kill.expect("kill runs").success());
        }
        let o = child.wait_with_output().expect("waits");
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "SIG{signal}: {stderr}");
        let side = sidecar(&out);
        assert_eq!(side["termination"], "interrupted", "SIG{signal}");
        let text = std::fs::read_to_string(format!("{out}.txt")).unwrap();
        assert_eq!(text.lines().count(), 300);
    }
}

/// An mls run stopped by --max-steps leaves NAME.checkpoint.json, and `pack --resume` continues
/// it to the packing the run without a stop ends in, byte for byte, with the run's own
/// parameters; a method without checkpoints refuses to resume.
#[test]
fn a_stopped_mls_run_resumes_exactly_from_its_checkpoint() {
    let scene = [
        "--method",
        "mls",
        "--N",
        "50",
        "--Ndim",
        "3",
        "--placement",
        "poisson",
        "--seed",
        "3",
        "--rate-final",
        "0.05",
        "--quiet",
        "--no-force-balance",
    ];
    let whole = tmp("mls_whole");
    let o = packbench(&[&["pack"][..], &scene, &["--output", &whole]].concat());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let part = tmp("mls_part");
    let o = packbench(
        &[
            &["pack"][..],
            &scene,
            &["--max-steps", "20000", "--output", &part],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let said = String::from_utf8_lossy(&o.stderr);
    assert!(
        said.contains("checkpoint") && said.contains("--resume"),
        "{said}"
    );
    let checkpoint = format!("{part}.checkpoint.json");
    let rest = tmp("mls_rest");
    // No --rate-final and no --max-steps now: both come from the checkpoint, but for the budget,
    // which a resumed run is given anew.
    let o = packbench(&[
        "pack",
        "--method",
        "mls",
        "--resume",
        &checkpoint,
        "--max-steps",
        "0",
        "--quiet",
        "--no-force-balance",
        "--output",
        &rest,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read_to_string(format!("{whole}.txt")).unwrap(),
        std::fs::read_to_string(format!("{rest}.txt")).unwrap()
    );
    let side = sidecar(&rest);
    assert!(side["extra"]["resumed_at_collisions"].as_u64().unwrap() <= 20000);
    // Its run time is the whole run's, both legs; the extra keeps this leg's.
    let whole_s = side["runtime_s"].as_f64().unwrap();
    assert_eq!(whole_s, side["extra"]["runtime_s"].as_f64().unwrap());
    assert!(whole_s > side["extra"]["this_leg_runtime_s"].as_f64().unwrap());
    let o = packbench(&["pack", "--method", "adam", "--resume", &checkpoint]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("cannot resume"));
}
