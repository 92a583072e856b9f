//! The NI scaling stated in TDMS properties (`NI_Number_Of_Scales`, `NI_Scale[i]_...`), as
//! NI-DAQmx logging and LabVIEW's raw writes leave it: a chain of scales, each reading the
//! output of another (its input source) or the raw values, the last giving physical units.
//! Linear and polynomial scales are applied; any other type leaves the channel unread, with
//! the reason, rather than returning raw counts as if they were physical values.

use super::values::PropValue;

/// The input source that means "the raw values".
const RAW: u32 = 0xFFFF_FFFF;
/// No real scaling chain is deeper; a longer one is a loop.
const MAX_DEPTH: usize = 32;
/// No real polynomial scale has more coefficients.
const MAX_COEFFICIENTS: usize = 64;

type Props = [(String, PropValue)];

fn number(p: &Props, key: &str) -> Option<f64> {
    p.iter().find_map(|(n, v)| match v {
        PropValue::Number(x) if n == key => Some(*x),
        _ => None,
    })
}

fn text<'p>(p: &'p Props, key: &str) -> Option<&'p str> {
    p.iter().find_map(|(n, v)| match v {
        PropValue::Text(t) if n == key => Some(t.as_str()),
        _ => None,
    })
}

/// The number of scales stated: `NI_Number_Of_Scales`, else one past the highest
/// `NI_Scale[i]_Scale_Type`.
fn scale_count(p: &Props) -> Option<u32> {
    if let Some(n) = number(p, "NI_Number_Of_Scales") {
        return Some(n.clamp(0.0, MAX_DEPTH as f64) as u32);
    }
    p.iter()
        .filter_map(|(n, _)| {
            n.strip_prefix("NI_Scale[")?
                .strip_suffix("]_Scale_Type")?
                .parse::<u32>()
                .ok()
        })
        .max()
        .map(|i| i.saturating_add(1))
}

/// The channel's values in physical units, from the first of `levels` (channel, group, file
/// properties) that states a scaling, with the chain applied (`DAQmx raw → Polynomial →
/// Linear`); `None` when nothing is to be applied. An error says why the channel cannot be
/// read.
pub fn apply(
    levels: &[&Props],
    daqmx_scale_id: Option<u32>,
    raw: &[f64],
) -> Result<Option<(Vec<f64>, String)>, String> {
    let found = levels
        .iter()
        .find_map(|p| scale_count(p).filter(|&n| n > 0).map(|n| (*p, n)));
    let Some((props, n)) = found else {
        return match daqmx_scale_id {
            Some(_) => Err("DAQmx raw values, and no scaling in the properties".into()),
            None => Ok(None),
        };
    };
    if text(props, "NI_Scaling_Status") == Some("scaled") {
        return Ok(None);
    }
    let mut chain = Vec::new();
    let values = scale(props, n - 1, daqmx_scale_id, raw, 0, &mut chain)?;
    Ok(Some((values, chain.join(" → "))))
}

/// The output of scale `i`, computing its input first.
fn scale(
    p: &Props,
    i: u32,
    daqmx: Option<u32>,
    raw: &[f64],
    depth: usize,
    chain: &mut Vec<String>,
) -> Result<Vec<f64>, String> {
    if i == RAW {
        chain.push("raw".into());
        return Ok(raw.to_vec());
    }
    if depth > MAX_DEPTH {
        return Err("the scales' input sources form a loop".into());
    }
    let key = |name: &str| format!("NI_Scale[{i}]_{name}");
    let need = |name: &str| {
        number(p, &key(name)).ok_or_else(|| format!("scale {i} lacks `{}`", key(name)))
    };
    let input = |kind: &str, chain: &mut Vec<String>| {
        let source = number(p, &key(&format!("{kind}_Input_Source"))).map_or(RAW, |s| s as u32);
        scale(p, source, daqmx, raw, depth + 1, chain)
    };
    let out = match text(p, &key("Scale_Type")) {
        None if daqmx == Some(i) => {
            chain.push("DAQmx raw".into());
            return Ok(raw.to_vec());
        }
        None => {
            return Err(format!(
                "scale {i} has no type and is not the channel's DAQmx scaler"
            ));
        }
        Some("Linear") => {
            let (slope, intercept) = (need("Linear_Slope")?, need("Linear_Y_Intercept")?);
            let x = input("Linear", chain)?;
            x.iter().map(|v| v * slope + intercept).collect()
        }
        Some("Polynomial") => {
            let size = number(p, &key("Polynomial_Coefficients_Size")).unwrap_or(4.0);
            if !(0.0..=MAX_COEFFICIENTS as f64).contains(&size) {
                return Err(format!("scale {i} states {size} polynomial coefficients"));
            }
            let c = (0..size as usize)
                .map(|k| need(&format!("Polynomial_Coefficients[{k}]")))
                .collect::<Result<Vec<_>, _>>()?;
            let x = input("Polynomial", chain)?;
            // Horner's rule, highest power first.
            x.iter()
                .map(|v| c.iter().rev().fold(0.0, |acc, ck| acc * v + ck))
                .collect()
        }
        Some("AdvancedAPI") => input("AdvancedAPI", chain)?,
        Some(other) => {
            return Err(format!(
                "scale {i} is of type {other}, which satqual does not apply"
            ));
        }
    };
    chain.push(text(p, &key("Scale_Type")).unwrap_or("").to_string());
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn props(list: &[(&str, PropValue)]) -> Vec<(String, PropValue)> {
        list.iter()
            .map(|(n, v)| (n.to_string(), v.clone()))
            .collect()
    }

    #[test]
    fn a_daqmx_chain_applies_polynomial_then_linear() {
        let t = |s: &str| PropValue::Text(s.into());
        let x = PropValue::Number;
        let p = props(&[
            ("NI_Number_Of_Scales", x(3.0)),
            ("NI_Scale[1]_Scale_Type", t("Polynomial")),
            ("NI_Scale[1]_Polynomial_Coefficients_Size", x(2.0)),
            ("NI_Scale[1]_Polynomial_Coefficients[0]", x(0.5)),
            ("NI_Scale[1]_Polynomial_Coefficients[1]", x(0.001)),
            ("NI_Scale[1]_Polynomial_Input_Source", x(0.0)),
            ("NI_Scale[2]_Scale_Type", t("Linear")),
            ("NI_Scale[2]_Linear_Slope", x(10.0)),
            ("NI_Scale[2]_Linear_Y_Intercept", x(-1.0)),
            ("NI_Scale[2]_Linear_Input_Source", x(1.0)),
        ]);
        let (v, chain) = apply(&[&p], Some(0), &[1000.0]).unwrap().unwrap();
        // (0.5 + 0.001·1000)·10 − 1 = 14.
        assert_eq!(v, [14.0]);
        assert_eq!(chain, "DAQmx raw → Polynomial → Linear");
    }

    #[test]
    fn unknown_types_loops_and_unscaled_daqmx_are_refused() {
        let t = |s: &str| PropValue::Text(s.into());
        let p = props(&[("NI_Scale[0]_Scale_Type", t("Thermocouple"))]);
        assert!(
            apply(&[&p], None, &[1.0])
                .unwrap_err()
                .contains("Thermocouple")
        );
        assert!(
            apply(&[&[]], Some(0), &[1.0])
                .unwrap_err()
                .contains("no scaling")
        );
        let l = props(&[
            ("NI_Scale[0]_Scale_Type", t("Linear")),
            ("NI_Scale[0]_Linear_Slope", PropValue::Number(1.0)),
            ("NI_Scale[0]_Linear_Y_Intercept", PropValue::Number(0.0)),
            ("NI_Scale[0]_Linear_Input_Source", PropValue::Number(0.0)),
        ]);
        assert!(apply(&[&l], None, &[1.0]).unwrap_err().contains("loop"));
        assert_eq!(apply(&[&[]], None, &[1.0]).unwrap(), None);
    }
}
