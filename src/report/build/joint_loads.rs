//! The joint loads: per joint, the envelope over the excitation axes of the sine peak and the
//! random 3σ loads, so a joint designer reads one line per joint.

use crate::report::document::{Block, Column, Section, Table};
use crate::response::SceneResponse;

/// The worst loads of one joint over every axis.
struct JointEnvelope {
    name: String,
    sine_axial_n: f64,
    sine_shear_n: f64,
    random_axial_n: f64,
    random_shear_n: f64,
}

/// The envelope of `name`, added (all zero) the first time the joint is met, so joints keep
/// the order in which the analyses list them.
fn entry<'a>(loads: &'a mut Vec<JointEnvelope>, name: &str) -> &'a mut JointEnvelope {
    let k = match loads.iter().position(|l| l.name == name) {
        Some(k) => k,
        None => {
            loads.push(JointEnvelope {
                name: name.to_string(),
                sine_axial_n: 0.0,
                sine_shear_n: 0.0,
                random_axial_n: 0.0,
                random_shear_n: 0.0,
            });
            loads.len() - 1
        }
    };
    &mut loads[k]
}

fn envelopes(resp: &SceneResponse) -> Vec<JointEnvelope> {
    let mut loads = Vec::new();
    for i in resp.sine.iter().flat_map(|a| &a.interfaces) {
        let e = entry(&mut loads, &i.name);
        e.sine_axial_n = e.sine_axial_n.max(i.max_tension_n);
        e.sine_shear_n = e.sine_shear_n.max(i.max_shear_n);
    }
    for i in resp.random.iter().flat_map(|a| &a.interfaces) {
        let e = entry(&mut loads, &i.name);
        e.random_axial_n = e.random_axial_n.max(i.tension_3sigma_n);
        e.random_shear_n = e.random_shear_n.max(i.shear_3sigma_n);
    }
    loads
}

pub fn section(resp: &SceneResponse) -> Option<Section> {
    let loads = envelopes(resp);
    if loads.is_empty() {
        return None;
    }
    let mut t = Table::new(vec![
        Column::left("joint"),
        Column::right("sine axial [N]"),
        Column::right("sine shear [N]"),
        Column::right("random 3σ axial [N]"),
        Column::right("random 3σ shear [N]"),
    ]);
    for l in loads {
        t.row(vec![
            l.name,
            format!("{:.0}", l.sine_axial_n),
            format!("{:.0}", l.sine_shear_n),
            format!("{:.0}", l.random_axial_n),
            format!("{:.0}", l.random_shear_n),
        ]);
    }
    Some(Section::new(
        "Joint loads (envelope over the axes)",
        vec![Block::Table(t)],
    ))
}
