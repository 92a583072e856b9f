//! Bad scene input: every case gives one clear error that names the file, the line and column,
//! and the key (issue 2, "Bad input").

use satqual::spec::Scene;
use std::path::Path;

const BASE: &str = r#"title = "base"

[[material]]
name = "steel"
youngs_modulus_pa = 210e9
poisson_ratio = 0.3
density_kg_m3 = 7850

[[section]]
name = "bar"
shape = "rectangle"
width_m = 0.02
height_m = 0.02

[[section]]
name = "pipe"
shape = "tube"
outer_diameter_m = 0.05
inner_diameter_m = 0.04

[[node]]
id = 1
position_m = [0.0, 0.0, 0.0]

[[node]]
id = 2
position_m = [1.0, 0.0, 0.0]

[[beam]]
nodes = [1, 2]
section = "bar"
material = "steel"
elements = 4
orientation = [0.0, 0.0, 1.0]

[[support]]
node = 1
dofs = "123456"
"#;

/// Parses `BASE` with one substitution and returns the error text.
fn err_with(from: &str, to: &str) -> String {
    assert!(BASE.contains(from), "fixture does not contain {from:?}");
    let text = BASE.replacen(from, to, 1);
    match Scene::parse(Path::new("bad.toml"), &text) {
        Ok(_) => panic!("scene with {to:?} was accepted"),
        Err(e) => e.to_string(),
    }
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .expect("needle")
        + 1
}

#[test]
fn base_scene_is_valid() {
    Scene::parse(Path::new("ok.toml"), BASE).unwrap();
}

#[test]
fn missing_node_reference() {
    let e = err_with("nodes = [1, 2]", "nodes = [1, 7]");
    assert!(
        e.starts_with(&format!("bad.toml:{}:", line_of(BASE, "nodes = [1, 2]"))),
        "{e}"
    );
    assert!(
        e.contains("beam[0].nodes") && e.contains("node 7 is not defined"),
        "{e}"
    );
}

#[test]
fn missing_section_and_material() {
    let e = err_with("section = \"bar\"", "section = \"nope\"");
    assert!(
        e.contains("beam[0].section") && e.contains("`nope` is not defined"),
        "{e}"
    );
    let e = err_with("material = \"steel\"", "material = \"unobtainium\"");
    assert!(
        e.contains("beam[0].material") && e.contains("`unobtainium`"),
        "{e}"
    );
}

#[test]
fn duplicate_node_id() {
    let e = err_with("id = 2", "id = 1");
    assert!(
        e.contains("node[1].id") && e.contains("duplicate node id 1"),
        "{e}"
    );
    assert!(
        e.starts_with(&format!("bad.toml:{}:", line_of(BASE, "id = 2"))),
        "{e}"
    );
}

#[test]
fn non_positive_modulus_density_dimension() {
    let e = err_with("youngs_modulus_pa = 210e9", "youngs_modulus_pa = 0.0");
    assert!(
        e.contains("material[0].youngs_modulus_pa") && e.contains("must be positive"),
        "{e}"
    );
    let e = err_with("density_kg_m3 = 7850", "density_kg_m3 = -1.0");
    assert!(e.contains("material[0].density_kg_m3"), "{e}");
    let e = err_with("width_m = 0.02", "width_m = -0.02");
    assert!(e.contains("section[0].width_m"), "{e}");
}

#[test]
fn inner_diameter_not_below_outer() {
    let e = err_with("inner_diameter_m = 0.04", "inner_diameter_m = 0.05");
    assert!(
        e.contains("section[1].inner_diameter_m") && e.contains("smaller than the outer"),
        "{e}"
    );
    assert!(
        e.starts_with(&format!("bad.toml:{}:", line_of(BASE, "inner_diameter_m"))),
        "{e}"
    );
}

#[test]
fn coincident_beam_nodes() {
    let e = err_with(
        "position_m = [1.0, 0.0, 0.0]",
        "position_m = [0.0, 0.0, 0.0]",
    );
    assert!(e.contains("beam[0].nodes") && e.contains("coincide"), "{e}");
}

#[test]
fn orientation_parallel_to_axis() {
    let e = err_with(
        "orientation = [0.0, 0.0, 1.0]",
        "orientation = [2.0, 0.0, 0.0]",
    );
    assert!(
        e.contains("beam[0].orientation") && e.contains("parallel"),
        "{e}"
    );
    assert!(
        e.starts_with(&format!("bad.toml:{}:", line_of(BASE, "orientation"))),
        "{e}"
    );
}

#[test]
fn nan_and_inf_anywhere() {
    let e = err_with("height_m = 0.02", "height_m = nan");
    assert!(
        e.contains("section[0].height_m") && e.contains("not a finite number"),
        "{e}"
    );
    let e = err_with(
        "position_m = [1.0, 0.0, 0.0]",
        "position_m = [1.0, inf, 0.0]",
    );
    assert!(
        e.contains("node[1].position_m[1]") && e.contains("not a finite"),
        "{e}"
    );
    assert!(
        e.starts_with(&format!("bad.toml:{}:", line_of(BASE, "position_m = [1.0"))),
        "{e}"
    );
}

#[test]
fn unknown_key_is_rejected_with_its_location() {
    let e = err_with("elements = 4", "elements = 4\nelemnets = 5");
    assert!(e.contains("elemnets"), "{e}");
    assert!(
        e.starts_with(&format!("bad.toml:{}:", line_of(BASE, "elements = 4") + 1)),
        "{e}"
    );
}

#[test]
fn wrong_type_names_the_key() {
    let e = err_with("elements = 4", "elements = \"four\"");
    assert!(
        e.contains("beam[0].elements") || e.contains("elements"),
        "{e}"
    );
    assert!(
        e.starts_with(&format!("bad.toml:{}:", line_of(BASE, "elements = 4"))),
        "{e}"
    );
}

#[test]
fn massless_unsupported_dof_names_node_and_dof() {
    // A point mass on a spring: the mass node's rotations carry neither mass nor support.
    let text = r#"
[[node]]
id = 1
position_m = [0.0, 0.0, 0.0]
[[node]]
id = 2
position_m = [0.0, 0.0, 0.0]
[[mass]]
node = 2
mass_kg = 10.0
[[spring]]
nodes = [1, 2]
stiffness = [1e6, 1e6, 1e6, 0.0, 0.0, 0.0]
[[support]]
node = 1
dofs = "123456"
"#;
    let scene = Scene::parse(Path::new("sdof.toml"), text).unwrap();
    let e = satqual::pipeline::modal(&scene, None, None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("node 2") && e.contains("DOF 4") && e.contains("(rx)"),
        "{e}"
    );
    assert!(e.starts_with("sdof.toml:6:"), "{e}");
    // Supporting the rotations makes it a valid 3-DOF model: f = √(k/m)/2π = 50.33 Hz.
    let fixed = text.to_string() + "[[support]]\nnode = 2\ndofs = \"456\"\n";
    let scene = Scene::parse(Path::new("sdof.toml"), &fixed).unwrap();
    let (_, sys) = satqual::pipeline::modal(&scene, None, None).unwrap();
    let f = (1e6f64 / 10.0).sqrt() / (2.0 * std::f64::consts::PI);
    for m in &sys.result.modes {
        assert!((m.frequency_hz - f).abs() < 1e-9 * f);
    }
}

#[test]
fn unconstrained_static_solve_is_an_error() {
    // Static loads on a model without supports: the stiffness is singular.
    let text = BASE.replace("[[support]]\nnode = 1\ndofs = \"123456\"\n", "")
        + "[[static_load]]\nnode = 2\nforce_n = [100.0, 0.0, 0.0]\n";
    let scene = Scene::parse(Path::new("free.toml"), &text).unwrap();
    let e = satqual::pipeline::modal(&scene, None, None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("unconstrained"), "{e}");
}

#[test]
fn malformed_toml_reports_line() {
    let e = err_with("dofs = \"123456\"", "dofs = \"123456");
    assert!(e.contains("bad.toml:") && e.contains("invalid TOML"), "{e}");
}
