//! A standard output closed before `dem` writes to it (`dem bench ... | head -1`) ends the
//! program without a panic.

use std::process::{Command, Stdio};

#[cfg(unix)]
#[test]
fn closed_stdout_is_not_a_panic() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_dem"))
        .args(["bench", "bonded", "--cells", "5,5", "--steps", "20"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Close the read end at once: the benchmark prints only after its run.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "stderr: {err}");
    assert_ne!(out.status.code(), Some(101), "stderr: {err}");
}
