//! The host link's scenarios (`tests/link/*.txt`): lines sent (`> `), the replies that must come
//! back (`< `, `*` matches anything), `= run`, where the run that START asked for is made by the
//! firmware's run logic on the twin, and `= reboot`, which starts a new session from the record
//! SAVE wrote (as the firmware loads it at boot). Every line goes through the byte-level
//! assembler the firmware uses, and every reply must be expected.

use nf_instrument::run::RunConfig;
use nf_instrument::session::{Action, LineAssembler, Session};
use nf_instrument::settings::{self, MAX_BYTES};
use nf_twin::{Recorder, TwinConfig, simulate};

fn matches(pattern: &str, text: &str) -> bool {
    let parts: Vec<&str> = pattern.split('*').collect();
    let (first, last) = (parts[0], parts[parts.len() - 1]);
    if parts.len() == 1 {
        return pattern == text;
    }
    if !text.starts_with(first) || !text[first.len()..].ends_with(last) {
        return false;
    }
    let mut rest = &text[first.len()..text.len() - last.len()];
    for mid in &parts[1..parts.len() - 1] {
        match rest.find(mid) {
            Some(i) => rest = &rest[i + mid.len()..],
            None => return false,
        }
    }
    true
}

fn play(name: &str, script: &str) {
    let mut session = Session::default();
    let mut lines = LineAssembler::default();
    let mut pending: Vec<String> = Vec::new();
    let mut start_asked = false;
    let mut saved: Option<Vec<u8>> = None;
    for (k, step) in script.lines().enumerate() {
        let at = format!("{name}:{}", k + 1);
        if let Some(sent) = step.strip_prefix('>') {
            assert!(
                pending.is_empty(),
                "{at}: replies not expected by the scenario: {pending:?}"
            );
            for b in sent.trim_start().bytes().chain(*b"\r\n") {
                if let Some(event) = lines.push(b) {
                    let (action, reply) = session.handle(event);
                    start_asked |= action == Action::Start;
                    pending.extend(reply.iter().map(|l| l.to_string()));
                    if action == Action::Save {
                        let mut bytes = [0; MAX_BYTES];
                        let n = settings::encode(&session.cfg, &mut bytes);
                        saved = Some(bytes[..n].to_vec());
                        pending.push("OK".into());
                    }
                }
            }
        } else if let Some(want) = step.strip_prefix("< ") {
            assert!(!pending.is_empty(), "{at}: expected '{want}', no reply came");
            let got = pending.remove(0);
            assert!(matches(want, &got), "{at}: expected '{want}', got '{got}'");
        } else if step == "= run" {
            assert!(start_asked, "{at}: no START to run");
            let mut rec = Recorder::default();
            let (report, _) = simulate(&TwinConfig::default(), &session.cfg, &mut rec);
            session.finished(report);
            start_asked = false;
        } else if step == "= reboot" {
            let cfg = saved.as_deref().map_or(Ok(RunConfig::DEFAULT), settings::decode);
            session = Session::new(cfg.unwrap_or_else(|e| panic!("{at}: the saved record: {e:?}")));
            lines = LineAssembler::default();
        } else {
            assert!(
                step.is_empty() || step.starts_with('#'),
                "{at}: not a scenario line: {step}"
            );
        }
    }
    assert!(
        pending.is_empty(),
        "{name}: replies not expected at the end: {pending:?}"
    );
}

#[test]
fn every_scenario_plays_as_written() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/link");
    let mut played = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        play(&name, &std::fs::read_to_string(&path).unwrap());
        played += 1;
    }
    assert!(played >= 5, "{played} scenarios in {}", dir.display());
}

#[test]
fn a_wrong_reply_fails_the_scenario() {
    let r = std::panic::catch_unwind(|| play("wrong", "> STATUS\n< STATUS running\n"));
    assert!(r.is_err());
    let r = std::panic::catch_unwind(|| play("unexpected", "> STATUS\n> STATUS\n< STATUS idle\n"));
    assert!(r.is_err());
    assert!(matches("a * c * e", "a b c d e") && !matches("a * c", "a b d"));
}
