//! `packbench view` and `packbench animate` from the command line, without a browser: what
//! the page holds and what the GIF is made of.

mod common;

use common::packbench;

fn tmp(name: &str) -> std::path::PathBuf {
    let dir =
        std::env::temp_dir().join(format!("packbench_cli_view_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The JSON data block of a page.
fn page_data(html: &str) -> serde_json::Value {
    let open = "id=\"packbench-data\">";
    let start = html.find(open).expect("data block") + open.len();
    let end = start + html[start..].find("</script>").unwrap();
    serde_json::from_str(&html[start..end]).unwrap()
}

/// A 2D MLS run with snapshots: the page has one frame per snapshot plus the final packing,
/// metrics only on the final one, equal to `packbench analyze`; the GIF has a frame per
/// snapshot; bad flags exit 2.
#[test]
fn a_run_with_snapshots_becomes_a_timeline_and_a_gif() {
    let dir = tmp("run");
    let run = dir.join("run");
    let run = run.to_str().unwrap();
    let out = packbench(&[
        "pack",
        "--method",
        "mls",
        "--N",
        "20",
        "--Ndim",
        "2",
        "--phi",
        "0.3",
        "--seed",
        "3",
        "--save-interval",
        "500",
        "--quiet",
        "--output",
        run,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let snapshots = std::fs::read_dir(&dir)
        .unwrap()
        .filter(|e| {
            let name = e.as_ref().unwrap().file_name();
            name.to_string_lossy().starts_with("run_step")
        })
        .count();
    assert!(snapshots >= 2, "{snapshots} snapshots");
    let page = dir.join("run.html");
    let out = packbench(&["view", &format!("{run}.json"), "--max-frames", "1000"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let data = page_data(&std::fs::read_to_string(&page).unwrap());
    let frames = data["panels"][0]["frames"].as_array().unwrap();
    assert_eq!(frames.len(), snapshots + 1);
    assert!(frames[..snapshots].iter().all(|f| f["metrics"].is_null()));
    let analyzed = packbench(&["analyze", &format!("{run}.txt")]);
    let analyzed: serde_json::Value = serde_json::from_slice(&analyzed.stdout).unwrap();
    assert_eq!(frames[snapshots]["metrics"], analyzed);
    let steps: Vec<u64> = frames.iter().map(|f| f["step"].as_u64().unwrap()).collect();
    assert!(steps.windows(2).all(|w| w[0] < w[1]), "{steps:?}");
    assert!(
        !data["panels"][0]["trace"]["phi"]
            .as_array()
            .unwrap()
            .is_empty()
    );

    let thinned = packbench(&[
        "view",
        run,
        "--max-frames",
        "3",
        "--output",
        page.to_str().unwrap(),
    ]);
    assert!(thinned.status.success());
    let data = page_data(&std::fs::read_to_string(&page).unwrap());
    assert_eq!(data["panels"][0]["frames"].as_array().unwrap().len(), 3);

    let gif = dir.join("run.gif");
    let out = packbench(&["animate", &format!("{run}.json"), "--size", "96"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(&gif).unwrap();
    assert_eq!(&bytes[..6], b"GIF89a");
    let bad = packbench(&["animate", &format!("{run}.json"), "--size", "8"]);
    assert_eq!(bad.status.code(), Some(2));
    let missing = packbench(&["view", dir.join("nothing.txt").to_str().unwrap()]);
    assert_eq!(missing.status.code(), Some(2));
}
