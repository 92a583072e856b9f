//! The `satqual modal` command-line contract: exit codes, JSON on stdout with the human table
//! on stderr, prestress fields, matrix export, and clean errors for bad input.

use crate::common;

fn satqual(args: &[&str]) -> std::process::Output {
    common::run(args, None)
}

#[test]
fn modal_json_contract() {
    let out = satqual(&["modal", "test-specs/verification/cantilever.toml", "--json"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("stdout is JSON");
    // 20×20 mm × 1 m steel: 3.14 kg.
    assert!((v["total_mass_kg"].as_f64().unwrap() - 0.02 * 0.02 * 1.0 * 7850.0).abs() < 1e-9);
    let modes = v["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 10, "[modal] modes = 10");
    assert_eq!(modes[0]["index"], 1);
    assert!((modes[0]["frequency_hz"].as_f64().unwrap() - 16.710).abs() < 0.02);
    for k in ["x", "y", "z", "rx", "ry", "rz"] {
        assert!(
            modes[0]["effective_mass_fraction"][k].is_number(),
            "missing {k}"
        );
    }
    assert!(
        v.get("prestress").is_none(),
        "no static loads, no prestress block"
    );
    // The human table went to stderr.
    assert!(String::from_utf8_lossy(&out.stderr).contains("freq [Hz]"));
}

#[test]
fn modal_human_output_goes_to_stdout_without_json() {
    let out = satqual(&[
        "modal",
        "test-specs/verification/nafems-fv5.toml",
        "--modes",
        "3",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let s = String::from_utf8_lossy(&out.stdout);
    assert!(
        s.contains("freq [Hz]")
            && s.lines()
                .filter(|l| l.trim_start().starts_with(['1', '2', '3']))
                .count()
                >= 3,
        "{s}"
    );
}

#[test]
fn fmax_override_limits_modes() {
    let out = satqual(&[
        "modal",
        "test-specs/verification/cantilever.toml",
        "--fmax",
        "200",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let f: Vec<f64> = v["modes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["frequency_hz"].as_f64().unwrap())
        .collect();
    assert_eq!(f.len(), 4, "{f:?}");
    assert!(f.iter().all(|x| *x <= 200.0));
}

#[test]
fn prestress_block_and_export() {
    let dir = crate::common::temp_dir("export");
    let scene = dir.join("bar.toml");
    let text = std::fs::read_to_string("test-specs/verification/cantilever.toml")
        .unwrap()
        .replace(
            "[modal]",
            "[[static_load]]\nnode = 2\nforce_n = [-1000.0, 0.0, 0.0]\n\n[modal]",
        );
    std::fs::write(&scene, text).unwrap();
    let out = satqual(&[
        "modal",
        scene.to_str().unwrap(),
        "--json",
        "--export-matrices",
        dir.join("mtx").to_str().unwrap(),
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // Cantilever under 1 kN compression: P_cr = π²EI/(4L²) = 6 907.6 N -> λ = 6.9076 (Euler
    // column, clamped-free); 1e-3 with 20 elements.
    let ei = 210e9 * 0.02f64.powi(4) / 12.0;
    let expect = std::f64::consts::PI.powi(2) * ei / 4.0 / 1000.0;
    let lambda = v["prestress"]["buckling_factor"].as_f64().unwrap();
    assert!(
        (lambda - expect).abs() < 1e-3 * expect,
        "{lambda} vs {expect}"
    );
    for f in ["K.mtx", "M.mtx", "KG.mtx", "dofs.csv"] {
        let p = dir.join("mtx").join(f);
        let s = std::fs::read_to_string(&p).unwrap_or_else(|_| panic!("{} missing", p.display()));
        assert!(s.len() > 100);
    }
    let k = std::fs::read_to_string(dir.join("mtx/K.mtx")).unwrap();
    assert!(k.starts_with("%%MatrixMarket matrix coordinate real symmetric"));
    let dofs = std::fs::read_to_string(dir.join("mtx/dofs.csv")).unwrap();
    assert_eq!(dofs.lines().count(), 121, "header + 120 reduced DOFs");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_scene_exits_2_with_location_and_no_panic() {
    let dir = crate::common::temp_dir("bad");
    let scene = dir.join("bad.toml");
    let text = std::fs::read_to_string("test-specs/verification/cantilever.toml")
        .unwrap()
        .replace("density_kg_m3 = 7850", "density_kg_m3 = -7850");
    std::fs::write(&scene, &text).unwrap();
    let out = satqual(&["modal", scene.to_str().unwrap(), "--json"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    let line = text
        .lines()
        .position(|l| l.contains("density_kg_m3"))
        .unwrap()
        + 1;
    assert!(
        err.contains(&format!("bad.toml:{line}:")) && err.contains("material[0].density_kg_m3"),
        "{err}"
    );
    assert!(!err.contains("panicked") && out.stdout.is_empty(), "{err}");
    let out = satqual(&["modal", dir.join("missing.toml").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("missing.toml"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn json_is_deterministic_across_thread_counts() {
    let run = |threads: &str| {
        common::run(
            &["modal", "test-specs/verification/nafems-fv4.toml", "--json"],
            Some(threads),
        )
        .stdout
    };
    assert_eq!(run("1"), run("2"));
}

/// A dense symmetric matrix from a Matrix Market file of its lower triangle.
fn read_mtx(path: &std::path::Path) -> faer::Mat<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('%'));
    let n: usize = lines
        .next()
        .unwrap()
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let mut a = faer::Mat::<f64>::zeros(n, n);
    for l in lines {
        let v: Vec<&str> = l.split_whitespace().collect();
        let (i, j): (usize, usize) = (v[0].parse().unwrap(), v[1].parse().unwrap());
        let x: f64 = v[2].parse().unwrap();
        a[(i - 1, j - 1)] = x;
        a[(j - 1, i - 1)] = x;
    }
    a
}

#[test]
fn exported_matrices_alone_reproduce_a_base_drive_response() {
    // The files of --export-matrices (KKG.mtx, M.mtx, influence.csv) and the scene's damping
    // (the shaker scene, clamped, set to Q = 15, ζ = 1/(2Q) for every mode) reproduce the direct frequency response of
    // `satqual::response` (src/response/frf.rs: the complex solve of (K − ω²M + iωC)·u = −p
    // with C = MΦ·diag(2ζω)·(MΦ)ᵀ) at 50 Hz along y, with a small dense solve. Tolerance 1e-9
    // relative: the files round-trip every value in 18 digits, so only the summation order of
    // the assembly differs.
    let dir = crate::common::temp_dir("export-influence");
    std::fs::create_dir_all(&dir).unwrap();
    let shaker = crate::common::load("test-specs/shaker-2sat.toml");
    let damping = shaker.text.find("\n[damping]\n").unwrap();
    let damping_end = damping + 1 + shaker.text[damping + 1..].find("\n\n").unwrap();
    let with_q = format!(
        "{}\n[damping]\nq = 15.0{}",
        &shaker.text[..damping],
        &shaker.text[damping_end..]
    );
    // Clamped base: the fixture's 1e12 seat ties would let the summation order of the two
    // assemblies, not the files, set the difference.
    let start = with_q.find("\n[stack.fixture]\n").unwrap();
    let end = start + with_q[start..].find("\n[modal]").unwrap();
    let with_q = format!("{}{}", &with_q[..start], &with_q[end..]);
    let scene_file = dir.join("shaker-q15.toml");
    std::fs::write(&scene_file, with_q).unwrap();
    let scene_path = scene_file.to_str().unwrap();
    let out = satqual(&[
        "modal",
        scene_path,
        "--export-matrices",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let k = read_mtx(&dir.join("KKG.mtx"));
    let m = read_mtx(&dir.join("M.mtx"));
    let n = k.nrows();
    let csv = std::fs::read_to_string(dir.join("influence.csv")).unwrap();
    let mut rows = csv.lines();
    assert_eq!(rows.next(), Some("index,p_x,p_y,p_z,r_x,r_y,r_z"));
    let p_y: Vec<f64> = rows
        .map(|l| l.split(',').nth(2).unwrap().parse().unwrap())
        .collect();
    assert_eq!(p_y.len(), n);
    let (f_hz, zeta) = (50.0, 0.5 / 15.0);
    let (lambda, phi) = satqual::modal::dense::generalized_whole_spectrum(&k, &m).unwrap();
    let mphi = &m * &phi;
    let d = faer::Mat::<f64>::from_fn(n, n, |i, j| {
        if i == j {
            2.0 * zeta * lambda[i].max(0.0).sqrt()
        } else {
            0.0
        }
    });
    let c = &mphi * &d * mphi.transpose();
    let w = 2.0 * std::f64::consts::PI * f_hz;
    let a = faer::Mat::<faer::c64>::from_fn(n, n, |i, j| {
        faer::c64::new(k[(i, j)] - w * w * m[(i, j)], w * c[(i, j)])
    });
    let mut u = faer::Mat::<faer::c64>::from_fn(n, 1, |i, _| faer::c64::new(-p_y[i], 0.0));
    use faer::linalg::solvers::Solve;
    a.partial_piv_lu().solve_in_place(u.as_mut());
    // The library's own direct response on the scene.
    let scene = crate::common::load(scene_path);
    let (model, sys) = satqual::pipeline::modal(&scene, None, None).unwrap();
    let prep = satqual::response::Prepared::new(&scene, &model, &sys).unwrap();
    let reference = prep.direct_frf(1).unwrap().solve(f_hz);
    let norm = reference.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
    let diff = (0..n)
        .map(|i| (u[(i, 0)] - reference[i]).norm_sqr())
        .sum::<f64>()
        .sqrt();
    assert!(
        norm > 0.0 && diff <= 1e-9 * norm,
        "difference {diff:e} of {norm:e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
