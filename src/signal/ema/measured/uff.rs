//! Measured FRFs from UFF58 records: which records belong together (one reference, or one
//! response of a roving hammer), their names, lines, form and unit.

use super::{FrfRecordSource, Layout, MeasuredFrfs, distinct, file_name, same_lines, select, span};
use crate::error::SignalError;
use crate::signal::ema::{FrfForm, FrfSet};
use crate::signal::ingest::Unit;
use crate::signal::uff::{self, UffRecord};
use realfft::num_complex::Complex64;
use std::path::PathBuf;

/// UFF58 function type of a frequency response function (record 6, field 1).
const FUNCTION_FRF: i64 = 4;

/// UFF58 function type of a time response, from which `ema` estimates FRFs.
const FUNCTION_TIME: i64 = 1;

/// UFF58 abscissa data type of a time axis (record 8): an FRF on it is not a spectrum.
const DATA_TYPE_TIME: i64 = 17;

/// Pound-force in newtons (exact by definition: 0.45359237 kg × 9.80665 m/s²).
const LBF_IN_N: f64 = 4.448_221_615_260_5;

/// One FRF record and the file it came from.
struct Found {
    file: PathBuf,
    record: UffRecord,
}

impl Found {
    fn err(&self, message: impl Into<String>) -> SignalError {
        SignalError::Uff {
            file: self.file.clone(),
            line: self.record.line,
            message: message.into(),
        }
    }

    fn reference(&self) -> String {
        let f = &self.record.function;
        labelled(&f.reference_entity, f.reference_node, f.reference_direction)
    }

    fn response(&self) -> String {
        let f = &self.record.function;
        labelled(&f.response_entity, f.response_node, f.response_direction)
    }
}

fn labelled(entity: &str, node: i64, direction: i64) -> String {
    let p = uff::point(node, direction);
    if entity.is_empty() {
        p
    } else {
        format!("{entity}:{p}")
    }
}

/// The measured FRFs of UFF files; `None` when they hold none but time histories.
pub(super) fn uff_frfs(
    paths: &[PathBuf],
    input: Option<&str>,
    outputs: &[String],
) -> Result<Option<MeasuredFrfs>, SignalError> {
    let (found, others) = frf_records(paths)?;
    if found.is_empty() {
        return without_frfs(&others);
    }
    if let Some(p) = paths.iter().find(|p| !uff::looks_like_uff(p)) {
        return Err(SignalError::Unsupported {
            file: p.clone(),
            message: "FRFs read from UFF files cannot be averaged with time histories: give \
                      either the UFF files or the logs"
                .into(),
        });
    }
    let (layout, common_point, chosen) = choose(found, input)?;
    let first_file = chosen[0].file.clone();
    let named = select(name(chosen, layout)?, outputs, &first_file)?;
    let freqs = common_lines(&named)?;
    let (form, form_basis) = common_form(&named)?;
    let (unit, scales, mut notes) = common_unit(&named)?;
    notes.insert(0, measured_note(&named, layout, &common_point));
    if !others.is_empty() {
        notes.push(format!(
            "{} UFF58 record(s) of other function types (time histories, spectra, \
             coherence) left out: only the FRFs (function type 4) are fitted",
            others.len()
        ));
    }
    let (set, records) = scaled_set(&named, freqs, &scales);
    Ok(Some(MeasuredFrfs {
        set,
        form,
        form_basis,
        layout,
        common_point,
        unit,
        records,
        notes,
    }))
}

/// No FRF: time histories to estimate FRFs from (`None`), or nothing `ema` can use, named
/// by the first record's file, line and function type.
fn without_frfs(others: &[Other]) -> Result<Option<MeasuredFrfs>, SignalError> {
    if others.iter().any(|o| o.function_type == FUNCTION_TIME) {
        return Ok(None);
    }
    match others.first() {
        Some(o) => Err(SignalError::Unsupported {
            file: o.file.clone(),
            message: format!(
                "line {}: record `{}` is {}, and no record is an FRF (UFF58 function type 4) \
                 or a time history (type 1) to estimate one from ({} record(s) read)",
                o.line,
                o.name,
                o.kind,
                others.len()
            ),
        }),
        None => Ok(None),
    }
}

/// A UFF58 record that is not an FRF: where it is and what it holds.
struct Other {
    file: PathBuf,
    line: u64,
    name: String,
    function_type: i64,
    /// `function type 2 (auto spectrum)`.
    kind: String,
}

/// The FRFs on `freqs`, each scaled to the common unit, and where each was read.
fn scaled_set(
    named: &[(String, Found)],
    freqs: Vec<f64>,
    scales: &[f64],
) -> (FrfSet, Vec<FrfRecordSource>) {
    let set = FrfSet {
        freqs,
        channels: named.iter().map(|(n, _)| n.clone()).collect(),
        h: (named.iter().zip(scales))
            .map(|((_, f), s)| complex_values(&f.record, *s))
            .collect(),
    };
    let records = named
        .iter()
        .map(|(n, f)| FrfRecordSource {
            channel: n.clone(),
            file: f.file.clone(),
            line: f.record.line,
        })
        .collect();
    (set, records)
}

/// Every FRF record of the UFF files among `paths`, and the others.
fn frf_records(paths: &[PathBuf]) -> Result<(Vec<Found>, Vec<Other>), SignalError> {
    let mut found = Vec::new();
    let mut others = Vec::new();
    for p in paths.iter().filter(|p| uff::looks_like_uff(p)) {
        for record in uff::read_uff(p)?.records {
            if record.function.function_type == FUNCTION_FRF {
                found.push(Found {
                    file: p.clone(),
                    record,
                });
            } else {
                others.push(Other {
                    file: p.clone(),
                    line: record.line,
                    name: record.id4.clone(),
                    function_type: record.function.function_type,
                    kind: record.function_kind(),
                });
            }
        }
    }
    Ok((found, others))
}

/// The FRFs of one reference (named by `input`, or the only one), else of one response (a
/// roving hammer); anything else needs `--input`.
fn choose(
    found: Vec<Found>,
    input: Option<&str>,
) -> Result<(Layout, String, Vec<Found>), SignalError> {
    let refs = distinct(found.iter().map(Found::reference));
    if let Some(want) = input {
        let hit = |f: &Found| {
            let r = &f.record.function;
            let short = uff::point(r.reference_node, r.reference_direction);
            f.reference().eq_ignore_ascii_case(want) || short.eq_ignore_ascii_case(want)
        };
        let chosen: Vec<Found> = found.into_iter().filter(hit).collect();
        let Some(first) = chosen.first() else {
            return Err(SignalError::BadParameter {
                name: "input",
                value: want.to_string(),
                reason: format!(
                    "no FRF in the file has this reference; its references: {}",
                    refs.join(", ")
                ),
            });
        };
        let point = first.reference();
        return Ok((Layout::CommonReference, point, chosen));
    }
    if refs.len() == 1 {
        return Ok((Layout::CommonReference, refs[0].clone(), found));
    }
    let responses = distinct(found.iter().map(Found::response));
    if responses.len() == 1 {
        return Ok((Layout::CommonResponse, responses[0].clone(), found));
    }
    Err(found[0].err(format!(
        "the FRFs have {} references ({}) and {} responses: name the reference with --input",
        refs.len(),
        refs.join(", "),
        responses.len()
    )))
}

/// Each FRF named by the point that roves: the response's channel name (ID line 4) when it is
/// unique, else the response point; the hit point of a roving hammer. Two FRFs of one point are
/// refused: which one to fit is the user's choice.
fn name(chosen: Vec<Found>, layout: Layout) -> Result<Vec<(String, Found)>, SignalError> {
    let ids: Vec<String> = chosen.iter().map(|f| f.record.id4.clone()).collect();
    let unique_id = |id: &String| !id.is_empty() && ids.iter().filter(|i| *i == id).count() == 1;
    let mut named: Vec<(String, Found)> = Vec::new();
    for f in chosen {
        let n = match layout {
            Layout::CommonResponse => f.reference(),
            Layout::CommonReference if unique_id(&f.record.id4) => f.record.id4.clone(),
            Layout::CommonReference => f.response(),
        };
        if let Some((_, g)) = named.iter().find(|(m, _)| *m == n) {
            return Err(f.err(format!(
                "a second FRF of `{n}` (the first at {} line {}): keep one of them",
                g.file.display(),
                g.record.line
            )));
        }
        named.push((n, f));
    }
    Ok(named)
}

/// The frequency lines every FRF shares; each must be complex and on a frequency axis.
fn common_lines(named: &[(String, Found)]) -> Result<Vec<f64>, SignalError> {
    let (first_name, first) = &named[0];
    let lines = &first.record.abscissa;
    for (n, f) in named {
        let r = &f.record;
        if r.abscissa.is_empty() {
            return Err(f.err(format!("FRF `{n}` holds no frequency line")));
        }
        if !matches!(r.ordinate_type, 5 | 6) {
            return Err(f.err(format!(
                "FRF `{n}` holds real values (ordinate type {}): an FRF is complex (type 5 or 6)",
                r.ordinate_type
            )));
        }
        if r.abscissa_axis.data_type == DATA_TYPE_TIME {
            return Err(f.err(format!(
                "FRF `{n}` is on a time axis (record 8 data type 17): expected frequency lines"
            )));
        }
        if !same_lines(&r.abscissa, lines) {
            return Err(f.err(format!(
                "FRF `{n}` is on other frequency lines than `{first_name}` ({}): {} against {}",
                first.record.line,
                span(&r.abscissa),
                span(lines)
            )));
        }
    }
    Ok(lines.clone())
}

/// What the FRFs measure, from record 9's data type (8 displacement, 11 velocity, 12
/// acceleration), and what it was read from; they must agree.
fn common_form(named: &[(String, Found)]) -> Result<(Option<FrfForm>, String), SignalError> {
    let form_of = |f: &Found| match f.record.ordinate_axis.data_type {
        8 => Some(FrfForm::Receptance),
        11 => Some(FrfForm::Mobility),
        12 => Some(FrfForm::Accelerance),
        _ => None,
    };
    let first = form_of(&named[0].1);
    match named.iter().find(|(_, f)| form_of(f) != first) {
        Some((n, f)) => Err(f.err(format!(
            "FRF `{n}` measures {:?} per force, `{}` {:?}: one fit needs one kind",
            form_of(f),
            named[0].0,
            first
        ))),
        None => {
            let t = named[0].1.record.ordinate_axis.data_type;
            let basis = match first {
                Some(_) => format!("record 9 data type {t}"),
                None => format!(
                    "record 9 data type {t} is no displacement (8), velocity (11) or acceleration (12)"
                ),
            };
            Ok((first, basis))
        }
    }
}

/// The unit of the FRFs and each one's factor to it: the file's own when every record states
/// the same, else g/N from each record's acceleration and force units.
fn common_unit(named: &[(String, Found)]) -> Result<(String, Vec<f64>, Vec<String>), SignalError> {
    let label = |f: &Found| {
        let r = &f.record;
        (
            r.ordinate_axis.unit.clone(),
            r.denominator_axis.unit.clone(),
        )
    };
    let first = label(&named[0].1);
    if named.iter().all(|(_, f)| label(f) == first) {
        let unit = match first {
            (o, d) if o.is_empty() && d.is_empty() => "as stored".to_string(),
            (o, d) if d.is_empty() => o,
            (o, d) => format!("{o}/{d}"),
        };
        return Ok((unit, vec![1.0; named.len()], Vec::new()));
    }
    let scales = named
        .iter()
        .map(|(n, f)| {
            let (o, d) = label(f);
            to_g_per_newton(&o, &d).ok_or_else(|| {
                f.err(format!(
                    "FRF `{n}` is in {o}/{d}, others in other units, and {o}/{d} is not an \
                     acceleration per force satqual converts (g, m/s2, mg, in/s2 per N, kN, lbf)"
                ))
            })
        })
        .collect::<Result<Vec<f64>, _>>()?;
    let note = "the FRFs are stored in different units: converted to g/N".to_string();
    Ok(("g/N".into(), scales, vec![note]))
}

fn to_g_per_newton(ordinate: &str, denominator: &str) -> Option<f64> {
    let acc = Unit::parse(ordinate).ok().filter(|u| *u != Unit::AsIs)?;
    let newtons = match denominator.trim().to_ascii_lowercase().as_str() {
        "n" => 1.0,
        "kn" => 1e3,
        "lbf" | "lb" => LBF_IN_N,
        _ => return None,
    };
    Some(acc.to_report_factor() / newtons)
}

fn complex_values(r: &UffRecord, scale: f64) -> Vec<Complex64> {
    r.re.iter()
        .zip(&r.im)
        .map(|(a, b)| Complex64::new(a * scale, b * scale))
        .collect()
}

fn measured_note(named: &[(String, Found)], layout: Layout, common: &str) -> String {
    let files = distinct(named.iter().map(|(_, f)| file_name(&f.file)));
    let shared = match layout {
        Layout::CommonReference => format!("reference {common}"),
        Layout::CommonResponse => format!(
            "response {common}, roving reference: the shapes are read at the reference \
             points (reciprocity)"
        ),
    };
    format!(
        "{} measured FRF(s) from {} ({shared}), fitted as stored: a window the acquisition \
         applied (an exponential one adds damping) is in them, and UFF58 does not record it",
        named.len(),
        files.join(", ")
    )
}
