//! Lock-integrity margins from the recovered loads: gapping and slip of every preloaded column
//! joint, and the strength of the guide bars. Factors come from `spec::analysis::MarginsSpec`
//! (the one place where the defaults and their sources are written). Results are values, not
//! messages: the `gates` layer gates the governing ones. Every margin follows the convention
//! of `gates::verdict::strength_margin`: MS = allowable / (FS × applied) − 1, `value` the
//! design load FS × applied, `limit` the allowable.
//!
//! - Gapping (NASA-STD-5020B §4.4.1 separation): allowable P_preload,min =
//!   nominal·(1 − uncertainty)·(1 − loss), applied P_ext = the axial tension amplitude of the
//!   joint plus (with `include_face_moment`, the default) M·A/Z of the face bending moment,
//!   FS = FF·FS_sep.
//! - Slip (NASA-STD-5020B §4.4.2): the shear V_ext goes through the first path that holds it:
//!   friction (μ·P_preload,min, FS_slip); else a shear key (`[stack.interface] shear_key`,
//!   FS = the yield factor); else the guide bar, which bears on the bore once the joint has
//!   slipped the radial clearance (FS = the yield factor). NASA-STD-5020B accepts slip where
//!   a shear feature carries the load and the joint is designed for it; the margin is that of
//!   the path that carries the load, and its source names the path.
//! - Guide bars (NASA-STD-5020B §4.3.1 form: preload unfactored at its maximum, external load
//!   factored): σ = σ_preload,max + FS·(|N|/A + M_b/Z), τ = FS·T/(J/c),
//!   σ_vm = √(σ² + 3τ²); MS = allowable/σ_vm − 1 against yield (FS 1.25) and ultimate (1.4).
//!
//! A margin whose load is nil is reported as `gates::MARGIN_CAP`. Each margin is a
//! [`Verdict`] naming its `kind` (`gapping`, `slip`, `bar yield`, `bar ultimate`) and its
//! `load_case` (`sine x`, `random z` ...).

use super::outputs::{BarStation, InterfaceOut};
use crate::gates::{Group, Verdict, design_margin, strength_margin};
use crate::spec::Material;
use crate::spec::analysis::MarginsSpec;
use crate::spec::stack::StackSpec;

/// The shear capacities of a stack joint beyond friction.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ShearPaths {
    /// Capacity of the shear key (connector), N, when the scene gives one.
    pub key_n: Option<f64>,
    /// Capacity of the guide bar bearing on the column bore, N: min(bar shear yield·A_bar,
    /// column bearing yield · d_bar · d_bar); `None` without material strengths.
    pub bar_n: Option<f64>,
    /// Radial clearance the joint slips before the bar bears, m.
    pub clearance_m: f64,
}

impl ShearPaths {
    /// The paths of a stack's column joints. The bar's bearing on the bore is taken over one
    /// bar diameter of bore length (ASSUMPTION: the edge contact of a bar tilted in its bore
    /// spreads over about a diameter; the line contact along the bore of the paper's model,
    /// §3.3.1, would bear more).
    pub fn of_stack(st: &StackSpec, materials: &[Material]) -> ShearPaths {
        let yield_of = |name: &str| {
            materials
                .iter()
                .find(|m| m.name == name)
                .and_then(|m| m.yield_strength_pa)
        };
        let d = st.bar_diameter_m;
        let bar_n = match (yield_of(&st.bar_material), yield_of(&st.column_material)) {
            (Some(fb), Some(fc)) => {
                let shear = fb / 3f64.sqrt() * std::f64::consts::PI / 4.0 * d * d;
                Some(shear.min(fc * d * d))
            }
            _ => None,
        };
        ShearPaths {
            key_n: st
                .interface
                .shear_key
                .as_ref()
                .and_then(|k| k.capacity_n(materials)),
            bar_n,
            clearance_m: st.radial_clearance_m(),
        }
    }
}

/// A verdict of a response analysis: its family and load case.
fn tagged(v: Verdict, kind: &str, case: &str) -> Verdict {
    // Bar margins compare stresses, joint margins forces.
    let (group, unit) = if kind.starts_with("bar") {
        (Group::BarStrength, "Pa")
    } else {
        (Group::LockIntegrity, "N")
    };
    Verdict {
        kind: kind.into(),
        load_case: case.into(),
        group: Some(group),
        unit: unit.into(),
        ..v
    }
}

/// Gapping and slip of one joint under an external tension `p_ext` and shear `v_ext` (N).
/// Joints without a known preload get no margin.
pub fn interface(
    ifc: &InterfaceOut,
    p_ext: f64,
    v_ext: f64,
    s: &MarginsSpec,
    case: &str,
) -> Vec<Verdict> {
    let Some(nominal) = ifc.preload_n else {
        return Vec::new();
    };
    let pmin = s.min_preload(nominal);
    let moment = if s.include_face_moment {
        " + M·A/Z of the face moment"
    } else {
        ""
    };
    let gapping = strength_margin(
        format!("gapping {}", ifc.name),
        p_ext,
        pmin,
        s.fitting_factor * s.separation_factor,
        format!(
            "NASA-STD-5020B separation: P_preload,min/(FF·FS_sep·P_ext) − 1, P_ext = tension{moment}, FF {}, FS_sep {}, preload {:.0} N −{:.0}% uncertainty −{:.0}% loss",
            s.fitting_factor,
            s.separation_factor,
            nominal,
            100.0 * s.preload_uncertainty,
            100.0 * s.preload_loss
        ),
    );
    vec![
        tagged(gapping, "gapping", case),
        tagged(slip(ifc, v_ext, pmin, s), "slip", case),
    ]
}

/// The slip margin of the path that carries the shear `v` (see the module note).
fn slip(ifc: &InterfaceOut, v: f64, pmin: f64, s: &MarginsSpec) -> Verdict {
    let name = format!("slip {}", ifc.name);
    let mu = s.friction_coefficient;
    let friction = strength_margin(
        &name,
        v,
        mu * pmin,
        s.slip_factor,
        format!(
            "load path: friction. NASA-STD-5020B slip: μ·P_preload,min/(FS_slip·V_ext) − 1, μ {mu}, FS_slip {}",
            s.slip_factor
        ),
    );
    if friction.pass {
        return friction;
    }
    let exceeded = format!(
        "friction exceeded (μ·P_min {:.0} N < FS_slip·V {:.0} N)",
        friction.limit, friction.value
    );
    let paths = &ifc.shear_paths;
    if let Some(key) = paths.key_n {
        return strength_margin(
            &name,
            v,
            key,
            s.yield_factor,
            format!(
                "load path: shear key. {exceeded}; the connector carries the shear: capacity min(τ·A_s, σ_br·A_br)/(FS·V) − 1, FS {} (NASA-STD-5020B: slip acceptable where a shear feature carries the load)",
                s.yield_factor
            ),
        );
    }
    if let Some(bar) = paths.bar_n {
        return strength_margin(
            &name,
            v,
            bar,
            s.yield_factor,
            format!(
                "load path: guide bar. {exceeded}; the joint slips the {:.2} mm radial clearance, then the bar bears on the bore: capacity min(bar shear yield, bore bearing yield over one bar diameter)/(FS·V) − 1, FS {} (NASA-STD-5020B: slip acceptable where a shear feature carries the load)",
                1e3 * paths.clearance_m,
                s.yield_factor
            ),
        );
    }
    Verdict {
        source: format!(
            "load path: none. {exceeded} and no shear key or guide-bar strength is given"
        ),
        ..friction
    }
}

/// Factored von Mises stress of a bar station for dynamic amplitudes (N, bending resultant,
/// torque) and a factor of safety `fs`.
pub fn bar_von_mises(st: &BarStation, s: &MarginsSpec, fs: f64, n: f64, mb: f64, t: f64) -> f64 {
    let pre = s.max_preload(st.preload_axial_n.max(0.0)) / st.area_m2;
    let sigma = pre + fs * (n.abs() / st.area_m2 + mb / st.section_modulus_m3);
    let tau = fs * t.abs() / st.torsion_modulus_m3;
    (sigma * sigma + 3.0 * tau * tau).sqrt()
}

/// Yield and ultimate margins of one bar station from its worst factored stresses
/// (`vm_yield` with the yield factor, `vm_ult` with the ultimate factor), when the material
/// gives the strengths.
pub fn bar(
    st: &BarStation,
    s: &MarginsSpec,
    vm_yield: f64,
    vm_ult: f64,
    case: &str,
) -> Vec<Verdict> {
    let mut out = Vec::new();
    if let Some(y) = st.yield_pa {
        let v = design_margin(
            format!("yield {}", st.bar),
            vm_yield,
            y,
            format!(
                "von Mises of max preload ({:.0} N +{:.0}%) + {}×dynamic vs yield (NASA-STD-5001B), worst station {}",
                st.preload_axial_n,
                100.0 * s.preload_uncertainty,
                s.yield_factor,
                st.name
            ),
        );
        out.push(tagged(v, "bar yield", case));
    }
    if let Some(u) = st.ultimate_pa {
        let v = design_margin(
            format!("ultimate {}", st.bar),
            vm_ult,
            u,
            format!(
                "von Mises of max preload ({:.0} N +{:.0}%) + {}×dynamic vs ultimate (NASA-STD-5001B), worst station {}",
                st.preload_axial_n,
                100.0 * s.preload_uncertainty,
                s.ultimate_factor,
                st.name
            ),
        );
        out.push(tagged(v, "bar ultimate", case));
    }
    out
}

/// Keeps, for each (name, kind), the smallest margin.
pub fn worst_per_item(ms: Vec<Verdict>) -> Vec<Verdict> {
    let mut out: Vec<Verdict> = Vec::new();
    for m in ms {
        match out
            .iter_mut()
            .find(|o| o.name == m.name && o.kind == m.kind)
        {
            Some(o) => {
                if m.margin < o.margin {
                    *o = m;
                }
            }
            None => out.push(m),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A joint of the paper stack: 45 kN / 4 = 11 250 N nominal preload, P_min = 11 250 ·
    /// 0.9 · 0.95 = 9 618.75 N, μ·P_min = 1 923.75 N with the default factors.
    fn joint(paths: ShearPaths) -> InterfaceOut {
        InterfaceOut {
            name: "interface a/b column 1".into(),
            rows: [0; 6],
            preload_n: Some(11_250.0),
            face_a_over_z: 0.0,
            shear_paths: paths,
        }
    }

    fn slip_of(ifc: &InterfaceOut, v: f64) -> Verdict {
        let ms = interface(ifc, 0.0, v, &MarginsSpec::default(), "sine x");
        ms.into_iter().find(|m| m.kind == "slip").unwrap()
    }

    /// Capacities of the paper-stack joint, by hand. Shear key (7075-T6 spigot, yield 503 MPa):
    /// shear 6.715e-4 m² · 503e6/√3 = 195 010 N, bearing 3.6e-4 m² · 503e6 = 181 080 N → 181 080 N.
    /// Guide bar (30CrMnSiA, yield 835 MPa, d = 20 mm): shear 835e6/√3 · π/4 · 0.02² =
    /// 151 452 N, bearing on the 7075 bore over one diameter 503e6 · 0.02² = 201 200 N →
    /// 151 452 N. Radial clearance (21 − 20)/2 = 0.5 mm.
    #[test]
    fn the_paper_stack_joint_has_the_hand_computed_shear_capacities() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/test-specs/paper-stack.toml");
        let scene = crate::spec::Scene::load(std::path::Path::new(path)).unwrap();
        let st = scene.file.stack.as_ref().unwrap();
        let p = ShearPaths::of_stack(st, &scene.model.material);
        assert!((p.key_n.unwrap() - 181_080.0).abs() < 1e-6);
        assert!(
            (p.bar_n.unwrap() - 151_452.25).abs() < 0.01,
            "{:?}",
            p.bar_n
        );
        assert!((p.clearance_m - 0.0005).abs() < 1e-12);
    }

    /// The slip gate takes the first path that holds the shear, with its own factor
    /// (NASA-STD-5001B convention MS = allowable/(FS·applied) − 1):
    /// - V = 1 500 N: friction holds, MS = 1 923.75/(1.0 · 1 500) − 1 = 0.2825;
    /// - V = 3 000 N, shear key of 181 080 N: MS = 181 080/(1.25 · 3 000) − 1 = 47.288;
    /// - V = 3 000 N, no key, bar of 151 452 N: MS = 151 452/(1.25 · 3 000) − 1 = 39.3872;
    /// - V = 3 000 N, no path: friction fails, MS = 1 923.75/3 000 − 1 = −0.35875.
    #[test]
    fn slip_is_judged_on_the_path_that_carries_the_shear() {
        let both = ShearPaths {
            key_n: Some(181_080.0),
            bar_n: Some(151_452.0),
            clearance_m: 0.0005,
        };
        let v = slip_of(&joint(both.clone()), 1_500.0);
        assert!(v.pass && (v.margin - 0.2825).abs() < 1e-12);
        assert!(v.source.starts_with("load path: friction"), "{}", v.source);
        let v = slip_of(&joint(both.clone()), 3_000.0);
        assert!((v.value - 3_750.0).abs() < 1e-9 && v.limit == 181_080.0);
        assert!((v.margin - 47.288).abs() < 1e-9);
        assert!(v.source.starts_with("load path: shear key"), "{}", v.source);
        let bar_only = ShearPaths {
            key_n: None,
            ..both
        };
        let v = slip_of(&joint(bar_only), 3_000.0);
        assert!((v.margin - (151_452.0 / 3_750.0 - 1.0)).abs() < 1e-12);
        assert!((v.margin - 39.3872).abs() < 1e-4);
        assert!(
            v.source.contains("0.50 mm radial clearance"),
            "{}",
            v.source
        );
        let v = slip_of(&joint(ShearPaths::default()), 3_000.0);
        assert!(!v.pass && (v.margin + 0.35875).abs() < 1e-12);
        assert!(v.source.starts_with("load path: none"), "{}", v.source);
    }

    /// Gapping with the face moment (on by default): P_ext = 2 000 N + 10 N·m · 100 1/m =
    /// 3 000 N; design 1.15 · 1.2 · 3 000 = 4 140 N; MS = 9 618.75/4 140 − 1 = 1.323370.
    /// The caller adds the moment (`Prepared::face_moment_factor`); here it is added by hand.
    #[test]
    fn gapping_uses_the_factored_tension_against_the_minimum_preload() {
        let ifc = InterfaceOut {
            face_a_over_z: 100.0,
            ..joint(ShearPaths::default())
        };
        let s = MarginsSpec::default();
        assert!(s.include_face_moment);
        let p_ext = 2_000.0 + 10.0 * ifc.face_a_over_z;
        let ms = interface(&ifc, p_ext, 0.0, &s, "random z");
        let g = &ms[0];
        assert_eq!(
            (g.kind.as_str(), g.load_case.as_str()),
            ("gapping", "random z")
        );
        assert!((g.value - 4_140.0).abs() < 1e-9 && (g.limit - 9_618.75).abs() < 1e-9);
        assert!((g.margin - 1.323370).abs() < 1e-6);
    }
}
