//! `dem bench cutting`: it runs, prints the state digest, the digest does not depend on the
//! thread count (the determinism contract), and bad flags are messages with exit code 2 naming
//! the flag. (A smoke test: the speed figures are benchmarks, never checked here.)

use std::process::{Command, Output};

mod common;
use common::text;

fn dem(args: &[&str]) -> Output {
    // From the repository root: the default --model and --material are relative to it.
    Command::new(env!("CARGO_BIN_EXE_dem"))
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .args(args)
        .output()
        .unwrap()
}

fn digest(o: &Output) -> String {
    let t = String::from_utf8_lossy(&o.stdout);
    t.lines()
        .find_map(|l| l.strip_prefix("state digest: "))
        .unwrap_or_else(|| panic!("no digest line in\n{}", text(o)))
        .to_string()
}

#[test]
fn bench_cutting_runs_and_its_digest_does_not_depend_on_threads() {
    let one = dem(&["bench", "cutting", "--steps", "200", "--threads", "1"]);
    assert!(one.status.success(), "{}", text(&one));
    let t = String::from_utf8_lossy(&one.stdout).to_string();
    assert!(t.contains("discs") && t.contains("intact bonds"), "{t}");
    let last = t.lines().last().unwrap_or_default();
    assert!(last.starts_with("particle-steps/s: "), "{t}");
    let two = dem(&["bench", "cutting", "--steps", "200", "--threads", "2"]);
    assert!(two.status.success(), "{}", text(&two));
    assert_eq!(digest(&one), digest(&two), "{t}\n{}", text(&two));
}

#[test]
fn bench_cutting_bad_flags_name_the_flag() {
    for (args, flag) in [
        (&["--steps", "0"][..], "--steps"),
        (&["--threads", "0"][..], "--threads"),
        (&["--method", "granular"][..], "--method"),
        (&["--speed", "0"][..], "--speed"),
        (
            &["--specimen", "/nonexistent/specimen.json"][..],
            "--specimen",
        ),
        (&["--model", "/nonexistent/model.json"][..], "--model"),
        (&["--steps", "100000000"][..], "--steps"),
    ] {
        let mut a = vec!["bench", "cutting"];
        a.extend_from_slice(args);
        let o = dem(&a);
        let t = text(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {t}");
        assert!(t.contains(flag), "{args:?}: {t}");
        assert!(!t.contains("panicked"), "{args:?}: {t}");
    }
}
