//! Monte Carlo determinism: the output for a seed is identical whatever the number
//! of threads. `RAYON_NUM_THREADS` only sizes rayon's global pool once per process, so the
//! test runs the same call inside explicit pools of 1 and 4 threads, which is what that
//! variable selects.

use satqual::separation::{Model, monte_carlo};

fn model() -> Model {
    let scene = crate::common::load(satqual::catalogue::PAPER_STACK);
    let mut m = Model::from_scene(&scene).unwrap();
    // Keep the test fast: rigid bars, the top two releases (the rest stay latched).
    m.bars = None;
    for t in m.release_times_s.iter_mut().skip(2) {
        *t = None;
    }
    m
}

#[test]
fn monte_carlo_is_identical_for_any_thread_count() {
    let m = model();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| monte_carlo(&m, 12, 42).unwrap())
    };
    let one = run(1);
    let four = run(4);
    assert_eq!(one, four, "bit-identical percentiles with 1 and 4 threads");
    // The dispersions did act: the runs differ from each other.
    let s = &one.satellites[0].final_speed_m_s;
    assert!(s.p99.value > s.p1.value, "{s:?}");
    assert!(
        one.min_clearance_m
            .expect("six satellites have pairs")
            .p50
            .value
            > 0.0
    );
    // Another seed gives another sample.
    let other = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap()
        .install(|| monte_carlo(&m, 12, 43).unwrap());
    assert_ne!(
        one.satellites[0].final_speed_m_s,
        other.satellites[0].final_speed_m_s
    );
}

/// A single satellite has no pair: its Monte Carlo has no clearance percentiles (null, not a
/// 0 m that reads as a collision), and `--monte-carlo 0` is refused rather than printing
/// percentiles of no sample.
#[test]
fn a_single_satellite_has_no_clearance_and_zero_runs_are_refused() {
    let text = satqual::catalogue::generated::small_stack(1, 1.5, "", "");
    let m = satqual::separation::Model::from_scene(&crate::common::parse(&text)).unwrap();
    let mc = monte_carlo(&m, 2, 1).unwrap();
    assert!(mc.min_clearance_m.is_none(), "{:?}", mc.min_clearance_m);
    let d = crate::common::temp_dir("mc-one-sat");
    let scene = d.join("one.toml");
    std::fs::write(&scene, text).unwrap();
    let s = scene.to_str().unwrap();
    let (code, out, err) =
        crate::common::run_text(&["separate", s, "--monte-carlo", "2", "--seed", "1"], None);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("min clearance P0.27 n/a (one satellite, no pair)"),
        "{out}"
    );
    let (code, _, err) =
        crate::common::run_text(&["separate", s, "--monte-carlo", "0", "--seed", "1"], None);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("a Monte Carlo needs at least 1 run"), "{err}");
}
