//! Body-fixed points of the release: the bore edges of every satellite (bottom and top of
//! each of its four columns) and the two seats of every spring, each relative to the CG of
//! the body that carries it, in that body's axes.

use super::super::body::V3;
use super::super::params::Model;

/// Edge points per satellite, relative to its CG: `[column][bottom, top]`. A satellite's
/// column segment is one pitch high and centred on the satellite's origin; its guided bore
/// (`bore_length_m`) is centred on the column.
pub(super) fn edge_points(m: &Model) -> Vec<[[V3; 2]; 4]> {
    column_points(m, m.bore_length_m)
}

/// The bottom and top of every column, relative to the CG: `[column][bottom, top]`.
pub(super) fn column_end_points(m: &Model) -> Vec<[[V3; 2]; 4]> {
    column_points(m, m.pitch_m)
}

/// Points on every column's axis at ∓`length`/2 from the satellite's origin.
fn column_points(m: &Model, length: f64) -> Vec<[[V3; 2]; 4]> {
    let hp = 0.5 * length;
    m.satellites
        .iter()
        .map(|s| {
            let c = s.cg_offset_m;
            let mut e = [[V3::zeros(); 2]; 4];
            for (j, xy) in m.columns_xy.iter().enumerate() {
                e[j][0] = V3::new(xy[0] - c[0], xy[1] - c[1], -hp - c[2]);
                e[j][1] = V3::new(xy[0] - c[0], xy[1] - c[1], hp - c[2]);
            }
            e
        })
        .collect()
}

/// Per spring: its seat on the upper body (the bottom of the upper satellite's column) and on
/// the lower body (the top of the lower satellite's column, or the carrier's base).
pub(super) fn spring_points(m: &Model) -> (Vec<V3>, Vec<V3>) {
    let hp = 0.5 * m.pitch_m;
    let n = m.n_satellites();
    let mut spring_up = Vec::new();
    let mut spring_low = Vec::new();
    for s in &m.springs {
        let xy = m.columns_xy[s.column];
        let cu = m.satellites[s.interface - 1].cg_offset_m;
        spring_up.push(V3::new(xy[0] - cu[0], xy[1] - cu[1], -hp - cu[2]));
        if s.interface < n {
            let cl = m.satellites[s.interface].cg_offset_m;
            spring_low.push(V3::new(xy[0] - cl[0], xy[1] - cl[1], hp - cl[2]));
        } else {
            // Carrier frame: origin at the bar root (= the carrier's CG).
            spring_low.push(V3::new(xy[0], xy[1], m.base_height_m));
        }
    }
    (spring_up, spring_low)
}

#[cfg(test)]
mod tests {
    use super::super::fixture;
    use super::*;

    /// Hand geometry of the fixture (columns at (±0.5, ±0.4), pitch 0.5, CG offset
    /// (0.01, −0.02, 0.03)): exact in binary for these inputs up to one rounding of each sum.
    #[test]
    fn edges_and_spring_seats_sit_at_the_column_ends_relative_to_the_cg() {
        let m = fixture::two_satellites();
        let e = edge_points(&m);
        let c = m.satellites[0].cg_offset_m;
        // Satellite 1, column 0 (+, +): bottom and top.
        assert_eq!(e[0][0][0], V3::new(0.5 - c[0], 0.4 - c[1], -0.25 - c[2]));
        assert_eq!(e[0][0][1], V3::new(0.5 - c[0], 0.4 - c[1], 0.25 - c[2]));
        let (up, low) = spring_points(&m);
        // Spring 0: interface 1 (below satellite 1, above satellite 2), column 0.
        assert_eq!(up[0], e[0][0][0]);
        assert_eq!(low[0], e[1][0][1]);
        // Springs 4..8: interface 2, on the carrier's base.
        assert_eq!(low[4], V3::new(0.5, 0.4, m.base_height_m));
    }

    /// A guided bore of 0.3 m on the 0.5 m column: its edges at ±0.15 m about the column's
    /// middle, the column ends (axial gaps) and spring seats still at ±0.25 m. Exact sums.
    #[test]
    fn a_short_bore_is_centred_on_its_column() {
        let mut m = fixture::two_satellites();
        m.bore_length_m = 0.3;
        let c = m.satellites[0].cg_offset_m;
        let e = edge_points(&m);
        assert_eq!(e[0][0][0], V3::new(0.5 - c[0], 0.4 - c[1], -0.15 - c[2]));
        assert_eq!(e[0][0][1], V3::new(0.5 - c[0], 0.4 - c[1], 0.15 - c[2]));
        let ends = column_end_points(&m);
        assert_eq!(ends[0][0][0], V3::new(0.5 - c[0], 0.4 - c[1], -0.25 - c[2]));
        let (up, _) = spring_points(&m);
        assert_eq!(up[0], ends[0][0][0]);
    }
}
