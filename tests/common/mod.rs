//! Scene fixtures shared by the separation tests: a small stack written out as TOML, so that
//! every test parses it through the same loader as a user's scene.

/// A small stack of `satellites` 150 kg satellites on steel bars of `bar_length_m`, with
/// rigid bars and 700 N/m springs of 0.08 m stroke. `separation_keys` go into the
/// `[separation]` table itself; `tables` (e.g. `[separation.contact]`) are appended at the end.
pub fn small_stack(
    satellites: usize,
    bar_length_m: f64,
    separation_keys: &str,
    tables: &str,
) -> String {
    format!(
        r#"
[[material]]
name = "steel"
youngs_modulus_pa = 210e9
poisson_ratio = 0.3
density_kg_m3 = 7850

[stack]
satellites = {satellites}
satellite_mass_kg = 150.0
satellite_inertia_kg_m2 = [16.0, 22.0, 30.0]
satellite_pitch_m = 0.5
base_height_m = 0.2
column_spacing_m = [1.0, 0.8]
column_outer_diameter_m = 0.04
column_inner_diameter_m = 0.021
column_material = "steel"
bar_diameter_m = 0.02
bar_length_m = {bar_length_m}
bar_material = "steel"
preload_total_n = 45000.0
[stack.interface]
axial_stiffness_n_m = 1e8
shear_stiffness_n_m = 1e8
rotational_stiffness_n_m_rad = 1e6
torsional_stiffness_n_m_rad = 1e6

[separation]
bar_modes = "rigid"
{separation_keys}[separation.spring]
stiffness_n_m = 700.0
stroke_m = 0.08
{tables}"#
    )
}
