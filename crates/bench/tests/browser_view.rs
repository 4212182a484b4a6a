//! `packbench view` pages opened in a real browser: headless Chromium with software WebGL
//! (SwiftShader). Each page must load with no error, report as many drawn spheres as the
//! packing has particles, show sphere colours in the middle of a screenshot, and make no
//! network request (Chromium's own network log is checked, behind a proxy that refuses).
//!
//! Needs the `chromium` package. Without it the tests say so and pass, except when the
//! environment variable `CI` is set: then a missing browser is a failure.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;

use common::packbench;

/// One browser at a time: two cores do not run several SwiftShader pages well.
static BROWSER: Mutex<()> = Mutex::new(());

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("packbench_browser_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The Chromium binary, or `None` (a failure under `CI`).
fn chromium() -> Option<PathBuf> {
    let found = ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .flat_map(|name| {
            std::env::var_os("PATH")
                .map(|p| {
                    std::env::split_paths(&p)
                        .map(|d| d.join(name))
                        .collect::<Vec<_>>()
                })
                .unwrap_or_default()
        })
        .find(|p| p.is_file());
    if found.is_none() {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI is set but no chromium is installed: install the Debian package `chromium`"
        );
        eprintln!("browser_view: no chromium on PATH, skipping (install `chromium` to run it)");
    }
    found
}

/// What one headless load of a page gave.
struct Load {
    /// The DOM after the page's scripts ran.
    dom: String,
    /// Chromium's log (console messages included).
    log: String,
    /// Chromium's network log (JSON).
    net_log: String,
}

/// Seconds a Chromium load may take before coreutils' `timeout` stops it (SIGTERM, then
/// SIGKILL 10 s later): a page that hangs fails the test instead of hanging the suite. A load
/// takes a few seconds; its virtual time budget is 20 s.
const CHROMIUM_TIMEOUT_S: &str = "300";

/// Loads `page` headless with software WebGL, no network (a refusing proxy, no DNS) and a
/// fresh profile; `extra` adds `--dump-dom` or `--screenshot=…`.
fn load(browser: &Path, page: &Path, work: &Path, extra: &str) -> Load {
    let profile = work.join(format!("profile{}", extra.len()));
    let net_log = work.join(format!("netlog{}.json", extra.len()));
    let out = Command::new("timeout")
        .args(["--kill-after=10", CHROMIUM_TIMEOUT_S])
        .arg(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--ignore-gpu-blocklist",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-extensions",
            "--proxy-server=127.0.0.1:9",
            "--host-resolver-rules=MAP * ~NOTFOUND",
            "--enable-logging=stderr",
            "--v=0",
            "--window-size=1000,700",
            "--virtual-time-budget=20000",
            &format!("--user-data-dir={}", profile.display()),
            &format!("--log-net-log={}", net_log.display()),
            extra,
        ])
        .arg(format!("file://{}", page.canonicalize().unwrap().display()))
        .current_dir(work)
        .output()
        .expect("chromium starts");
    // `timeout` exits 124 when it stopped the command (137 after SIGKILL).
    assert!(
        !matches!(out.status.code(), Some(124) | Some(137)),
        "chromium did not finish loading {} within {CHROMIUM_TIMEOUT_S} s",
        page.display()
    );
    Load {
        dom: String::from_utf8_lossy(&out.stdout).into_owned(),
        log: String::from_utf8_lossy(&out.stderr).into_owned(),
        net_log: std::fs::read_to_string(&net_log).unwrap_or_default(),
    }
}

/// The value of attribute `name` on the page's `<html>` element in a dumped DOM.
fn html_attribute(dom: &str, name: &str) -> Option<String> {
    let start = dom.find("<html")?;
    let tag = &dom[start..start + dom[start..].find('>')?];
    let key = format!(" {name}=\"");
    let at = tag.find(&key)? + key.len();
    Some(tag[at..at + tag[at..].find('"')?].to_string())
}

/// Fraction of pixels in the central third of a PNG screenshot that are clearly coloured
/// (sphere colours: not the white background, not grey lines or text).
fn coloured_fraction_in_middle(png_path: &Path) -> f64 {
    let decoder = png::Decoder::new(std::fs::File::open(png_path).expect("screenshot written"));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let (w, h) = (info.width as usize, info.height as usize);
    let (mut coloured, mut total) = (0usize, 0usize);
    for y in h / 3..2 * h / 3 {
        for x in w / 3..2 * w / 3 {
            let p = &buf[(y * w + x) * channels..(y * w + x) * channels + 3];
            let (max, min) = (*p.iter().max().unwrap(), *p.iter().min().unwrap());
            total += 1;
            if max - min > 40 {
                coloured += 1;
            }
        }
    }
    coloured as f64 / total as f64
}

/// Loads `page` twice (DOM and screenshot) and checks everything; `panel_spheres` is the
/// expected `data-spheres` of each panel in order (the page's is their sum). Returns what
/// was wrong, so that a broken page can be shown to fail.
fn inspect(browser: &Path, name: &str, page: &Path, panel_spheres: &[usize]) -> Result<(), String> {
    let _one_at_a_time = BROWSER.lock().unwrap_or_else(|e| e.into_inner());
    let work = tmp(&format!("{name}_browser"));
    let run = load(browser, page, &work, "--dump-dom");
    if let Some(errors) = html_attribute(&run.dom, "data-errors") {
        return Err(format!("{name}: the page reported errors: {errors}"));
    }
    let console: Vec<&str> = run
        .log
        .lines()
        .filter(|l| l.contains("CONSOLE") && (l.contains("Uncaught") || l.contains("Error")))
        .collect();
    if !console.is_empty() {
        return Err(format!("{name}: console errors: {console:#?}"));
    }
    if html_attribute(&run.dom, "data-ready").as_deref() != Some("1") {
        return Err(format!("{name}: the page never finished drawing"));
    }
    let total: usize = panel_spheres.iter().sum();
    if html_attribute(&run.dom, "data-spheres") != Some(total.to_string()) {
        return Err(format!(
            "{name}: {:?} spheres drawn, {total} expected",
            html_attribute(&run.dom, "data-spheres")
        ));
    }
    let drawn: Vec<usize> = run
        .dom
        .match_indices("class=\"panel\" data-spheres=\"")
        .map(|(at, m)| {
            let rest = &run.dom[at + m.len()..];
            rest[..rest.find('"').unwrap()].parse().unwrap()
        })
        .collect();
    if drawn != panel_spheres {
        return Err(format!(
            "{name}: spheres per panel {drawn:?}, expected {panel_spheres:?}"
        ));
    }
    no_network_requests(name, &run.net_log)?;
    let shot = work.join("shot.png");
    let run = load(
        browser,
        page,
        &work,
        &format!("--screenshot={}", shot.display()),
    );
    no_network_requests(name, &run.net_log)?;
    let coloured = coloured_fraction_in_middle(&shot);
    if let Some(dir) = std::env::var_os("PACKBENCH_KEEP_SCREENSHOTS") {
        std::fs::copy(&shot, Path::new(&dir).join(format!("{name}.png"))).unwrap();
    }
    if coloured < 0.15 {
        return Err(format!(
            "{name}: only {:.1}% of the screenshot's middle is sphere-coloured",
            100.0 * coloured
        ));
    }
    Ok(())
}

/// Checks a page packbench wrote: its text, then in the browser.
fn check_page(name: &str, page: &Path, panel_spheres: &[usize]) {
    let html = std::fs::read_to_string(page).unwrap();
    assert_no_network_references(&html);
    let Some(browser) = chromium() else { return };
    if let Err(e) = inspect(&browser, name, page, panel_spheres) {
        panic!("{e}");
    }
}

/// The page names no remote resource: no `http(s)://` anywhere in its text (three.js and the
/// viewer sit inside it as `data:` modules), no external script, stylesheet or image.
fn assert_no_network_references(html: &str) {
    for needle in [
        "http://",
        "https://",
        "<script src",
        "<link",
        "<img",
        "@import",
        "url(",
    ] {
        assert!(!html.contains(needle), "the page contains `{needle}`");
    }
    assert!(html.contains("default-src 'none'"), "the page lost its CSP");
}

/// Chromium's network log shows no request made by the page. Requests of a page opened from
/// disk carry the initiator `null` (its opaque origin); Chromium's own background requests
/// (which the flags do not fully silence, and the refusing proxy fails) carry `not an origin`.
fn no_network_requests(name: &str, net_log: &str) -> Result<(), String> {
    let log: serde_json::Value = serde_json::from_str(net_log)
        .map_err(|e| format!("{name}: chromium wrote no readable network log: {e}"))?;
    let events = log["events"].as_array().expect("net log events");
    let from_page: Vec<&str> = events
        .iter()
        .filter_map(|e| {
            let p = &e["params"];
            let initiator = p["initiator"].as_str()?;
            (initiator != "not an origin").then(|| p["url"].as_str().unwrap_or(initiator))
        })
        .collect();
    if from_page.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{name}: the page made network requests: {from_page:?}"
        ))
    }
}

/// Runs `packbench ARGS`, asserting success.
fn ok(args: &[&str]) {
    let out = packbench(args);
    assert!(
        out.status.success(),
        "packbench {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Runs `packbench pack FLAGS --quiet --output DIR/run`, then `packbench view DIR/run.EXT`,
/// and returns the page.
fn packed_and_viewed(name: &str, flags: &str, ext: &str) -> PathBuf {
    let dir = tmp(name);
    let run = dir.join("run");
    let run = run.to_str().unwrap();
    let mut args: Vec<&str> = flags.split_whitespace().collect();
    args.extend(["--quiet", "--output", run]);
    ok(&args);
    let page = dir.join("run.html");
    ok(&[
        "view",
        &format!("{run}.{ext}"),
        "--output",
        page.to_str().unwrap(),
    ]);
    page
}

#[test]
fn a_3d_packing_page_draws_every_sphere_in_a_real_browser() {
    let page = packed_and_viewed(
        "pack3d",
        "pack --method fire --N 60 --Ndim 3 --dist bidisperse --d1 1 --d2 1.4 --p 0.5 --seed 2",
        "json",
    );
    check_page("pack3d", &page, &[60]);
}

#[test]
fn a_2d_run_page_with_snapshots_draws_every_disk_in_a_real_browser() {
    let page = packed_and_viewed(
        "run2d",
        "pack --method mls --N 30 --Ndim 2 --phi 0.3 --seed 4 --save-interval 200",
        "txt",
    );
    check_page("run2d", &page, &[30]);
}

#[test]
fn a_comparison_page_draws_one_panel_per_method_in_a_real_browser() {
    let dir = tmp("compare");
    let out = dir.join("cmp");
    ok(&[
        "compare",
        "--methods",
        "fire,adam",
        "--N",
        "24",
        "--seeds",
        "2",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    let page = out.join("viewer.html");
    assert!(page.is_file(), "compare wrote no viewer.html");
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        report.contains("(viewer.html)"),
        "the report does not link the viewer"
    );
    check_page("compare", &page, &[24, 24]);
}

/// The checks catch a broken page: a script error, a wrong sphere count, and a page that
/// fetches from the network quietly (its policy removed so the request really goes out, the
/// failure swallowed so only the network log can tell).
#[test]
fn the_browser_checks_fail_on_a_broken_page() {
    let dir = tmp("broken");
    let packing = dir.join("p.txt");
    let mut text = String::new();
    for i in 0..8 {
        let c = |k: usize| if i >> k & 1 == 1 { 0.75 } else { 0.25 };
        text.push_str(&format!("{} {} {} 0.5\n", c(0), c(1), c(2)));
    }
    std::fs::write(&packing, text).unwrap();
    let page = dir.join("p.html");
    ok(&[
        "view",
        packing.to_str().unwrap(),
        "--output",
        page.to_str().unwrap(),
    ]);
    let html = std::fs::read_to_string(&page).unwrap();
    let Some(browser) = chromium() else { return };
    inspect(&browser, "unbroken", &page, &[8]).unwrap();
    let script = "<script type=\"module\">\n";
    assert!(html.contains(script));
    let broken = [
        (
            "script_error",
            html.replacen(script, &format!("{script}null.x;\n"), 1),
        ),
        ("wrong_count", html.clone()),
        (
            "network",
            html.replace("default-src 'none'", "default-src *")
                .replacen(
                    "<body>",
                    "<body><script>fetch('http://example.com/x').catch(function () {})</script>",
                    1,
                ),
        ),
    ];
    for (name, text) in broken {
        let path = dir.join(format!("{name}.html"));
        std::fs::write(&path, text).unwrap();
        let expected: &[usize] = if name == "wrong_count" { &[9] } else { &[8] };
        let found = inspect(&browser, name, &path, expected);
        assert!(found.is_err(), "{name}: the broken page passed");
    }
}
