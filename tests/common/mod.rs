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

/// A path for `name` in this test binary's directory under the target's `tmp` (each run
/// writes over the last; none of it is left in the system's temporary directory).
pub fn tmp(name: &str) -> String {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(env!("CARGO_CRATE_NAME"));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name).to_string_lossy().into_owned()
}
