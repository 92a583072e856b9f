//! Where commands write and what they print on stderr: `bench` writes only where it is told
//! (the tracked tables need `--update-tracked`), and progress never reaches a pipe.

use crate::common::{run, temp_dir};

#[test]
fn bench_without_a_destination_is_refused_and_writes_nothing() {
    let before = std::fs::read(crate::common::repo_path("reports/bench/fem.md")).ok();
    for args in [
        &["bench", "fem"][..],
        &["bench", "fem", "--out", "reports/bench"][..],
    ] {
        let o = run(args, None);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("--update-tracked"), "{args:?}: {err}");
    }
    let after = std::fs::read(crate::common::repo_path("reports/bench/fem.md")).ok();
    assert_eq!(before, after, "the tracked table is untouched");
}

#[test]
fn bench_writes_its_tables_where_it_is_told() {
    let d = temp_dir("bench-out");
    let o = run(
        &["bench", "fem", "--out", d.to_str().unwrap(), "--json"],
        None,
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(d.join("fem.json").exists() && d.join("fem.md").exists());
    let _ = std::fs::remove_dir_all(&d);
}

/// stderr is a pipe here, so the spinner must stay silent: no carriage returns or terminal
/// escape sequences (what an indicatif frame is made of) in the captured text, with or
/// without --quiet.
#[test]
fn progress_never_reaches_a_pipe() {
    let d = temp_dir("progress");
    let out = d.join("r");
    let o = run(
        &[
            "qualify",
            "test-specs/verification/cantilever.toml",
            "--out",
            out.to_str().unwrap(),
        ],
        None,
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.code() == Some(1), "{err}");
    assert!(!err.contains('\r') && !err.contains('\u{1b}'), "{err:?}");
    let _ = std::fs::remove_dir_all(&d);
}
