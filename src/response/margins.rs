//! Lock-integrity margins from the recovered loads: gapping and slip of every preloaded column
//! joint, and the strength of the guide bars. Factors come from `spec::analysis::MarginsSpec`
//! (the one place where the defaults and their sources are written). Results are values, not
//! messages: the `gates` layer gates the governing ones.
//!
//! - Gapping (NASA-STD-5020B §4.4.1 separation): MS = P_preload,min / (FF·FS_sep·P_ext) − 1,
//!   P_ext = the axial tension amplitude of the joint (plus, with `include_face_moment`, M·A/Z
//!   of the face bending moment: the moment that unloads the face edge as much as that tension
//!   would), P_preload,min =
//!   nominal·(1 − uncertainty)·(1 − loss).
//! - Slip (NASA-STD-5020B §4.4.2): MS = μ·P_preload,min / (FS_slip·V_ext) − 1 with the shear
//!   resultant amplitude V_ext.
//! - Guide bars (NASA-STD-5020B §4.3.1 form: preload unfactored at its maximum, external load
//!   factored): σ = σ_preload,max + FS·(|N|/A + M_b/Z), τ = FS·T/(J/c),
//!   σ_vm = √(σ² + 3τ²); MS = allowable/σ_vm − 1 against yield (FS 1.25) and ultimate (1.4).
//!
//! A margin whose load is nil is reported as [`MARGIN_CAP`]. Each margin is a
//! [`Verdict`] naming its `kind` (`gapping`, `slip`, `bar yield`, `bar ultimate`) and its
//! `load_case` (`sine x`, `random z` ...); `value` is the factored applied quantity (N, or Pa
//! for stresses) and `limit` the allowable it is compared with.

use super::outputs::{BarStation, InterfaceOut};
use crate::gates::{Group, Verdict};
use crate::spec::analysis::MarginsSpec;

/// Margins above this are reported as this value (no meaningful load on that path).
pub const MARGIN_CAP: f64 = 999.0;

fn margin(name: String, kind: &str, case: &str, value: f64, limit: f64, source: String) -> Verdict {
    let m = if value > 1e-12 * limit.abs().max(1e-300) {
        (limit / value - 1.0).min(MARGIN_CAP)
    } else {
        MARGIN_CAP
    };
    // Bar margins compare stresses, joint margins forces.
    let (group, unit) = if kind.starts_with("bar") {
        (Group::BarStrength, "Pa")
    } else {
        (Group::LockIntegrity, "N")
    };
    Verdict {
        name,
        group: Some(group),
        kind: kind.into(),
        load_case: case.into(),
        value,
        limit,
        unit: unit.into(),
        margin: m,
        pass: m > 0.0,
        source,
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
    vec![
        margin(
            format!("gapping {}", ifc.name),
            "gapping",
            case,
            s.fitting_factor * s.separation_factor * p_ext,
            pmin,
            format!(
                "NASA-STD-5020B separation: P_preload,min/(FF·FS_sep·P_ext) − 1, FF {}, FS_sep {}, preload {:.0} N −{:.0}% uncertainty −{:.0}% loss",
                s.fitting_factor,
                s.separation_factor,
                nominal,
                100.0 * s.preload_uncertainty,
                100.0 * s.preload_loss
            ),
        ),
        margin(
            format!("slip {}", ifc.name),
            "slip",
            case,
            s.slip_factor * v_ext,
            s.friction_coefficient * pmin,
            format!(
                "NASA-STD-5020B slip: μ·P_preload,min/(FS_slip·V_ext) − 1, μ {}, FS_slip {}",
                s.friction_coefficient, s.slip_factor
            ),
        ),
    ]
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
        out.push(margin(
            format!("yield {}", st.bar),
            "bar yield",
            case,
            vm_yield,
            y,
            format!(
                "von Mises of max preload ({:.0} N +{:.0}%) + {}×dynamic vs yield (NASA-STD-5001B), worst station {}",
                st.preload_axial_n,
                100.0 * s.preload_uncertainty,
                s.yield_factor,
                st.name
            ),
        ));
    }
    if let Some(u) = st.ultimate_pa {
        out.push(margin(
            format!("ultimate {}", st.bar),
            "bar ultimate",
            case,
            vm_ult,
            u,
            format!(
                "von Mises of max preload ({:.0} N +{:.0}%) + {}×dynamic vs ultimate (NASA-STD-5001B), worst station {}",
                st.preload_axial_n,
                100.0 * s.preload_uncertainty,
                s.ultimate_factor,
                st.name
            ),
        ));
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
