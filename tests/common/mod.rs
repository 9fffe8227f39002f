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

/// A path for `name` in this test binary's directory under the target's `tmp`, with no file
/// there yet: a file the last run left would pass a test that a command writes nothing
/// (none of it is left in the system's temporary directory).
pub fn tmp(name: &str) -> String {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(env!("CARGO_CRATE_NAME"));
    std::fs::create_dir_all(&d).unwrap();
    let path = d.join(name);
    // Absent is what is wanted: a failure to remove shows in the test that needs it so.
    let _ = std::fs::remove_file(&path);
    path.to_string_lossy().into_owned()
}
