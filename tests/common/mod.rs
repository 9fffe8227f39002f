//! What the integration tests that run the `nf` binary share.

use std::process::Command;

/// Runs `nf` with `args`: exit code, standard output, standard error.
pub fn nf(args: &[&str]) -> (i32, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_nf")).args(args).output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into(),
        String::from_utf8_lossy(&o.stderr).into(),
    )
}

/// A path for `name` in a directory of this test binary and process.
pub fn tmp(name: &str) -> String {
    let d = std::env::temp_dir().join(format!("nf-{}-{}", env!("CARGO_CRATE_NAME"), std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name).to_string_lossy().into_owned()
}
