//! The generic model of the scene contract (`docs/scene-format.md`): materials, sections, nodes,
//! beams, masses, rigid links, springs, supports, static loads and the `[modal]` request, plus
//! the checks that make a model well-posed before the FE layer sees it.

use super::Locator;
use super::plausible;
use crate::error::SpecError;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::collections::{HashMap, HashSet};

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Material {
    pub name: String,
    pub youngs_modulus_pa: f64,
    pub poisson_ratio: f64,
    pub density_kg_m3: f64,
    /// Tensile yield strength, for strength gates.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yield_strength_pa: Option<f64>,
    /// Ultimate tensile strength, for strength gates.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ultimate_strength_pa: Option<f64>,
}

impl Material {
    pub fn shear_modulus_pa(&self) -> f64 {
        self.youngs_modulus_pa / (2.0 * (1.0 + self.poisson_ratio))
    }
}

/// A cross-section. `shape` selects which dimension keys apply; the others must be absent.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq, Default)]
#[serde(deny_unknown_fields)]
pub struct Section {
    pub name: String,
    /// rectangle | circle | tube | general
    pub shape: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width_m: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height_m: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub diameter_m: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outer_diameter_m: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inner_diameter_m: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub area_m2: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub iy_m4: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub iz_m4: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub j_m4: Option<f64>,
    /// Timoshenko shear factor of a `general` section (both planes). Absent: shear-rigid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_factor: Option<f64>,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Node {
    pub id: i64,
    pub position_m: [f64; 3],
}

#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Theory {
    #[default]
    Timoshenko,
    EulerBernoulli,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Beam {
    /// Optional member name, used for load recovery and reports.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    pub nodes: [i64; 2],
    pub section: String,
    pub material: String,
    /// Subdivisions between the two nodes.
    #[serde(default = "one")]
    pub elements: usize,
    /// Vector in the local x–z plane (OpenSees `vecxz`). Default: global z, or global y
    /// for a beam along z.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation: Option<[f64; 3]>,
    #[serde(default)]
    pub theory: Theory,
}

fn one() -> usize {
    1
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Mass {
    pub node: i64,
    pub mass_kg: f64,
    /// About the mass's own centre, principal axes along global x, y, z.
    #[serde(default)]
    pub inertia_kg_m2: [f64; 3],
    /// The mass sits rigidly at node position + offset.
    #[serde(default)]
    pub offset_m: [f64; 3],
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Rigid {
    pub master: i64,
    pub slaves: Vec<i64>,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Spring {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    pub nodes: [i64; 2],
    /// N/m and N·m/rad in global x, y, z, rx, ry, rz.
    pub stiffness: [f64; 6],
}

/// A preloaded joint between two nodes (a pretension section): in the prestress solve the
/// joint is cut along `axis` and the preload is applied across the cut, `force_n` pulling the
/// first node along +axis and pushing the second along −axis; afterwards (modes, responses)
/// the joint is locked with `stiffness`. The structure itself equilibrates the preload, so
/// the members in the loop carry exactly `force_n`, whatever their stiffness.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Preload {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    pub nodes: [i64; 2],
    pub force_n: f64,
    /// Global axis of the preload: "x", "y" or "z".
    pub axis: String,
    /// Locked joint stiffness, N/m and N·m/rad in global x, y, z, rx, ry, rz.
    pub stiffness: [f64; 6],
}

impl Preload {
    pub fn axis_index(&self) -> Option<usize> {
        match self.axis.as_str() {
            "x" => Some(0),
            "y" => Some(1),
            "z" => Some(2),
            _ => None,
        }
    }
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Support {
    pub node: i64,
    /// Fixed DOFs as digits: 1-3 translations, 4-6 rotations (global).
    pub dofs: String,
}

impl Support {
    /// The fixed DOF indices 0..6.
    pub fn dof_indices(&self) -> Vec<usize> {
        self.dofs
            .chars()
            .filter_map(|c| c.to_digit(10))
            .map(|d| d as usize - 1)
            .collect()
    }
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct StaticLoad {
    pub node: i64,
    #[serde(default)]
    pub force_n: [f64; 3],
    #[serde(default)]
    pub moment_n_m: [f64; 3],
}

#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum SolverChoice {
    /// Dense below a size threshold, sparse shift-invert Lanczos above it.
    #[default]
    Auto,
    Dense,
    Sparse,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq, Default)]
#[serde(deny_unknown_fields)]
pub struct ModalSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fmax_hz: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub modes: Option<usize>,
    #[serde(default)]
    pub solver: SolverChoice,
}

/// Checks the model's total element count against `[limits] model_elements`, naming the beam
/// whose count pushes the total over the limit.
fn check_model_size(f: &super::SceneFile, loc: &Locator) -> Result<(), SpecError> {
    let limit = f.limits().model_elements;
    let mut total: usize = 0;
    for (i, b) in f.beam.iter().enumerate() {
        total = total.saturating_add(b.elements);
        if total > limit {
            return Err(loc.err(
                &format!("beam[{i}].elements"),
                format!(
                    "the model would have at least {total} beam elements ({} on this beam), above the limit of {limit}; {}",
                    b.elements,
                    super::limits::raise_hint("model_elements")
                ),
            ));
        }
    }
    Ok(())
}

/// Checks references, uniqueness, positivity, plausibility and geometry of the generic model.
pub fn validate(f: &super::SceneFile, loc: &Locator) -> Result<(), SpecError> {
    check_model_size(f, loc)?;
    let mut materials = HashSet::new();
    for (i, m) in f.material.iter().enumerate() {
        let k = |s: &str| format!("material[{i}].{s}");
        if !materials.insert(m.name.as_str()) {
            return Err(loc.err(&k("name"), format!("duplicate material name `{}`", m.name)));
        }
        positive(loc, &k("youngs_modulus_pa"), m.youngs_modulus_pa)?;
        positive(loc, &k("density_kg_m3"), m.density_kg_m3)?;
        plausible::check(
            loc,
            &k("youngs_modulus_pa"),
            m.youngs_modulus_pa,
            plausible::YOUNGS_MODULUS_PA,
        )?;
        plausible::check(
            loc,
            &k("density_kg_m3"),
            m.density_kg_m3,
            plausible::DENSITY_KG_M3,
        )?;
        if !(m.poisson_ratio > -1.0 && m.poisson_ratio < 0.5) {
            return Err(loc.err(
                &k("poisson_ratio"),
                format!("must lie in (-1, 0.5), got {}", m.poisson_ratio),
            ));
        }
        if let Some(v) = m.yield_strength_pa {
            plausible::check(loc, &k("yield_strength_pa"), v, plausible::STRENGTH_PA)?;
        }
        if let Some(v) = m.ultimate_strength_pa {
            plausible::check(loc, &k("ultimate_strength_pa"), v, plausible::STRENGTH_PA)?;
        }
        if let (Some(fy), Some(fu)) = (m.yield_strength_pa, m.ultimate_strength_pa)
            && fu < fy
        {
            return Err(loc.err(
                &k("ultimate_strength_pa"),
                format!("{fu} Pa is below the yield strength {fy} Pa: the two are swapped or one is mistyped"),
            ));
        }
    }
    let mut sections = HashSet::new();
    for (i, s) in f.section.iter().enumerate() {
        if !sections.insert(s.name.as_str()) {
            return Err(loc.err(
                &format!("section[{i}].name"),
                format!("duplicate section name `{}`", s.name),
            ));
        }
        validate_section(s, i, loc)?;
    }
    let mut nodes: HashMap<i64, [f64; 3]> = HashMap::new();
    for (i, n) in f.node.iter().enumerate() {
        for (j, x) in n.position_m.iter().enumerate() {
            let key = format!("node[{i}].position_m[{j}]");
            plausible::check(loc, &key, x.abs(), plausible::COORDINATE_M)?;
        }
        if nodes.insert(n.id, n.position_m).is_some() {
            return Err(loc.err(
                &format!("node[{i}].id"),
                format!("duplicate node id {}", n.id),
            ));
        }
    }
    let node_ref = |key: String, id: i64| -> Result<[f64; 3], SpecError> {
        nodes
            .get(&id)
            .copied()
            .ok_or_else(|| loc.err(&key, format!("node {id} is not defined")))
    };
    for (i, b) in f.beam.iter().enumerate() {
        let k = |s: &str| format!("beam[{i}].{s}");
        let a = node_ref(k("nodes"), b.nodes[0])?;
        let c = node_ref(k("nodes"), b.nodes[1])?;
        if !sections.contains(b.section.as_str()) {
            return Err(loc.err(
                &k("section"),
                format!("section `{}` is not defined", b.section),
            ));
        }
        if !materials.contains(b.material.as_str()) {
            return Err(loc.err(
                &k("material"),
                format!("material `{}` is not defined", b.material),
            ));
        }
        if b.elements == 0 {
            return Err(loc.err(&k("elements"), "must be at least 1"));
        }
        let (a, c) = (Vector3::from(a), Vector3::from(c));
        let axis = c - a;
        let len = axis.norm();
        let scale = a.norm().max(c.norm()).max(1.0);
        if len <= 1e-12 * scale {
            return Err(loc.err(
                &k("nodes"),
                format!(
                    "the beam's nodes {} and {} coincide: a beam needs a length",
                    b.nodes[0], b.nodes[1]
                ),
            ));
        }
        if let Some(o) = b.orientation {
            let o = Vector3::from(o);
            let on = o.norm();
            if on == 0.0 {
                return Err(loc.err(&k("orientation"), "the orientation vector is zero"));
            }
            if axis.cross(&o).norm() <= 1e-6 * len * on {
                return Err(loc.err(
                    &k("orientation"),
                    "the orientation vector is parallel to the beam axis: it must define the local x-z plane",
                ));
            }
        }
    }
    for (i, m) in f.mass.iter().enumerate() {
        node_ref(format!("mass[{i}].node"), m.node)?;
        nonneg(loc, &format!("mass[{i}].mass_kg"), m.mass_kg)?;
        plausible::check(
            loc,
            &format!("mass[{i}].mass_kg"),
            m.mass_kg,
            plausible::MASS_KG,
        )?;
        for (j, v) in m.inertia_kg_m2.iter().enumerate() {
            nonneg(loc, &format!("mass[{i}].inertia_kg_m2[{j}]"), *v)?;
            let key = format!("mass[{i}].inertia_kg_m2[{j}]");
            plausible::check(loc, &key, *v, plausible::INERTIA_KG_M2)?;
        }
    }
    let mut slaves_seen = HashSet::new();
    for (i, r) in f.rigid.iter().enumerate() {
        node_ref(format!("rigid[{i}].master"), r.master)?;
        for (j, s) in r.slaves.iter().enumerate() {
            node_ref(format!("rigid[{i}].slaves[{j}]"), *s)?;
            if *s == r.master {
                return Err(loc.err(
                    &format!("rigid[{i}].slaves[{j}]"),
                    "a node cannot be its own slave",
                ));
            }
            if !slaves_seen.insert(*s) {
                return Err(loc.err(
                    &format!("rigid[{i}].slaves[{j}]"),
                    format!("node {s} is already a slave of another rigid link"),
                ));
            }
        }
    }
    for (i, r) in f.rigid.iter().enumerate() {
        if slaves_seen.contains(&r.master) {
            return Err(loc.err(
                &format!("rigid[{i}].master"),
                format!("master node {} is a slave of another rigid link; chain links through one master", r.master),
            ));
        }
    }
    for (i, s) in f.spring.iter().enumerate() {
        node_ref(format!("spring[{i}].nodes"), s.nodes[0])?;
        node_ref(format!("spring[{i}].nodes"), s.nodes[1])?;
        if s.nodes[0] == s.nodes[1] {
            return Err(loc.err(
                &format!("spring[{i}].nodes"),
                "a spring needs two different nodes",
            ));
        }
        for (j, v) in s.stiffness.iter().enumerate() {
            nonneg(loc, &format!("spring[{i}].stiffness[{j}]"), *v)?;
            let key = format!("spring[{i}].stiffness[{j}]");
            plausible::check(loc, &key, *v, plausible::STIFFNESS)?;
        }
    }
    for (i, p) in f.preload.iter().enumerate() {
        node_ref(format!("preload[{i}].nodes"), p.nodes[0])?;
        node_ref(format!("preload[{i}].nodes"), p.nodes[1])?;
        if p.nodes[0] == p.nodes[1] {
            return Err(loc.err(
                &format!("preload[{i}].nodes"),
                "a preloaded joint needs two different nodes",
            ));
        }
        positive(loc, &format!("preload[{i}].force_n"), p.force_n)?;
        let key = format!("preload[{i}].force_n");
        plausible::check(loc, &key, p.force_n, plausible::FORCE_N)?;
        if p.axis_index().is_none() {
            return Err(loc.err(
                &format!("preload[{i}].axis"),
                format!("`{}` is not an axis: use x, y or z", p.axis),
            ));
        }
        for (j, v) in p.stiffness.iter().enumerate() {
            nonneg(loc, &format!("preload[{i}].stiffness[{j}]"), *v)?;
            let key = format!("preload[{i}].stiffness[{j}]");
            plausible::check(loc, &key, *v, plausible::STIFFNESS)?;
        }
    }
    for (i, s) in f.support.iter().enumerate() {
        node_ref(format!("support[{i}].node"), s.node)?;
        if s.dofs.is_empty() || !s.dofs.chars().all(|c| ('1'..='6').contains(&c)) {
            return Err(loc.err(
                &format!("support[{i}].dofs"),
                format!(
                    "`{}` is not a DOF list: use digits 1-6 (1-3 translations, 4-6 rotations)",
                    s.dofs
                ),
            ));
        }
    }
    for (i, l) in f.static_load.iter().enumerate() {
        node_ref(format!("static_load[{i}].node"), l.node)?;
    }
    if let Some(m) = &f.modal {
        match (m.fmax_hz, m.modes) {
            (Some(_), Some(_)) => {
                return Err(loc.err("modal", "give either `fmax_hz` or `modes`, not both"));
            }
            (Some(fm), None) => positive(loc, "modal.fmax_hz", fm)?,
            (None, Some(0)) => return Err(loc.err("modal.modes", "must be at least 1")),
            _ => {}
        }
    }
    Ok(())
}

fn validate_section(s: &Section, i: usize, loc: &Locator) -> Result<(), SpecError> {
    let k = |n: &str| format!("section[{i}].{n}");
    let all: [(&str, Option<f64>); 10] = [
        ("width_m", s.width_m),
        ("height_m", s.height_m),
        ("diameter_m", s.diameter_m),
        ("outer_diameter_m", s.outer_diameter_m),
        ("inner_diameter_m", s.inner_diameter_m),
        ("area_m2", s.area_m2),
        ("iy_m4", s.iy_m4),
        ("iz_m4", s.iz_m4),
        ("j_m4", s.j_m4),
        ("shear_factor", s.shear_factor),
    ];
    let (required, optional): (&[&str], &[&str]) = match s.shape.as_str() {
        "rectangle" => (&["width_m", "height_m"], &[]),
        "circle" => (&["diameter_m"], &[]),
        "tube" => (&["outer_diameter_m", "inner_diameter_m"], &[]),
        "general" => (&["area_m2", "iy_m4", "iz_m4", "j_m4"], &["shear_factor"]),
        other => {
            return Err(loc.err(
                &k("shape"),
                format!("unknown shape `{other}`: use rectangle, circle, tube or general"),
            ));
        }
    };
    for (name, v) in all {
        match v {
            Some(x) => {
                if !required.contains(&name) && !optional.contains(&name) {
                    return Err(
                        loc.err(&k(name), format!("does not apply to a {} section", s.shape))
                    );
                }
                positive(loc, &k(name), x)?;
            }
            None if required.contains(&name) => {
                return Err(loc.err(&k("shape"), format!("a {} section needs `{name}`", s.shape)));
            }
            None => {}
        }
    }
    if let (Some(o), Some(inner)) = (s.outer_diameter_m, s.inner_diameter_m)
        && inner >= o
    {
        return Err(loc.err(
            &k("inner_diameter_m"),
            format!("the inner diameter {inner} m must be smaller than the outer diameter {o} m"),
        ));
    }
    if let (Some(a), Some(iy), Some(iz), Some(j)) = (s.area_m2, s.iy_m4, s.iz_m4, s.j_m4) {
        check_general_section(a, iy + iz, j, &k, loc)?;
    }
    Ok(())
}

/// What no cross-section can have, whatever its shape: a polar moment Iy + Iz below the
/// solid disc's A²/(2π), the least any area A can have about its centroid; a torsion
/// constant J above the polar moment (Saint-Venant: J = Ip − ∫|∇ψ|² dA for the warping ψ,
/// equal for circles and tubes only). Either is a unit slip (mm⁴ or cm⁴ as m⁴, mm² as m²).
/// The other way, a polar moment above [`MOST_POLAR_PER_AREA_SQUARED`]·A² would take a tube
/// whose radius is 63 000 times its wall (Ip/A² = R/(2πt)): no structure, but mm⁴ typed as m⁴
/// beside an area in m² (1e12 times too large).
fn check_general_section(
    a: f64,
    polar: f64,
    j: f64,
    k: &dyn Fn(&str) -> String,
    loc: &Locator,
) -> Result<(), SpecError> {
    let least = a * a / (2.0 * std::f64::consts::PI);
    if polar < least * (1.0 - 1e-9) {
        return Err(loc.err(
            &k("iy_m4"),
            format!(
                "iy_m4 + iz_m4 = {polar:.4e} m⁴ is below A²/(2π) = {least:.4e} m⁴, the least polar moment any section of area {a:e} m² has (a solid circle): check the units of area_m2, iy_m4 and iz_m4"
            ),
        ));
    }
    if polar > MOST_POLAR_PER_AREA_SQUARED * a * a {
        return Err(loc.err(
            &k("iy_m4"),
            format!(
                "iy_m4 + iz_m4 = {polar:.4e} m⁴ is {:.3e} times A² for area {a:e} m²: a thin tube would need a radius {:.1e} times its wall thickness (Ip/A² = R/(2πt)), beyond any structure's {MOST_POLAR_PER_AREA_SQUARED:e}: check the units of area_m2, iy_m4 and iz_m4 (mm⁴ as m⁴?)",
                polar / (a * a),
                2.0 * std::f64::consts::PI * polar / (a * a)
            ),
        ));
    }
    if j > polar * (1.0 + 1e-9) {
        return Err(loc.err(
            &k("j_m4"),
            format!(
                "the torsion constant {j:.4e} m⁴ exceeds the polar moment iy_m4 + iz_m4 = {polar:.4e} m⁴, which bounds it for every section (equal for circles and tubes): check its units"
            ),
        ));
    }
    Ok(())
}

/// Largest Iy + Iz over A² of a general section: a tube of radius 63 000 times its wall
/// (R/(2πt)); thin-walled launcher structures stay below 200 (R/t ≈ 1000), rolled and built-up
/// sections below 10.
const MOST_POLAR_PER_AREA_SQUARED: f64 = 1e4;

/// Beyond every plausible range of a model quantity; above it a product of two overflows.
const HUGE: f64 = 1e30;

/// Positive, finite, not subnormal and at most [`HUGE`]: a NaN fails every comparison, so the
/// test is written to accept, not to refuse.
pub(super) fn positive(loc: &Locator, key: &str, v: f64) -> Result<(), SpecError> {
    if v.is_normal() && v > 0.0 && v <= HUGE {
        Ok(())
    } else {
        Err(loc.err(
            key,
            format!("must be positive, finite, not subnormal and at most {HUGE:e}, got {v}"),
        ))
    }
}

/// Zero, or positive as [`positive`].
pub(super) fn nonneg(loc: &Locator, key: &str, v: f64) -> Result<(), SpecError> {
    if v == 0.0 || (v.is_normal() && v > 0.0 && v <= HUGE) {
        Ok(())
    } else {
        Err(loc.err(
            key,
            format!(
                "must not be negative, and finite, not subnormal and at most {HUGE:e}, got {v}"
            ),
        ))
    }
}
