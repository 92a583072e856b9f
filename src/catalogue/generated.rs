//! Scenes generated from the catalogue's problems: the paper stack with N satellites, the same
//! with the bars bearing on their bores, frame towers of any size, and a small stack for the
//! separation model. They are scene text, so tests and benchmarks parse them through the same
//! loader as a user's scene.

use std::fmt::Write as _;

/// The first number on a `key = value  # comment` line.
fn value_of(line: &str) -> Option<f64> {
    line.split('=')
        .nth(1)?
        .split('#')
        .next()?
        .trim()
        .parse()
        .ok()
}

fn starts_with_key(line: &str, key: &str) -> bool {
    let t = line.trim_start();
    t.strip_prefix(key)
        .is_some_and(|rest| rest.trim_start().starts_with('='))
}

/// `base` (a `[stack]` scene such as the paper stack) with `satellites = n`, and the guide bars
/// one satellite pitch longer per added satellite, so that they still reach through the stack.
pub fn stack_with_satellites(base: &str, n: usize) -> String {
    let get = |key: &str| {
        base.lines()
            .find(|l| starts_with_key(l, key))
            .and_then(value_of)
    };
    let n0 = get("satellites").unwrap_or(6.0);
    let pitch = get("satellite_pitch_m").unwrap_or(0.6);
    let mut s = String::with_capacity(base.len());
    for line in base.lines() {
        if starts_with_key(line, "satellites") {
            let _ = writeln!(s, "satellites = {n}");
        } else if starts_with_key(line, "bar_length_m") {
            let length = value_of(line).unwrap_or(3.85) + (n as f64 - n0) * pitch;
            let _ = writeln!(s, "bar_length_m = {length}");
        } else {
            let _ = writeln!(s, "{line}");
        }
    }
    s
}

/// `base` (a `[stack]` scene) with its mesh set: `column_elements` beam elements per half
/// column and `bar_elements` per satellite pitch along each bar.
pub fn stack_with_mesh(base: &str, column_elements: usize, bar_elements: usize) -> String {
    let key = "bar_elements_per_satellite";
    let s = with_first_line(
        base,
        "column_elements",
        &format!("column_elements = {column_elements}"),
    );
    with_first_line(&s, key, &format!("{key} = {bar_elements}"))
}

/// `text` (a `[stack]` scene) with the guide bars bearing on their bores at every satellite
/// (`bar_bore = "closed"`), which braces a long stack laterally.
pub fn with_closed_bores(text: &str) -> String {
    let mut s = String::with_capacity(text.len() + 24);
    for line in text.lines() {
        let _ = writeln!(s, "{line}");
        if starts_with_key(line, "satellites") {
            let _ = writeln!(s, "bar_bore = \"closed\"");
        }
    }
    s
}

/// A frame tower: `levels` floors of an `nx` × `ny` grid of steel members, `elements` finite
/// elements each; tube columns and floor beams in x, rectangular floor beams in y; a point
/// mass with an offset and its own inertia on every top-floor node; diagonal springs between
/// neighbouring floors.
#[derive(Debug, Clone, Copy)]
pub struct FrameTower {
    pub nx: usize,
    pub ny: usize,
    pub levels: usize,
    pub elements: usize,
    /// Free-free (no supports, no springs) instead of clamped at the base.
    pub free: bool,
    /// A downward force on every top node, which puts the columns in compression (prestress
    /// and buckling); 0 for none.
    pub load_n: f64,
    /// Beams and plain point masses only (no springs, no mass offsets or inertias): the model
    /// a general FE code holds as it is (`bench modal` solves it with CalculiX too).
    pub beams_and_point_masses: bool,
}

/// One member of a [`FrameTower`]: its end nodes, section name and axis (0 = x, 1 = y, 2 = z).
pub struct TowerMember {
    pub nodes: [usize; 2],
    pub section: &'static str,
    pub axis: usize,
}

impl FrameTower {
    /// A clamped, unloaded tower with two elements per member.
    pub fn clamped(nx: usize, ny: usize, levels: usize) -> FrameTower {
        FrameTower {
            nx,
            ny,
            levels,
            elements: 2,
            free: false,
            load_n: 0.0,
            beams_and_point_masses: false,
        }
    }

    fn id(&self, i: usize, j: usize, k: usize) -> usize {
        1 + i + self.nx * (j + self.ny * k)
    }

    /// Every node as (id, position in m), by floor, then row, then column.
    pub fn nodes(&self) -> Vec<(usize, [f64; 3])> {
        let mut v = Vec::new();
        for k in 0..=self.levels {
            for j in 0..self.ny {
                for i in 0..self.nx {
                    let p = [1.1 * i as f64, 0.8 * j as f64, 0.7 * k as f64];
                    v.push((self.id(i, j, k), p));
                }
            }
        }
        v
    }

    /// The members at grid point (i, j, k): the x and y floor beams starting there (above
    /// the base) and the column up from it.
    fn members_at(&self, i: usize, j: usize, k: usize) -> Vec<TowerMember> {
        let here = self.id(i, j, k);
        let mut v = Vec::new();
        if k > 0 && i + 1 < self.nx {
            v.push(TowerMember {
                nodes: [here, self.id(i + 1, j, k)],
                section: "tube",
                axis: 0,
            });
        }
        if k > 0 && j + 1 < self.ny {
            v.push(TowerMember {
                nodes: [here, self.id(i, j + 1, k)],
                section: "rect",
                axis: 1,
            });
        }
        if k < self.levels {
            v.push(TowerMember {
                nodes: [here, self.id(i, j, k + 1)],
                section: "tube",
                axis: 2,
            });
        }
        v
    }

    /// Every member, in the order the scene lists them.
    pub fn members(&self) -> Vec<TowerMember> {
        let mut v = Vec::new();
        for k in 0..=self.levels {
            for j in 0..self.ny {
                for i in 0..self.nx {
                    v.extend(self.members_at(i, j, k));
                }
            }
        }
        v
    }

    /// The top-floor point masses as (node, kg).
    pub fn top_masses(&self) -> Vec<(usize, f64)> {
        let mut v = Vec::new();
        for j in 0..self.ny {
            for i in 0..self.nx {
                v.push((self.id(i, j, self.levels), 20.0 + 3.0 * (i + 2 * j) as f64));
            }
        }
        v
    }

    /// The base nodes (clamped unless the tower is free).
    pub fn base_nodes(&self) -> Vec<usize> {
        let mut v = Vec::new();
        for j in 0..self.ny {
            for i in 0..self.nx {
                v.push(self.id(i, j, 0));
            }
        }
        v
    }

    /// The tower as scene text.
    pub fn scene(&self) -> String {
        let mut s = String::from(
            "title = \"generated frame tower\"\n\n[[material]]\nname = \"steel\"\nyoungs_modulus_pa = 210e9\npoisson_ratio = 0.3\ndensity_kg_m3 = 7850\n\n\
             [[section]]\nname = \"tube\"\nshape = \"tube\"\nouter_diameter_m = 0.06\ninner_diameter_m = 0.05\n\n\
             [[section]]\nname = \"rect\"\nshape = \"rectangle\"\nwidth_m = 0.04\nheight_m = 0.03\n\n",
        );
        for (id, [x, y, z]) in self.nodes() {
            let _ = writeln!(s, "[[node]]\nid = {id}\nposition_m = [{x}, {y}, {z}]\n");
        }
        self.write_members(&mut s);
        self.write_top_and_base(&mut s);
        s
    }

    fn write_members(&self, s: &mut String) {
        let springs = !self.free && !self.beams_and_point_masses;
        for k in 0..=self.levels {
            for j in 0..self.ny {
                for i in 0..self.nx {
                    for m in self.members_at(i, j, k) {
                        let [a, b] = m.nodes;
                        let _ = writeln!(
                            s,
                            "[[beam]]\nnodes = [{a}, {b}]\nsection = \"{}\"\nmaterial = \"steel\"\nelements = {}\n",
                            m.section, self.elements
                        );
                    }
                    // The springs act along global axes between distinct points, so a rigid
                    // rotation strains them: the free-free tower goes without.
                    let diagonal = i + 1 < self.nx && j + 1 < self.ny && (i + j + k) % 2 == 0;
                    if springs && k < self.levels && diagonal {
                        let _ = writeln!(
                            s,
                            "[[spring]]\nnodes = [{}, {}]\nstiffness = [2e6, 3e6, 1e6, 1e4, 2e4, 5e3]\n",
                            self.id(i, j, k),
                            self.id(i + 1, j + 1, k + 1)
                        );
                    }
                }
            }
        }
    }

    fn write_top_and_base(&self, s: &mut String) {
        for ((top, mass_kg), base) in self.top_masses().into_iter().zip(self.base_nodes()) {
            if self.beams_and_point_masses {
                let _ = writeln!(s, "[[mass]]\nnode = {top}\nmass_kg = {mass_kg}\n");
            } else {
                let _ = writeln!(
                    s,
                    "[[mass]]\nnode = {top}\nmass_kg = {mass_kg}\ninertia_kg_m2 = [0.5, 0.7, 0.9]\noffset_m = [0.05, -0.03, 0.1]\n"
                );
            }
            if !self.free {
                let _ = writeln!(s, "[[support]]\nnode = {base}\ndofs = \"123456\"\n");
            }
            if self.load_n != 0.0 {
                let _ = writeln!(
                    s,
                    "[[static_load]]\nnode = {top}\nforce_n = [0.0, 0.0, {}]\n",
                    -self.load_n
                );
            }
        }
    }
}

/// A small stack for the separation model: `satellites` 150 kg satellites on steel bars of
/// `bar_length_m`, with rigid bars and 700 N/m springs of 0.08 m stroke. `separation_keys` go
/// into the `[separation]` table itself; `tables` (e.g. `[separation.contact]`) are appended
/// at the end.
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

/// The true values of the round-trip model: Young's modulus (handbook steel), a root rotational
/// spring of 2.4·EI/L (EI/L = 4200 N·m: compliant enough to shape the modes) and a 1 kg tip
/// mass on a 4.71 kg beam. Every number is chosen, not measured.
pub const UPDATE_TRUE: [f64; 3] = [210e9, 1.0e4, 1.0];
/// Parameter paths of the round-trip scene, in the order of [`UPDATE_TRUE`].
pub const UPDATE_PATHS: [&str; 3] = [
    "material.0.youngs_modulus_pa",
    "spring.0.stiffness.4",
    "mass.0.mass_kg",
];

/// A 1 m steel cantilever (30 × 20 mm, bending in z about its weak axis) on root springs to a
/// supported ground node, with a tip mass and one tip accelerometer along +z; `values` in the
/// order of [`UPDATE_PATHS`], `test_hz` the `[test_modes]`, `update` appended as written.
pub fn update_round_trip_scene(values: [f64; 3], test_hz: &[f64], update: &str) -> String {
    let modes: String = test_hz
        .iter()
        .map(|f| format!("\n[[test_modes.mode]]\nfrequency_hz = {f:?}\n"))
        .collect();
    let model = update_beam(values, &[(2, 1.0, 20)]);
    format!(
        r#"{model}
[[test_point]]
channel = "tip_z"
node = 2
direction = "+z"

[test_modes]
source = "synthetic: the same model at the true values"
{modes}
{update}"#
    )
}

/// Accelerometers of the log round trip along the beam, +z: (channel, node id, x in m). The
/// stations are multiples of the 0.05 m element, so the mesh is that of the one-point scene.
pub const UPDATE_LOG_POINTS: [(&str, i64, f64); 4] = [
    ("z30", 3, 0.3),
    ("z55", 4, 0.55),
    ("z80", 5, 0.8),
    ("tip_z", 2, 1.0),
];
/// The base-acceleration channel of the synthetic logs.
pub const UPDATE_LOG_CONTROL: &str = "base_z";
/// Modal damping ratio the synthetic logs are made with (a chosen, typical structural value).
pub const UPDATE_LOG_ZETA: f64 = 0.02;

/// The round-trip cantilever with the accelerometers of [`UPDATE_LOG_POINTS`], each also a
/// `[[response]]` point (so the response code recovers its absolute acceleration), the modal
/// damping the logs are made with, and `logs` (`(name, file, kind)`) as `[[test_log]]`s whose
/// FRFs `[correlation]` identifies the test modes from over `band_hz` (no `[correlation]` without logs); `update`
/// appended.
pub fn update_log_scene(
    values: [f64; 3],
    logs: &[(&str, &str, &str)],
    nperseg: usize,
    band_hz: [f64; 2],
    update: &str,
) -> String {
    let mut stations = Vec::new();
    let mut x0 = 0.0;
    for &(_, node, x) in &UPDATE_LOG_POINTS {
        stations.push((node, x, ((x - x0) / 0.05).round() as usize));
        x0 = x;
    }
    let mut s = update_beam(values, &stations);
    let _ = writeln!(s, "\n[damping]\nzeta = {UPDATE_LOG_ZETA:?}");
    let responses: Vec<String> = UPDATE_LOG_POINTS
        .iter()
        .map(|p| format!("{:?}", p.0))
        .collect();
    for (channel, node, _) in UPDATE_LOG_POINTS {
        let _ = writeln!(s, "\n[[response]]\nname = \"{channel}\"\nnode = {node}");
        let _ = writeln!(
            s,
            "\n[[test_point]]\nchannel = \"{channel}\"\nnode = {node}\ndirection = \"+z\""
        );
    }
    for (name, file, kind) in logs {
        let _ = writeln!(
            s,
            "\n[[test_log]]\nname = \"{name}\"\nfile = {file:?}\nkind = \"{kind}\"\ncontrol = \"{UPDATE_LOG_CONTROL}\"\nresponses = [{}]\nnperseg = {nperseg}",
            responses.join(", ")
        );
    }
    let names: Vec<String> = logs.iter().map(|l| format!("{:?}", l.0)).collect();
    if !names.is_empty() {
        let _ = writeln!(
            s,
            "\n[correlation]\nlogs = [{}]\nfmin_hz = {:?}\nfmax_hz = {:?}\n",
            names.join(", "),
            band_hz[0],
            band_hz[1]
        );
    }
    s.push_str(update);
    s
}

/// The model shared by the round-trip scenes, up to `[modal]`: the beam from node 1 at x = 0
/// through `stations` (node id, x in m, elements from the previous station).
fn update_beam(values: [f64; 3], stations: &[(i64, f64, usize)]) -> String {
    let [e, kr, m] = values;
    let tip = stations.last().expect("at least the tip").0;
    let mut nodes = String::new();
    let mut beams = String::new();
    let mut from = 1;
    for &(id, x, elements) in stations {
        let _ = write!(
            nodes,
            "[[node]]\nid = {id}\nposition_m = [{x:?}, 0.0, 0.0]\n\n"
        );
        let _ = write!(
            beams,
            "[[beam]]\nnodes = [{from}, {id}]\nsection = \"bar\"\nmaterial = \"steel\"\nelements = {elements}\norientation = [0.0, 0.0, 1.0]\ntheory = \"euler-bernoulli\"\n\n"
        );
        from = id;
    }
    format!(
        r#"title = "round trip"

[[material]]
name = "steel"
youngs_modulus_pa = {e:?}
poisson_ratio = 0.3
density_kg_m3 = 7850

[[section]]
name = "bar"
shape = "rectangle"
width_m = 0.03
height_m = 0.02

[[node]]
id = 1
position_m = [0.0, 0.0, 0.0]

{nodes}[[node]]
id = 9
position_m = [0.0, 0.0, 0.0]

{beams}# The root: rigid in effect but for the rotation about y that z-bending loads.
[[spring]]
name = "root"
nodes = [9, 1]
stiffness = [1e10, 1e10, 1e10, 1e7, {kr:?}, 1e7]

[[support]]
node = 9
dofs = "123456"

[[mass]]
node = {tip}
mass_kg = {m:?}

[modal]
modes = 12
"#
    )
}

/// `[update]` over the three parameters, bounds a factor 3 either side of the truth.
pub fn update_section(extra: &str) -> String {
    let mut s = String::from("[update]\nmax_iterations = 50\n");
    s.push_str(extra);
    for (p, t) in UPDATE_PATHS.iter().zip(UPDATE_TRUE) {
        s.push_str(&format!(
            "\n[[update.parameter]]\npath = \"{p}\"\nlower = {:?}\nupper = {:?}\n",
            t / 3.0,
            t * 3.0
        ));
    }
    s
}

/// Parameters of the stack update benchmark, their values in the paper stack, and the factor
/// the start is off by: joint bending and axial stiffness, satellite mass and column diameter,
/// the four the stack's lateral modes feel (the preload is left out: the sensitivities do not
/// carry the prestress stiffness).
pub const STACK_UPDATE_PARAMS: [(&str, f64, f64); 4] = [
    ("stack.interface.rotational_stiffness_n_m_rad", 9.7e4, 1.3),
    ("stack.satellite_mass_kg", 120.0, 0.7),
    ("stack.interface.axial_stiffness_n_m", 8.35e6, 1.3),
    ("stack.column_outer_diameter_m", 0.050, 0.7),
];

/// `text` with the first line that sets `key` set to `value` instead.
fn with_first_value(text: &str, key: &str, value: f64) -> String {
    with_first_line(text, key, &format!("{key} = {value:?}"))
}

/// `text` with the first line that sets `key` replaced by `new_line`.
fn with_first_line(text: &str, key: &str, new_line: &str) -> String {
    let mut done = false;
    let mut s = String::with_capacity(text.len());
    for line in text.lines() {
        if !done && starts_with_key(line, key) {
            let _ = writeln!(s, "{new_line}");
            done = true;
        } else {
            let _ = writeln!(s, "{line}");
        }
    }
    s
}

/// The paper stack (`base`) with `n` satellites, its modal analysis cut to the lowest `modes`
/// modes and every other analysis dropped, a triaxial accelerometer on satellite 1 (node
/// 1000), and the parameters of [`STACK_UPDATE_PARAMS`] set to `values`.
pub fn stack_update_model(base: &str, n: usize, modes: usize, values: &[f64; 4]) -> String {
    let stack = stack_with_satellites(base, n);
    let cut = stack.find("\n[separation]").unwrap_or(stack.len());
    let mut s = with_first_line(&stack[..cut], "fmax_hz", &format!("modes = {modes}"));
    for ((path, _, _), v) in STACK_UPDATE_PARAMS.iter().zip(values) {
        let key = path.rsplit('.').next().expect("a dotted path");
        s = with_first_value(&s, key, *v);
    }
    for axis in ["x", "y", "z"] {
        let _ = write!(
            s,
            "\n[[test_point]]\nchannel = \"sat1_{axis}\"\nnode = 1000\ndirection = \"+{axis}\"\n"
        );
    }
    s
}

/// `[test_modes]` of (frequency, shape) pairs and the `[update]` over
/// [`STACK_UPDATE_PARAMS`], bounds a factor 3 either side (the column diameter ±50 %).
pub fn stack_update_tables(test: &[(f64, Vec<f64>)]) -> String {
    let mut s = String::from(
        "\n[test_modes]\nsource = \"synthetic: the same stack at the paper stack's values\"\n",
    );
    for (f, shape) in test {
        let _ = write!(
            s,
            "[[test_modes.mode]]\nfrequency_hz = {f:?}\nshape = {shape:?}\n"
        );
    }
    s.push_str("\n[update]\nmax_iterations = 50\n");
    for (path, v, _) in STACK_UPDATE_PARAMS {
        let (lo, hi) = if path.ends_with("diameter_m") {
            (v / 1.5, v * 1.5)
        } else {
            (v / 3.0, v * 3.0)
        };
        let _ = write!(
            s,
            "[[update.parameter]]\npath = \"{path}\"\nlower = {lo:?}\nupper = {hi:?}\n"
        );
    }
    s
}
