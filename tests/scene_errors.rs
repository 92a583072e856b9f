//! Bad scene input: every case gives one clear error that names the file, the line and column,
//! and the key, so that a user can fix the scene without reading the source.

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
    scene_error(BASE, from, to)
}

use crate::common::{line_of, scene_error};

#[test]
fn base_scene_is_valid() {
    Scene::parse(Path::new("ok.toml"), BASE).unwrap();
}

refused_input_cases! {
    error: err_with;
    missing_node_reference: "nodes = [1, 2]" => "nodes = [1, 7]",
        contains ["beam[0].nodes", "node 7 is not defined"], at line_of(BASE, "nodes = [1, 2]");
    missing_section: "section = \"bar\"" => "section = \"nope\"",
        contains ["beam[0].section", "`nope` is not defined"];
    missing_material: "material = \"steel\"" => "material = \"unobtainium\"",
        contains ["beam[0].material", "`unobtainium`"];
    duplicate_node_id: "id = 2" => "id = 1",
        contains ["node[1].id", "duplicate node id 1"], at line_of(BASE, "id = 2");
    non_positive_modulus: "youngs_modulus_pa = 210e9" => "youngs_modulus_pa = 0.0",
        contains ["material[0].youngs_modulus_pa", "must be positive"];
    ultimate_below_yield: "density_kg_m3 = 7850" => "density_kg_m3 = 7850\nyield_strength_pa = 835e6\nultimate_strength_pa = 100e6",
        contains ["material[0].ultimate_strength_pa", "is below the yield strength"];
    negative_density: "density_kg_m3 = 7850" => "density_kg_m3 = -1.0",
        contains ["material[0].density_kg_m3"];
    negative_dimension: "width_m = 0.02" => "width_m = -0.02",
        contains ["section[0].width_m"];
    inner_diameter_not_below_outer: "inner_diameter_m = 0.04" => "inner_diameter_m = 0.05",
        contains ["section[1].inner_diameter_m", "smaller than the outer"],
        at line_of(BASE, "inner_diameter_m");
    coincident_beam_nodes: "position_m = [1.0, 0.0, 0.0]" => "position_m = [0.0, 0.0, 0.0]",
        contains ["beam[0].nodes", "coincide"];
    orientation_parallel_to_axis: "orientation = [0.0, 0.0, 1.0]" => "orientation = [2.0, 0.0, 0.0]",
        contains ["beam[0].orientation", "parallel"], at line_of(BASE, "orientation");
    nan_dimension: "height_m = 0.02" => "height_m = nan",
        contains ["section[0].height_m", "not a finite number"];
    inf_coordinate: "position_m = [1.0, 0.0, 0.0]" => "position_m = [1.0, inf, 0.0]",
        contains ["node[1].position_m[1]", "not a finite"], at line_of(BASE, "position_m = [1.0");
    // The misspelt key is on the line after the one it follows.
    unknown_key_is_rejected_with_its_location: "elements = 4" => "elements = 4\nelemnets = 5",
        contains ["elemnets"], at line_of(BASE, "elements = 4") + 1;
    wrong_type_names_the_key: "elements = 4" => "elements = \"four\"",
        contains ["elements"], at line_of(BASE, "elements = 4");
    malformed_toml_reports_line: "dofs = \"123456\"" => "dofs = \"123456",
        contains ["bad.toml:", "invalid TOML"];
    // serde fills a fixed-length array from its first entries: a fourth coordinate or a third
    // beam node would be dropped without a word.
    extra_coordinate_is_refused: "position_m = [1.0, 0.0, 0.0]" => "position_m = [1.0, 0.0, 0.0, 5.0]",
        contains ["node[1].position_m", "has 4 entries, but takes 3"],
        at line_of(BASE, "position_m = [1.0");
    // A 20 × 20 mm bar as a general section (A = 4e-4 m², I = 1.333e-8 m⁴, J = 2.25e-8 m⁴)
    // with its second moments a million times too small: below A²/(2π) = 2.5465e-8 m⁴.
    general_section_below_the_least_polar_moment: "shape = \"rectangle\"\nwidth_m = 0.02\nheight_m = 0.02" =>
        "shape = \"general\"\narea_m2 = 4e-4\niy_m4 = 1.33e-14\niz_m4 = 1.33e-14\nj_m4 = 2.25e-14",
        contains ["section[0].iy_m4", "below A²/(2π) = 2.5465e-8 m⁴"];
    // The same bar with its second moments in mm⁴ (1.3333e4) beside an area in m²: Ip/A² =
    // 1.67e11, a tube of radius 1e12 walls, far past the 1e4 of any structure.
    general_section_moments_in_mm4: "shape = \"rectangle\"\nwidth_m = 0.02\nheight_m = 0.02" =>
        "shape = \"general\"\narea_m2 = 4e-4\niy_m4 = 1.3333e4\niz_m4 = 1.3333e4\nj_m4 = 2.25e4",
        contains ["section[0].iy_m4", "1.667e11 times A²", "mm⁴ as m⁴"];
    // The same bar with J a hundred times too large: above Iy + Iz, which bounds it.
    general_section_torsion_above_polar: "shape = \"rectangle\"\nwidth_m = 0.02\nheight_m = 0.02" =>
        "shape = \"general\"\narea_m2 = 4e-4\niy_m4 = 1.3333e-8\niz_m4 = 1.3333e-8\nj_m4 = 2.25e-6",
        contains ["section[0].j_m4", "exceeds the polar moment"];
    third_beam_node_is_refused: "nodes = [1, 2]" => "nodes = [1, 2, 99]",
        contains ["beam[0].nodes", "has 3 entries, but takes 2"], at line_of(BASE, "nodes = [1, 2]");
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
    // An inertia given, but in g·mm² (1e-9 of kg·m²): 1e-15 against the 10 kg of the
    // translations is below the 1e-14 the mass check resolves; the message says so.
    let tiny = text.replace(
        "mass_kg = 10.0",
        "mass_kg = 10.0\ninertia_kg_m2 = [1e-15, 1e-15, 1e-15]",
    );
    let scene = Scene::parse(Path::new("sdof.toml"), &tiny).unwrap();
    let e = satqual::pipeline::modal(&scene, None, None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("node 2 DOF 4 (rx): its mass term 1.000e-15 is below 1e-14 of the model's largest (1.000e1)")
            && e.contains("g·mm²"),
        "{e}"
    );
    // Supporting the rotations makes it a valid 3-DOF model: f = √(k/m)/2π = 50.33 Hz.
    let fixed = text.to_string() + "[[support]]\nnode = 2\ndofs = \"456\"\n";
    let scene = Scene::parse(Path::new("sdof.toml"), &fixed).unwrap();
    let (_, sys) = satqual::pipeline::modal(&scene, None, None).unwrap();
    let f = (1e6f64 / 10.0).sqrt() / (2.0 * std::f64::consts::PI);
    for m in &sys.result.modes {
        assert!((m.frequency_hz - f).abs() < 1e-9 * f);
    }
}

/// Supports that leave nothing free, and a support on a rigid-link slave (its motion is its
/// master's), are located at the support that causes them.
#[test]
fn supports_that_hold_everything_or_a_slave_are_located() {
    let modal_error = |text: &str| {
        let scene = Scene::parse(Path::new("bad.toml"), text).unwrap();
        satqual::pipeline::modal(&scene, None, None)
            .unwrap_err()
            .to_string()
    };
    // One element between two clamped nodes: no interior node is left free.
    let held = BASE.replace("elements = 4", "elements = 1")
        + "\n[[support]]\nnode = 2\ndofs = \"123456\"\n";
    let e = modal_error(&held);
    let at = format!("bad.toml:{}:", line_of(BASE, "[[support]]") + 1);
    assert!(
        e.starts_with(&at) && e.contains("support[0].node") && e.contains("no free degree"),
        "{e}"
    );
    let slave = BASE.to_string()
        + "\n[[node]]\nid = 3\nposition_m = [1.0, 0.1, 0.0]\n\n[[rigid]]\nmaster = 2\nslaves = [3]\n\n[[support]]\nnode = 3\ndofs = \"123\"\n";
    let e = modal_error(&slave);
    let at = format!("bad.toml:{}:", line_of(&slave, "node = 3"));
    assert!(
        e.starts_with(&at)
            && e.contains("support[1].node")
            && e.contains(
                "node 3 is a rigid-link slave and also supported: support its master, node 2"
            ),
        "{e}"
    );
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
