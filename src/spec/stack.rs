//! The parametric `[stack]` section: N flat satellites stacked on a carrier platform, four
//! corner load-bearing columns per satellite, four guide bars through the columns, and the
//! compression device's preload. The FE expansion lives in `fem::stack`; the separation
//! simulation reads the same geometry, so both describe one piece of hardware.
//!
//! Axes: z is the stacking (axial) axis, pointing from the carrier platform towards the
//! compression device; x and y are the lateral axes of the satellite footprint.
//! Satellite 1 is the top one (next to the compression device, released first); satellite N
//! sits on the carrier platform and travels the whole bar length when released.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct StackSpec {
    /// Number of satellites.
    pub satellites: usize,
    /// Mass of one satellite without its four load-bearing columns (their mass comes from the
    /// column material and section), kg.
    pub satellite_mass_kg: f64,
    /// Principal moments of inertia about the satellite's CG, axes x, y, z, kg·m².
    pub satellite_inertia_kg_m2: [f64; 3],
    /// CG offset from the centre of the satellite's column segment (mid-height, footprint
    /// centre), m.
    #[serde(default)]
    pub satellite_cg_offset_m: [f64; 3],
    /// Axial pitch of the stack = height of one satellite's load-bearing columns, m.
    pub satellite_pitch_m: f64,
    /// Centre-to-centre distance of the corner columns along x and y, m.
    pub column_spacing_m: [f64; 2],
    pub column_outer_diameter_m: f64,
    pub column_inner_diameter_m: f64,
    /// Name of a `[[material]]`.
    pub column_material: String,
    /// Guide bar: solid circular section.
    pub bar_diameter_m: f64,
    /// From the fixed base on the carrier platform to the compression device, m.
    pub bar_length_m: f64,
    /// Name of a `[[material]]`.
    pub bar_material: String,
    /// Height of the lowest satellite's column bottom above the bar root (the carrier
    /// platform / adapter interface), m.
    #[serde(default)]
    pub base_height_m: f64,
    /// Total preload of the compression device, shared by the four bars, N.
    pub preload_total_n: f64,
    /// Stiffness of one preloaded column-to-column (or column-to-platform) joint.
    pub interface: InterfaceSpec,
    /// Compression device joint between each bar top and the top column, locked after the
    /// preload: axial stiffness, N/m. Assumption (the paper gives none): a threaded steel
    /// nut/flange assembly, far stiffer than the bar (EA/L ≈ 2e7 N/m) it closes.
    #[serde(default = "device_axial")]
    pub device_axial_stiffness_n_m: f64,
    /// Lateral stiffness of the same joint, N/m (same assumption). Its rotations are free: the
    /// preload nut seats on a flange, and the bar's lower end on a spherical washer (§2.2, Fig. 3).
    #[serde(default = "device_axial")]
    pub device_lateral_stiffness_n_m: f64,
    /// Beam elements per half column (the satellite attaches at mid-height).
    #[serde(default = "one")]
    pub column_elements: usize,
    /// Beam elements per half column of the model the buckling factor is taken on, when
    /// finer than `column_elements`: the columns between the satellites are what buckles,
    /// and their mesh sets the factor's error (+0.52 % at 1, +0.06 % at 2, +0.010 % at 4 on
    /// the paper stack, docs/fem.md), while the modes converge at 1 (1e-5).
    #[serde(default = "four")]
    pub buckling_column_elements: usize,
    /// Beam elements per satellite pitch along each guide bar.
    #[serde(default = "two")]
    pub bar_elements_per_satellite: usize,
    /// Lateral contact of each guide bar with the column bores at every interface level.
    /// `open` (default): the radial clearance stays open, and the bar is held laterally only
    /// at its root and by the compression device. `closed`: bar and bore touch (a bar bowed
    /// by lateral load, or a long stack, closes the fraction of a millimetre), modelled as
    /// lateral springs of `bar_bore_stiffness_n_m` between the bar and the column ends at each
    /// level. Closed bores brace the preloaded columns: the bar tension and the column
    /// compression then act on one laterally coupled section and do not buckle it globally.
    #[serde(default)]
    pub bar_bore: BarBore,
    /// Lateral contact stiffness of one closed bar–bore contact, N/m. ASSUMPTION: 1e8 N/m, a
    /// linearised steel-on-aluminium line contact a few centimetres long.
    #[serde(default = "bore_stiffness")]
    pub bar_bore_stiffness_n_m: f64,
    /// The shaker test's fixture under the stack (test scenes only); absent, the carrier
    /// platform and the bar roots are clamped to the ground.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fixture: Option<super::fixture::FixtureSpec>,
}

/// See [`StackSpec::bar_bore`].
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum BarBore {
    #[default]
    Open,
    Closed,
}

fn bore_stiffness() -> f64 {
    1e8
}

fn two() -> usize {
    2
}

fn four() -> usize {
    4
}

fn one() -> usize {
    1
}

fn device_axial() -> f64 {
    1e9
}

/// A preloaded joint as a spring: axial (z), shear (x, y) and rotational stiffness.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct InterfaceSpec {
    pub axial_stiffness_n_m: f64,
    pub shear_stiffness_n_m: f64,
    /// About the lateral axes (x, y), N·m/rad.
    pub rotational_stiffness_n_m_rad: f64,
    /// About the column axis (z), N·m/rad.
    pub torsional_stiffness_n_m_rad: f64,
    /// A connector that carries the joint's shear once friction is exceeded (the male and
    /// female connectors of the paper's Fig. 4). Absent: friction, then the guide bar bearing
    /// on the bore, carry the shear.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_key: Option<ShearKeySpec>,
}

/// `[stack.interface] shear_key`: a spigot, pin or cone across the joint plane. Its capacity
/// is min(τ_allow · shear area, σ_br,allow · bearing area).
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ShearKeySpec {
    /// Name of a `[[material]]`; its yield strength gives the default allowables.
    pub material: String,
    /// Section of the key sheared in the joint plane, m².
    pub shear_area_m2: f64,
    /// Projected bearing area of the key on its socket (diameter × engagement), m².
    pub bearing_area_m2: f64,
    /// Allowable shear stress, Pa. Default: yield/√3 of the material (distortion-energy
    /// criterion for a ductile metal in pure shear).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_strength_pa: Option<f64>,
    /// Allowable bearing stress, Pa. Default: the material's tensile yield (below the bearing
    /// yield MMPDS gives for an edge distance of 1.5 diameters or more, so conservative).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bearing_strength_pa: Option<f64>,
}

impl ShearKeySpec {
    /// (shear, bearing) allowable stresses, Pa, from the explicit keys or the material's yield.
    pub fn allowables(&self, materials: &[super::Material]) -> Option<(f64, f64)> {
        let fy = materials
            .iter()
            .find(|m| m.name == self.material)
            .and_then(|m| m.yield_strength_pa);
        let shear = self.shear_strength_pa.or(fy.map(|y| y / 3f64.sqrt()))?;
        let bearing = self.bearing_strength_pa.or(fy)?;
        Some((shear, bearing))
    }

    /// Capacity of the key in the joint plane, N.
    pub fn capacity_n(&self, materials: &[super::Material]) -> Option<f64> {
        let (tau, sigma) = self.allowables(materials)?;
        Some((tau * self.shear_area_m2).min(sigma * self.bearing_area_m2))
    }

    fn validate(&self, materials: &[super::Material], loc: &Locator) -> Result<(), SpecError> {
        let k = |s: &str| format!("stack.interface.shear_key.{s}");
        for (key, v) in [
            ("shear_area_m2", Some(self.shear_area_m2)),
            ("bearing_area_m2", Some(self.bearing_area_m2)),
            ("shear_strength_pa", self.shear_strength_pa),
            ("bearing_strength_pa", self.bearing_strength_pa),
        ] {
            if let Some(v) = v
                && !(v > 0.0 && v.is_finite())
            {
                return Err(loc.err(&k(key), format!("must be positive, got {v}")));
            }
        }
        if !materials.iter().any(|m| m.name == self.material) {
            return Err(loc.err(
                &k("material"),
                format!("material `{}` is not defined", self.material),
            ));
        }
        if self.allowables(materials).is_none() {
            return Err(loc.err(
                &k("material"),
                format!(
                    "material `{}` gives no yield_strength_pa: give it one, or give shear_strength_pa and bearing_strength_pa",
                    self.material
                ),
            ));
        }
        Ok(())
    }
}

impl StackSpec {
    /// Positions (x, y) of the four columns, ordered (+,+), (−,+), (−,−), (+,−).
    pub fn column_xy(&self) -> [[f64; 2]; 4] {
        let (hx, hy) = (
            0.5 * self.column_spacing_m[0],
            0.5 * self.column_spacing_m[1],
        );
        [[hx, hy], [-hx, hy], [-hx, -hy], [hx, -hy]]
    }

    /// z of the bottom of satellite `i` (1 = top, N = bottom), measured from the bar root.
    pub fn satellite_bottom_z(&self, i: usize) -> f64 {
        self.base_height_m + (self.satellites - i) as f64 * self.satellite_pitch_m
    }

    /// Radial clearance between a column bore and a centred guide bar, m.
    pub fn radial_clearance_m(&self) -> f64 {
        0.5 * (self.column_inner_diameter_m - self.bar_diameter_m)
    }
}

use super::Locator;
use super::model::{Beam, Mass, Node, Preload, Rigid, Section, Spring, Support, Theory};
use crate::error::SpecError;

/// Node-id scheme of the expansion (documented so that users can name response points):
/// satellite i's rigid body `1000·i`; its column c (1–4) bottom, mid-height and top
/// `1000·i + 10·c + 1/2/3`; the carrier-platform point under column c `10·c`; guide bar c at
/// level j (0 = bottom of the lowest satellite, N = top of the stack) `10000000·c + 10 + j`, its
/// root `10000000·c` and its free tip above the compression device `10000000·c + 9999` (ids far above any satellite's, so stacks of up to 9999 satellites never collide).
/// With a fixture: the shaker table `1`, the adapter plate `2`, the bar seats `10000000·c + 1`.
pub mod ids {
    pub fn satellite(i: usize) -> i64 {
        1000 * i as i64
    }
    pub fn column(i: usize, c: usize, k: usize) -> i64 {
        1000 * i as i64 + 10 * c as i64 + k as i64
    }
    pub fn platform(c: usize) -> i64 {
        10 * c as i64
    }
    pub fn bar(c: usize, level: usize) -> i64 {
        10_000_000 * c as i64 + 10 + level as i64
    }
    pub fn bar_root(c: usize) -> i64 {
        10_000_000 * c as i64
    }
    pub fn bar_tip(c: usize) -> i64 {
        10_000_000 * c as i64 + 9999
    }
    /// With a `[stack.fixture]`: the driven shaker table (ground) and the adapter plate on it.
    pub fn shaker_table() -> i64 {
        1
    }
    pub fn fixture_plate() -> i64 {
        2
    }
    /// With a `[stack.fixture]`: the plate's point under guide bar c, where the bar root's
    /// spherical washer seats.
    pub fn bar_seat(c: usize) -> i64 {
        10_000_000 * c as i64 + 1
    }
}

impl StackSpec {
    /// Height of the top of the stack above the bar root, m.
    pub fn stack_top_z(&self) -> f64 {
        self.base_height_m + self.satellites as f64 * self.satellite_pitch_m
    }

    /// Checks the stack's own consistency (the generic checks run on the expansion).
    pub fn validate(
        &self,
        materials: &[super::Material],
        limits: &super::limits::LimitsSpec,
        loc: &Locator,
    ) -> Result<(), SpecError> {
        let k = |s: &str| format!("stack.{s}");
        if self.satellites == 0 {
            return Err(loc.err(&k("satellites"), "a stack needs at least one satellite"));
        }
        if self.preload_total_n <= 0.0 {
            return Err(loc.err(
                &k("preload_total_n"),
                format!(
                    "the preload must be positive, got {} N",
                    self.preload_total_n
                ),
            ));
        }
        // Positive, then plausible: a 1e-300 m bar makes every stiffness matrix singular.
        use super::plausible::{
            MASS_KG, SATELLITE_SIZE_M, STACK_DIAMETER_M, STACK_LENGTH_M, STIFFNESS,
        };
        let i = &self.interface;
        for (key, v, range) in [
            ("satellite_mass_kg", self.satellite_mass_kg, MASS_KG),
            (
                "satellite_pitch_m",
                self.satellite_pitch_m,
                SATELLITE_SIZE_M,
            ),
            (
                "column_spacing_m",
                self.column_spacing_m[0],
                SATELLITE_SIZE_M,
            ),
            (
                "column_spacing_m",
                self.column_spacing_m[1],
                SATELLITE_SIZE_M,
            ),
            (
                "column_outer_diameter_m",
                self.column_outer_diameter_m,
                STACK_DIAMETER_M,
            ),
            (
                "column_inner_diameter_m",
                self.column_inner_diameter_m,
                STACK_DIAMETER_M,
            ),
            ("bar_diameter_m", self.bar_diameter_m, STACK_DIAMETER_M),
            ("bar_length_m", self.bar_length_m, STACK_LENGTH_M),
            (
                "interface.axial_stiffness_n_m",
                i.axial_stiffness_n_m,
                STIFFNESS,
            ),
            (
                "device_axial_stiffness_n_m",
                self.device_axial_stiffness_n_m,
                STIFFNESS,
            ),
        ] {
            if v.is_nan() || v <= 0.0 {
                return Err(loc.err(&k(key), format!("must be positive, got {v}")));
            }
            super::plausible::check(loc, &k(key), v, range)?;
        }
        for (key, v) in [
            (
                "interface.shear_stiffness_n_m",
                self.interface.shear_stiffness_n_m,
            ),
            (
                "interface.rotational_stiffness_n_m_rad",
                self.interface.rotational_stiffness_n_m_rad,
            ),
            (
                "interface.torsional_stiffness_n_m_rad",
                self.interface.torsional_stiffness_n_m_rad,
            ),
            (
                "device_lateral_stiffness_n_m",
                self.device_lateral_stiffness_n_m,
            ),
            ("base_height_m", self.base_height_m),
            ("bar_bore_stiffness_n_m", self.bar_bore_stiffness_n_m),
        ] {
            if v < 0.0 {
                return Err(loc.err(&k(key), format!("must not be negative, got {v}")));
            }
        }
        for (i, v) in self.satellite_inertia_kg_m2.iter().enumerate() {
            if *v < 0.0 {
                return Err(loc.err(
                    &format!("stack.satellite_inertia_kg_m2[{i}]"),
                    format!("must not be negative, got {v}"),
                ));
            }
        }
        if self.column_elements == 0 || self.bar_elements_per_satellite == 0 {
            return Err(loc.err(&k("column_elements"), "element counts must be at least 1"));
        }
        if self.buckling_column_elements == 0 {
            return Err(loc.err(
                &k("buckling_column_elements"),
                "element counts must be at least 1",
            ));
        }
        self.check_size(limits.model_elements, loc)?;
        if let Some(b) = self.buckling_stack() {
            b.check_size(limits.model_elements, loc).map_err(|e| {
                let msg = format!("the buckling model: {}", e.message);
                loc.err(&k("buckling_column_elements"), msg)
            })?;
        }
        if self.column_inner_diameter_m >= self.column_outer_diameter_m {
            return Err(loc.err(
                &k("column_inner_diameter_m"),
                format!(
                    "the column bore {} m must be smaller than its outer diameter {} m",
                    self.column_inner_diameter_m, self.column_outer_diameter_m
                ),
            ));
        }
        let spacing = self.column_spacing_m[0].min(self.column_spacing_m[1]);
        if self.column_outer_diameter_m >= spacing {
            return Err(loc.err(
                &k("column_outer_diameter_m"),
                format!(
                    "columns of {} m outer diameter overlap at a column spacing of {spacing} m (stack.column_spacing_m): diameters are in metres (50 mm = 0.05)",
                    self.column_outer_diameter_m
                ),
            ));
        }
        if self.bar_diameter_m >= self.column_inner_diameter_m {
            return Err(loc.err(
                &k("bar_diameter_m"),
                format!(
                    "the guide bar (diameter {} m) does not fit through the column bore (inner diameter {} m)",
                    self.bar_diameter_m, self.column_inner_diameter_m
                ),
            ));
        }
        let top = self.stack_top_z();
        if self.bar_length_m < top - 1e-9 {
            return Err(loc.err(
                &k("bar_length_m"),
                format!(
                    "the guide bars ({} m) are shorter than the stack they must clamp: base {} m + {} satellites × {} m = {} m",
                    self.bar_length_m, self.base_height_m, self.satellites, self.satellite_pitch_m, top
                ),
            ));
        }
        for (key, name) in [
            ("column_material", &self.column_material),
            ("bar_material", &self.bar_material),
        ] {
            if !materials.iter().any(|m| &m.name == name) {
                return Err(loc.err(&k(key), format!("material `{name}` is not defined")));
            }
        }
        if let Some(key) = &self.interface.shear_key {
            key.validate(materials, loc)?;
        }
        if let Some(fixture) = &self.fixture {
            fixture.validate(loc)?;
        }
        Ok(())
    }

    /// Expands the stack into generic-model parts appended to `f` (materials stay as given).
    /// The stack meshed for the buckling factor (`buckling_column_elements` per half
    /// column), when that is finer than the modes' mesh.
    pub fn buckling_stack(&self) -> Option<StackSpec> {
        (self.buckling_column_elements > self.column_elements).then(|| StackSpec {
            column_elements: self.buckling_column_elements,
            ..self.clone()
        })
    }

    /// The expanded model's element count, estimated before expansion: two column halves on
    /// each of four columns per satellite, and four bars of one segment per level.
    fn check_size(&self, limit: usize, loc: &Locator) -> Result<(), SpecError> {
        let columns = self
            .satellites
            .saturating_mul(8)
            .saturating_mul(self.column_elements);
        let bars = self
            .satellites
            .saturating_add(1)
            .saturating_mul(4)
            .saturating_mul(self.bar_elements_per_satellite);
        let total = columns.saturating_add(bars);
        if total <= limit {
            return Ok(());
        }
        let key = if columns >= bars {
            "stack.column_elements"
        } else {
            "stack.bar_elements_per_satellite"
        };
        Err(loc.err(
            key,
            format!(
                "the stack of {} satellites would expand to about {total} beam elements ({columns} in the columns, {bars} in the guide bars), above the limit of {limit}; {}",
                self.satellites,
                super::limits::raise_hint("model_elements")
            ),
        ))
    }

    pub fn expand_into(&self, f: &mut super::SceneFile) {
        let n = self.satellites;
        let xy = self.column_xy();
        let z = |level: usize| self.base_height_m + level as f64 * self.satellite_pitch_m;
        f.section.push(Section {
            name: "stack column".into(),
            shape: "tube".into(),
            outer_diameter_m: Some(self.column_outer_diameter_m),
            inner_diameter_m: Some(self.column_inner_diameter_m),
            ..Default::default()
        });
        f.section.push(Section {
            name: "stack guide bar".into(),
            shape: "circle".into(),
            diameter_m: Some(self.bar_diameter_m),
            ..Default::default()
        });
        let beam = |name: String, a: i64, b: i64, sec: &str, mat: &str, el: usize| Beam {
            name: Some(name),
            nodes: [a, b],
            section: sec.into(),
            material: mat.into(),
            elements: el,
            orientation: Some([1.0, 0.0, 0.0]),
            theory: Theory::Timoshenko,
        };
        let joint = |name: String, a: i64, b: i64| Spring {
            name: Some(name),
            nodes: [a, b],
            stiffness: [
                self.interface.shear_stiffness_n_m,
                self.interface.shear_stiffness_n_m,
                self.interface.axial_stiffness_n_m,
                self.interface.rotational_stiffness_n_m_rad,
                self.interface.rotational_stiffness_n_m_rad,
                self.interface.torsional_stiffness_n_m_rad,
            ],
        };
        for (c, p) in xy.iter().enumerate() {
            let c = c + 1;
            f.node.push(Node {
                id: ids::platform(c),
                position_m: [p[0], p[1], z(0)],
            });
            if self.fixture.is_none() {
                f.support.push(Support {
                    node: ids::platform(c),
                    dofs: "123456".into(),
                });
            }
        }
        for i in 1..=n {
            let bottom = z(n - i);
            let mid = bottom + 0.5 * self.satellite_pitch_m;
            let cg = self.satellite_cg_offset_m;
            f.node.push(Node {
                id: ids::satellite(i),
                position_m: [cg[0], cg[1], mid + cg[2]],
            });
            f.mass.push(Mass {
                node: ids::satellite(i),
                mass_kg: self.satellite_mass_kg,
                inertia_kg_m2: self.satellite_inertia_kg_m2,
                offset_m: [0.0; 3],
            });
            let mut slaves = Vec::new();
            for (c, p) in xy.iter().enumerate() {
                let c = c + 1;
                for (k, zz) in [(1, bottom), (2, mid), (3, bottom + self.satellite_pitch_m)] {
                    f.node.push(Node {
                        id: ids::column(i, c, k),
                        position_m: [p[0], p[1], zz],
                    });
                }
                slaves.push(ids::column(i, c, 2));
                let mat = &self.column_material;
                let el = self.column_elements;
                f.beam.push(beam(
                    format!("sat {i} column {c} lower"),
                    ids::column(i, c, 1),
                    ids::column(i, c, 2),
                    "stack column",
                    mat,
                    el,
                ));
                f.beam.push(beam(
                    format!("sat {i} column {c} upper"),
                    ids::column(i, c, 2),
                    ids::column(i, c, 3),
                    "stack column",
                    mat,
                    el,
                ));
                let below = if i == n {
                    ids::platform(c)
                } else {
                    ids::column(i + 1, c, 3)
                };
                let name = if i == n {
                    format!("interface platform/sat {i} column {c}")
                } else {
                    format!("interface sat {}/sat {i} column {c}", i + 1)
                };
                f.spring.push(joint(name, below, ids::column(i, c, 1)));
            }
            f.rigid.push(Rigid {
                master: ids::satellite(i),
                slaves,
            });
        }
        let top = self.stack_top_z();
        for (c, p) in xy.iter().enumerate() {
            let c = c + 1;
            let mat = &self.bar_material;
            let el = self.bar_elements_per_satellite;
            f.node.push(Node {
                id: ids::bar_root(c),
                position_m: [p[0], p[1], 0.0],
            });
            // The spherical washer at the bar's lower end (§2.2, Fig. 3 item 15) lets it rotate:
            // translations and torsion held, bending rotations free.
            if self.fixture.is_some() {
                seat_on_fixture(f, c, [p[0], p[1], 0.0]);
            } else {
                f.support.push(Support {
                    node: ids::bar_root(c),
                    dofs: "1236".into(),
                });
            }
            let mut prev = ids::bar_root(c);
            for level in 0..=n {
                if level == 0 && self.base_height_m <= 0.0 {
                    // The root is level 0; alias it by giving the level-0 id to the root node.
                    continue;
                }
                f.node.push(Node {
                    id: ids::bar(c, level),
                    position_m: [p[0], p[1], z(level)],
                });
                let elements = if level == 0 { el.max(1) } else { el };
                f.beam.push(beam(
                    format!("bar {c} segment {level}"),
                    prev,
                    ids::bar(c, level),
                    "stack guide bar",
                    mat,
                    elements,
                ));
                prev = ids::bar(c, level);
            }
            if self.bar_bore == BarBore::Closed {
                // Level j is the bottom of satellite n − j (the platform joint at j = 0); the
                // top level carries the compression device, laterally stiff already.
                for level in 0..n {
                    let bar_node = if level == 0 && self.base_height_m <= 0.0 {
                        ids::bar_root(c)
                    } else {
                        ids::bar(c, level)
                    };
                    let k = self.bar_bore_stiffness_n_m;
                    f.spring.push(Spring {
                        name: Some(format!("bar {c} bore contact sat {}", n - level)),
                        nodes: [bar_node, ids::column(n - level, c, 1)],
                        stiffness: [k, k, 0.0, 0.0, 0.0, 0.0],
                    });
                }
            }
            f.preload.push(Preload {
                name: Some(format!("compression device bar {c}")),
                nodes: [prev, ids::column(1, c, 3)],
                force_n: self.preload_total_n / 4.0,
                axis: "z".into(),
                stiffness: [
                    self.device_lateral_stiffness_n_m,
                    self.device_lateral_stiffness_n_m,
                    self.device_axial_stiffness_n_m,
                    0.0,
                    0.0,
                    0.0,
                ],
            });
            let stub = self.bar_length_m - top;
            if stub > 1e-6 {
                f.node.push(Node {
                    id: ids::bar_tip(c),
                    position_m: [p[0], p[1], self.bar_length_m],
                });
                f.beam.push(beam(
                    format!("bar {c} tip"),
                    prev,
                    ids::bar_tip(c),
                    "stack guide bar",
                    mat,
                    1,
                ));
            }
        }
        if let Some(fixture) = &self.fixture {
            expand_fixture(fixture, f);
        }
    }
}

/// Stiffness of the tie between a bar root and its seat on the fixture plate, N/m and N·m/rad:
/// a penalty for "held" (1000× a bar segment's EA/L of ~6e8 N/m), as the ground holds it
/// without a fixture.
const SEAT_TIE: f64 = 1e12;

/// The bar root's seat on the fixture plate: translations and torsion tied, bending free.
fn seat_on_fixture(f: &mut super::SceneFile, c: usize, position_m: [f64; 3]) {
    f.node.push(Node {
        id: ids::bar_seat(c),
        position_m,
    });
    f.spring.push(Spring {
        name: Some(format!("bar {c} seat on the fixture")),
        nodes: [ids::bar_seat(c), ids::bar_root(c)],
        stiffness: [SEAT_TIE, SEAT_TIE, SEAT_TIE, 0.0, 0.0, SEAT_TIE],
    });
}

/// The shaker table (driven, held) and the adapter plate on its six springs, carrying the
/// carrier-platform points and the bar seats.
fn expand_fixture(fixture: &super::fixture::FixtureSpec, f: &mut super::SceneFile) {
    for id in [ids::shaker_table(), ids::fixture_plate()] {
        f.node.push(Node {
            id,
            position_m: [0.0; 3],
        });
    }
    f.support.push(Support {
        node: ids::shaker_table(),
        dofs: "123456".into(),
    });
    f.mass.push(Mass {
        node: ids::fixture_plate(),
        mass_kg: fixture.mass_kg,
        inertia_kg_m2: fixture.inertia_kg_m2,
        offset_m: [0.0; 3],
    });
    f.spring.push(Spring {
        name: Some("fixture".into()),
        nodes: [ids::shaker_table(), ids::fixture_plate()],
        stiffness: fixture.stiffness(),
    });
    let slaves = (1..=4)
        .flat_map(|c| [ids::platform(c), ids::bar_seat(c)])
        .collect();
    f.rigid.push(Rigid {
        master: ids::fixture_plate(),
        slaves,
    });
}
