//! `--report` of `nf fit`, `nf diagnose` and `nf allan`: one self-contained HTML page, loaded in
//! headless Chromium, which must render it without errors and show the result. Chromium is
//! required where `NF_REQUIRE_CHROMIUM` is set (`.ci/run` installs it); elsewhere the page is
//! checked as text only.

use std::process::Command;

mod common;
use common::{nf, tmp};

/// Runs `nf`, which must succeed.
fn nf_ok(args: &[&str]) {
    let (code, _, err) = nf(args);
    assert_eq!(code, 0, "nf {args:?}: {err}");
}

fn chromium() -> Option<&'static str> {
    ["chromium", "chromium-browser", "google-chrome"].into_iter().find(|c| {
        Command::new(c)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

/// The DOM Chromium builds from the page, and what it logged.
fn render(browser: &str, page: &str) -> (String, String) {
    let profile = tmp("chromium-profile");
    let o = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--enable-logging=stderr",
            &format!("--user-data-dir={profile}"),
            "--dump-dom",
            &format!("file://{page}"),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "chromium: {}", String::from_utf8_lossy(&o.stderr));
    (
        String::from_utf8_lossy(&o.stdout).into(),
        String::from_utf8_lossy(&o.stderr).into(),
    )
}

#[test]
fn reports_are_whole_pages_that_render_and_show_the_result() {
    let run = tmp("run.csv");
    nf_ok(&["simulate", "--n", "24", "--dwell", "0.5", "--tilt", "0.2", "-o", &run]);
    let log = tmp("static.csv");
    nf_ok(&["simulate", "--n", "72", "--dwell", "0.5", "-o", &log]);
    let cases = [
        (vec!["fit", run.as_str()], "azimuth psi"),
        (vec!["diagnose", run.as_str()], "final psi"),
        (vec!["allan", log.as_str()], "N: "),
    ];
    let browser = chromium();
    if browser.is_none() {
        assert!(
            std::env::var_os("NF_REQUIRE_CHROMIUM").is_none(),
            "NF_REQUIRE_CHROMIUM is set and no Chromium was found"
        );
    }
    for (k, (args, shows)) in cases.into_iter().enumerate() {
        let page = tmp(&format!("report{k}.html"));
        let mut args = args.clone();
        args.extend(["--report", &page]);
        nf_ok(&args);
        let html = std::fs::read_to_string(&page).unwrap();
        assert!(
            html.starts_with("<!DOCTYPE html>") && html.contains("<svg") && !html.contains("<script"),
            "{page}"
        );
        assert!(html.contains(&format!("<p id=\"headline\">{shows}")), "{page}: {html}");
        if let Some(b) = browser {
            let (dom, log) = render(b, &page);
            assert!(
                dom.contains("id=\"headline\"") && dom.contains(shows) && dom.contains("<svg"),
                "{page}: {dom}"
            );
            assert!(
                !log.contains("Uncaught") && !log.contains("ERROR:CONSOLE"),
                "{page}: {log}"
            );
        }
    }
}
