//! The qualification report an engineer signs: `report.html` (self-contained, inline SVG, no
//! network, printable), `report.md` with the plots as SVG files beside it, `results.json`
//! (every number, no timestamps) and `curves/*.csv` (the data behind every plot).
//! Input: a `results::Qualification`. The whole folder is built under a temporary name and
//! swapped in only when complete, so an existing report is never left half-replaced.

use super::plot::{Marker, Scale, Series, lines_markers_svg, lines_svg};
use crate::error::Error;
use crate::results::Qualification;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A figure: file stem, caption, SVG text.
struct Figure {
    stem: String,
    caption: String,
    svg: String,
}

/// Files of the report, relative path -> content.
type Files = Vec<(String, Vec<u8>)>;

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

fn fmt(v: f64) -> String {
    if !v.is_finite() {
        return "–".into();
    }
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e5).contains(&a) {
        format!("{v:.4e}")
    } else {
        format!("{v:.4}")
    }
}

fn csv(header: &str, rows: impl Iterator<Item = Vec<f64>>) -> Vec<u8> {
    let mut s = String::from(header);
    s.push('\n');
    for r in rows {
        let line: Vec<String> = r.iter().map(|v| format!("{v:.9e}")).collect();
        s.push_str(&line.join(","));
        s.push('\n');
    }
    s.into_bytes()
}

/// Builds the figures and their CSV curves.
fn figures(q: &Qualification, files: &mut Files) -> Result<Vec<Figure>, Error> {
    let mut figs = Vec::new();
    if let Some(m) = &q.modal {
        // Effective-mass fractions per mode: where the mass participates.
        let modes: Vec<&crate::modal::Mode> = m
            .result
            .modes
            .iter()
            .filter(|x| x.frequency_hz > 1e-3)
            .collect();
        let mut series_pts: Vec<Vec<(f64, f64)>> = vec![Vec::new(); 3];
        for md in &modes {
            let f = md.effective_mass_fraction.to_array();
            for d in 0..3 {
                series_pts[d].push((md.frequency_hz, f[d]));
            }
        }
        files.push((
            "curves/effective_mass.csv".into(),
            csv(
                "mode,frequency_hz,fraction_x,fraction_y,fraction_z,fraction_rx,fraction_ry,fraction_rz",
                modes.iter().map(|md| {
                    let f = md.effective_mass_fraction.to_array();
                    vec![md.index as f64, md.frequency_hz, f[0], f[1], f[2], f[3], f[4], f[5]]
                }),
            ),
        ));
        let series: Vec<Series> = ["x", "y", "z"]
            .iter()
            .zip(&series_pts)
            .map(|(l, p)| Series {
                label: format!("effective mass fraction {l}"),
                points: p,
            })
            .collect();
        figs.push(Figure {
            stem: "effective_mass".into(),
            caption: "Effective-mass fraction of each mode against its frequency".into(),
            svg: lines_svg(
                "Effective mass by mode",
                "frequency [Hz]",
                "fraction of total mass",
                &series,
                Scale::Log,
                Scale::Linear,
            )?,
        });
    }
    if let Some(resp) = &q.response {
        let sine_peaks = |a: &crate::response::sine::SineAxis| -> Vec<Marker> {
            a.peaks
                .iter()
                .map(|p| Marker {
                    x: p.frequency_hz,
                    y: p.acceleration_g,
                    label: format!(
                        "{} {:.2} g @ {:.1} Hz",
                        p.name, p.acceleration_g, p.frequency_hz
                    ),
                })
                .collect()
        };
        let random_peaks = |a: &crate::response::random::RandomAxis| -> Vec<Marker> {
            a.responses
                .iter()
                .map(|r| Marker {
                    x: r.peak_psd_hz,
                    y: r.peak_psd_g2_hz,
                    label: format!("{} {:.2} Grms", r.name, r.grms),
                })
                .collect()
        };
        for (kind, axes_curves) in [
            (
                "sine",
                resp.sine
                    .iter()
                    .map(|a| (&a.axis, &a.curves, sine_peaks(a)))
                    .collect::<Vec<_>>(),
            ),
            (
                "random",
                resp.random
                    .iter()
                    .map(|a| (&a.axis, &a.curves, random_peaks(a)))
                    .collect::<Vec<_>>(),
            ),
        ] {
            for (axis, c, mut markers) in axes_curves {
                // Annotate the highest peak at up to three distinct frequencies: labels of
                // points that peak together would overprint.
                markers.sort_by(|a, b| b.y.total_cmp(&a.y));
                let mut kept: Vec<Marker> = Vec::new();
                for m in markers.drain(..) {
                    if kept.len() < 3 && kept.iter().all(|k| (k.x / m.x).ln().abs() > 0.1) {
                        kept.push(m);
                    }
                }
                let markers = kept;
                let input_name = if kind == "sine" {
                    "input_g"
                } else {
                    "input_g2_hz"
                };
                files.push((
                    format!("curves/{kind}_{axis}_points.csv"),
                    c.to_csv(input_name).into_bytes(),
                ));
                files.push((
                    format!("curves/{kind}_{axis}_interfaces.csv"),
                    c.csv_of(input_name, &c.interfaces).into_bytes(),
                ));
                files.push((
                    format!("curves/{kind}_{axis}_bars.csv"),
                    c.csv_of(input_name, &c.bars).into_bytes(),
                ));
                let input: Vec<(f64, f64)> = c
                    .frequency_hz
                    .iter()
                    .copied()
                    .zip(c.input.iter().copied())
                    .collect();
                let pts: Vec<Vec<(f64, f64)>> = c
                    .series
                    .iter()
                    .map(|(_, v)| {
                        c.frequency_hz
                            .iter()
                            .copied()
                            .zip(v.iter().copied())
                            .collect()
                    })
                    .collect();
                let mut series = vec![Series {
                    label: "input".into(),
                    points: &input,
                }];
                for ((name, _), p) in c.series.iter().zip(&pts) {
                    series.push(Series {
                        label: name.clone(),
                        points: p,
                    });
                }
                let (title, ylab, cap) = if kind == "sine" {
                    (
                        format!("Sine response, {axis} axis"),
                        "acceleration [g]",
                        format!(
                            "Sine sweep along {axis}: absolute acceleration of the response points against the input level"
                        ),
                    )
                } else {
                    (
                        format!("Random response PSD, {axis} axis"),
                        "PSD [g²/Hz]",
                        format!(
                            "Random vibration along {axis}: response PSDs with the input profile"
                        ),
                    )
                };
                figs.push(Figure {
                    stem: format!("{kind}_{axis}"),
                    caption: cap,
                    svg: lines_markers_svg(
                        &title,
                        "frequency [Hz]",
                        ylab,
                        &series,
                        &markers,
                        Scale::Log,
                        Scale::Log,
                    )?,
                });
            }
        }
    }
    if let Some(td) = &q.test_data {
        for (k, log) in td.logs.iter().enumerate() {
            let stem = format!("test_{}", k + 1);
            for (label, pts) in &log.curves {
                let safe: String = label
                    .chars()
                    .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
                    .collect();
                files.push((
                    format!("curves/{stem}_{safe}.csv"),
                    csv("frequency_hz,value", pts.iter().map(|p| vec![p.0, p.1])),
                ));
            }
            let is_frf = log.curves.iter().any(|(l, _)| l == "coherence");
            if is_frf {
                let h: Vec<Series> = log
                    .curves
                    .iter()
                    .filter(|(l, _)| l != "coherence")
                    .map(|(l, p)| Series {
                        label: l.clone(),
                        points: p,
                    })
                    .collect();
                figs.push(Figure {
                    stem: format!("{stem}_frf"),
                    caption: format!("{}: |H1| with its resonances ({})", log.name, log.file),
                    svg: lines_svg(
                        &format!("{}: FRF", log.name),
                        "frequency [Hz]",
                        "|H1|",
                        &h,
                        Scale::Log,
                        Scale::Log,
                    )?,
                });
                let c: Vec<Series> = log
                    .curves
                    .iter()
                    .filter(|(l, _)| l == "coherence")
                    .map(|(l, p)| Series {
                        label: l.clone(),
                        points: p,
                    })
                    .collect();
                figs.push(Figure {
                    stem: format!("{stem}_coherence"),
                    caption: format!("{}: coherence", log.name),
                    svg: lines_svg(
                        &format!("{}: coherence", log.name),
                        "frequency [Hz]",
                        "γ²",
                        &c,
                        Scale::Log,
                        Scale::Linear,
                    )?,
                });
            } else {
                let ser: Vec<Series> = log
                    .curves
                    .iter()
                    .map(|(l, p)| Series {
                        label: l.clone(),
                        points: p,
                    })
                    .collect();
                figs.push(Figure {
                    stem: format!("{stem}_psd"),
                    caption: format!("{}: measured PSD against the reference profile and its tolerance bands ({})", log.name, log.file),
                    svg: lines_svg(&format!("{}: PSD", log.name), "frequency [Hz]", "PSD [g²/Hz]", &ser, Scale::Log, Scale::Log)?,
                });
            }
        }
    }
    if let Some(mc) = q.separation.as_ref().and_then(|s| s.monte_carlo.as_ref()) {
        for (stem, label, samples) in [
            (
                "mc_exit_speed",
                "exit speed [m/s]",
                &mc.samples_final_speed_m_s,
            ),
            (
                "mc_tip_off_rate",
                "tip-off rate [deg/s]",
                &mc.samples_tip_off_rate_deg_s,
            ),
            (
                "mc_min_clearance",
                "minimum inter-satellite clearance [m]",
                &mc.samples_min_clearance_m,
            ),
        ] {
            files.push((
                format!("curves/{stem}.csv"),
                csv("sample", samples.iter().map(|v| vec![*v])),
            ));
            let steps = histogram_steps(samples, 20);
            figs.push(Figure {
                stem: stem.into(),
                caption: format!(
                    "Monte Carlo ({} runs, seed {}): histogram of the {label}",
                    mc.runs, mc.seed
                ),
                svg: lines_svg(
                    &format!("Monte Carlo: {label}"),
                    label,
                    "count",
                    &[Series {
                        label: format!("{} samples", samples.len()),
                        points: &steps,
                    }],
                    Scale::Linear,
                    Scale::Linear,
                )?,
            });
        }
    }
    if let Some(sep) = &q.separation
        && let Some(h) = &sep.result.history
    {
        let n = h.satellites.len();
        let mut speed: Vec<Vec<(f64, f64)>> = vec![Vec::new(); n];
        let mut rate: Vec<Vec<(f64, f64)>> = vec![Vec::new(); n];
        let mut z: Vec<Vec<(f64, f64)>> = vec![Vec::new(); n];
        for (k, t) in h.times_s.iter().enumerate() {
            for i in 0..n {
                if let Some(s) = h.satellites[i].get(k) {
                    speed[i].push((*t, s[6]));
                    rate[i].push((*t, s[10]));
                    z[i].push((*t, s[2]));
                }
            }
        }
        files.push((
            "curves/separation_history.csv".into(),
            csv(
                &{
                    let mut hdr = String::from("time_s");
                    for i in 1..=n {
                        let _ = write!(hdr, ",sat{i}_z_m,sat{i}_speed_m_s,sat{i}_rate_deg_s");
                    }
                    hdr
                },
                h.times_s.iter().enumerate().map(|(k, t)| {
                    let mut row = vec![*t];
                    for i in 0..n {
                        let s = h.satellites[i].get(k).copied().unwrap_or([f64::NAN; 11]);
                        row.extend([s[2], s[6], s[10]]);
                    }
                    row
                }),
            ),
        ));
        fn mk(pts: &[Vec<(f64, f64)>]) -> Vec<Series<'_>> {
            pts.iter()
                .enumerate()
                .map(|(i, p)| Series {
                    label: format!("satellite {}", i + 1),
                    points: p,
                })
                .collect()
        }
        figs.push(Figure {
            stem: "separation_position".into(),
            caption: "Axial position of each satellite during the release (bar root at 0)".into(),
            svg: lines_svg(
                "Separation: trajectories",
                "time [s]",
                "z [m]",
                &mk(&z),
                Scale::Linear,
                Scale::Linear,
            )?,
        });
        figs.push(Figure {
            stem: "separation_speed".into(),
            caption: "Speed of each satellite; dips are contacts with the guide bars".into(),
            svg: lines_svg(
                "Separation: speed",
                "time [s]",
                "speed [m/s]",
                &mk(&speed),
                Scale::Linear,
                Scale::Linear,
            )?,
        });
        figs.push(Figure {
            stem: "separation_rate".into(),
            caption: "Angular rate of each satellite".into(),
            svg: lines_svg(
                "Separation: angular rate",
                "time [s]",
                "rate [deg/s]",
                &mk(&rate),
                Scale::Linear,
                Scale::Linear,
            )?,
        });
    }
    Ok(figs)
}

/// A histogram as a step outline: `bins` equal bins between the sample extremes.
fn histogram_steps(samples: &[f64], bins: usize) -> Vec<(f64, f64)> {
    let finite: Vec<f64> = samples.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.is_empty() {
        return Vec::new();
    }
    let lo = finite.iter().copied().fold(f64::INFINITY, f64::min);
    let mut hi = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if hi <= lo {
        hi = lo + 1e-12_f64.max(lo.abs() * 1e-9);
    }
    let w = (hi - lo) / bins as f64;
    let mut counts = vec![0usize; bins];
    for v in finite {
        let k = (((v - lo) / w) as usize).min(bins - 1);
        counts[k] += 1;
    }
    let mut pts = vec![(lo, 0.0)];
    for (k, c) in counts.iter().enumerate() {
        let (a, b) = (lo + k as f64 * w, lo + (k + 1) as f64 * w);
        pts.push((a, *c as f64));
        pts.push((b, *c as f64));
    }
    pts.push((hi, 0.0));
    pts
}

fn gate_rows(q: &Qualification) -> Vec<[String; 6]> {
    q.gates
        .iter()
        .map(|g| {
            [
                g.name.clone(),
                fmt(g.value),
                fmt(g.limit),
                format!("{:+.1}%", g.margin * 100.0),
                if g.pass { "pass".into() } else { "FAIL".into() },
                g.source.clone(),
            ]
        })
        .collect()
}

/// Markdown version; plots referenced as SVG files beside it.
fn markdown(q: &Qualification, figs: &[Figure]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Qualification report: {}\n",
        q.title.as_deref().unwrap_or(&q.scene)
    );
    let failed: Vec<&str> = q
        .gates
        .iter()
        .filter(|g| !g.pass)
        .map(|g| g.name.as_str())
        .collect();
    let _ = writeln!(
        s,
        "**Verdict: {}** — {} gates, {} failed.\n",
        if q.pass { "PASS" } else { "FAIL" },
        q.gates.len(),
        failed.len()
    );
    for f in &failed {
        let _ = writeln!(s, "- failed: {f}");
    }
    let _ = writeln!(
        s,
        "\n## Gates\n\n| gate | value | limit | margin | verdict | source |\n|---|---:|---:|---:|---|---|"
    );
    for r in gate_rows(q) {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            r[0], r[1], r[2], r[3], r[4], r[5]
        );
    }
    let _ = writeln!(s, "\n## Analyses\n\nRan: {}.\n", q.ran.join(", "));
    for sk in &q.skipped {
        let _ = writeln!(s, "- skipped **{}**: {}", sk.analysis, sk.reason);
    }
    if let Some(m) = &q.modal {
        let r = &m.result;
        let _ = writeln!(
            s,
            "\n## Model and modes\n\nTotal mass {:.3} kg, centre of mass ({:.4}, {:.4}, {:.4}) m, {} DOFs, solver {}.\n",
            r.total_mass_kg,
            r.center_of_mass_m[0],
            r.center_of_mass_m[1],
            r.center_of_mass_m[2],
            r.dofs,
            r.solver
        );
        if let Some(ps) = &r.prestress {
            let _ = writeln!(
                s,
                "Buckling factor under the preload: {}.\n",
                ps.buckling_factor.map(fmt).unwrap_or("none".into())
            );
        }
        let _ = writeln!(
            s,
            "| mode | f [Hz] | x | y | z | rx | ry | rz |\n|---:|---:|---:|---:|---:|---:|---:|---:|"
        );
        for md in r.modes.iter().take(30) {
            let f = md.effective_mass_fraction.to_array();
            let _ = writeln!(
                s,
                "| {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} |",
                md.index, md.frequency_hz, f[0], f[1], f[2], f[3], f[4], f[5]
            );
        }
        if r.modes.len() > 30 {
            let _ = writeln!(s, "\n({} more modes in results.json)", r.modes.len() - 30);
        }
    }
    if let Some(resp) = &q.response {
        if !resp.sine.is_empty() {
            let _ = writeln!(
                s,
                "\n## Sine response\n\n| axis | point | peak [g] | at [Hz] |\n|---|---|---:|---:|"
            );
            for a in &resp.sine {
                for p in &a.peaks {
                    let _ = writeln!(
                        s,
                        "| {} | {} | {:.3} | {:.2} |",
                        a.axis, p.name, p.acceleration_g, p.frequency_hz
                    );
                }
            }
        }
        // Joint loads: the envelope over the axes, per joint (sine peak, random 3σ).
        type Load = (String, f64, f64, f64, f64);
        let mut loads: Vec<Load> = Vec::new();
        fn entry(loads: &mut Vec<Load>, name: &str) -> usize {
            match loads.iter().position(|l| l.0 == name) {
                Some(i) => i,
                None => {
                    loads.push((name.to_string(), 0.0, 0.0, 0.0, 0.0));
                    loads.len() - 1
                }
            }
        }
        for a in &resp.sine {
            for i in &a.interfaces {
                let k = entry(&mut loads, &i.name);
                loads[k].1 = loads[k].1.max(i.max_tension_n);
                loads[k].2 = loads[k].2.max(i.max_shear_n);
            }
        }
        for a in &resp.random {
            for i in &a.interfaces {
                let k = entry(&mut loads, &i.name);
                loads[k].3 = loads[k].3.max(i.tension_3sigma_n);
                loads[k].4 = loads[k].4.max(i.shear_3sigma_n);
            }
        }
        if !loads.is_empty() {
            let _ = writeln!(
                s,
                "\n## Joint loads (envelope over the axes)\n\n| joint | sine axial [N] | sine shear [N] | random 3σ axial [N] | random 3σ shear [N] |\n|---|---:|---:|---:|---:|"
            );
            for l in &loads {
                let _ = writeln!(
                    s,
                    "| {} | {:.0} | {:.0} | {:.0} | {:.0} |",
                    l.0, l.1, l.2, l.3, l.4
                );
            }
        }
        if !resp.random.is_empty() {
            let _ = writeln!(
                s,
                "\n## Random response\n\n| axis | input Grms | point | Grms | 3σ [g] | peak PSD [g²/Hz] | at [Hz] |\n|---|---:|---|---:|---:|---:|---:|"
            );
            for a in &resp.random {
                for r in &a.responses {
                    let _ = writeln!(
                        s,
                        "| {} | {:.2} | {} | {:.3} | {:.3} | {:.4} | {:.1} |",
                        a.axis,
                        a.input_grms,
                        r.name,
                        r.grms,
                        r.three_sigma_g,
                        r.peak_psd_g2_hz,
                        r.peak_psd_hz
                    );
                }
            }
        }
    }
    if !q.assumptions.is_empty() {
        let _ = writeln!(s, "\n## Assumptions of the scene\n");
        for a in &q.assumptions {
            let _ = writeln!(s, "- {a}");
        }
    }
    if let Some(sep) = &q.separation {
        let _ = writeln!(
            s,
            "\n## Separation\n\n| satellite | max speed [m/s] | exit speed [m/s] | exit rate [deg/s] | peak rate [deg/s] | exit time [s] | contacts |\n|---:|---:|---:|---:|---:|---:|---:|"
        );
        for st in &sep.result.satellites {
            let _ = writeln!(
                s,
                "| {} | {:.4} | {:.4} | {:.3} | {:.3} | {} | {} |",
                st.index,
                st.max_speed_m_s,
                st.final_speed_m_s,
                st.final_rate_deg_s,
                st.peak_rate_deg_s,
                st.exit_time_s
                    .map(|t| format!("{t:.3}"))
                    .unwrap_or("—".into()),
                st.contacts
            );
        }
        let _ = writeln!(
            s,
            "\nEnergy-audit residual: {:.3e} of the spring work.",
            sep.result.energy.relative_residual
        );
        if let Some(mc) = &sep.monte_carlo {
            let _ = writeln!(
                s,
                "\nMonte Carlo, {} runs, seed {}:\n\n| quantity | P0.27 | P1 | P50 | P99 | P99.73 |\n|---|---:|---:|---:|---:|---:|",
                mc.runs, mc.seed
            );
            for (name, p) in [
                ("exit speed [m/s]", &mc.final_speed_m_s),
                ("tip-off rate [deg/s]", &mc.tip_off_rate_deg_s),
                ("min. clearance [m]", &mc.min_clearance_m),
            ] {
                let _ = writeln!(
                    s,
                    "| {name} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} |",
                    p.p0_27, p.p1, p.p50, p.p99, p.p99_73
                );
            }
        }
    }
    if let Some(td) = &q.test_data {
        let _ = writeln!(s, "\n## Test data\n");
        for log in &td.logs {
            let _ = writeln!(
                s,
                "- **{}** (`{}`, {:?}): {}",
                log.name,
                log.file,
                log.kind,
                log.channels
                    .iter()
                    .map(|(n, g)| format!("{n} {g:.4} Grms"))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
            if let Some(t) = &log.tolerance {
                let _ = writeln!(
                    s,
                    "  - tolerance: {:.2}% of lines beyond ±{} dB (alarm), {:.2}% beyond ±{} dB (abort); worst {:+.2} dB at {:.0} Hz; Grms {:.4} against {:.4} ({:+.2}%)",
                    t.fraction_outside_alarm * 100.0,
                    t.spec.alarm_db,
                    t.fraction_outside_abort * 100.0,
                    t.spec.abort_db,
                    t.worst_excursion_db,
                    t.worst_frequency_hz,
                    t.measured_grms,
                    t.reference_grms,
                    t.grms_error_pct
                );
            }
            if !log.resonances.is_empty() {
                let r: Vec<String> = log
                    .resonances
                    .iter()
                    .map(|r| format!("{:.1} Hz", r.frequency_hz))
                    .collect();
                let _ = writeln!(s, "  - resonances: {}", r.join(", "));
            }
        }
        if let Some(sig) = &td.signature {
            let _ = writeln!(
                s,
                "\n| mode | before [Hz] | after [Hz] | shift [%] | amplitude change [%] | verdict |\n|---:|---:|---:|---:|---:|---|"
            );
            for m in &sig.modes {
                let _ = writeln!(
                    s,
                    "| {} | {:.2} | {} | {} | {} | {} |",
                    m.mode,
                    m.before_hz,
                    m.after_hz.map(|v| format!("{v:.2}")).unwrap_or("—".into()),
                    m.shift_pct
                        .map(|v| format!("{v:+.3}"))
                        .unwrap_or("—".into()),
                    m.amplitude_change_pct
                        .map(|v| format!("{v:+.2}"))
                        .unwrap_or("—".into()),
                    if m.pass {
                        "pass".to_string()
                    } else {
                        format!("FAIL: {}", m.reason)
                    }
                );
            }
        }
    }
    if !q.paper_comparison.is_empty() {
        let _ = writeln!(
            s,
            "\n## Comparison with the paper\n\n| quantity | paper | satqual | source |\n|---|---|---|---|"
        );
        for c in &q.paper_comparison {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} |",
                c.quantity, c.paper, c.satqual, c.source
            );
        }
    }
    if !figs.is_empty() {
        let _ = writeln!(s, "\n## Plots\n");
        for f in figs {
            let _ = writeln!(
                s,
                "![{}](plots/{}.svg)\n\n*{}*\n",
                f.caption, f.stem, f.caption
            );
        }
    }
    let p = &q.provenance;
    let _ = writeln!(
        s,
        "\n## Provenance\n\n- scene: `{}` (FNV-1a {})\n- satqual {}\n- modal solver: {}\n- separation tolerance: {}",
        p.scene_file,
        p.scene_hash,
        p.satqual_version,
        p.modal_solver.as_deref().unwrap_or("—"),
        p.separation_tolerance
            .map(|t| format!("{t:e}"))
            .unwrap_or("—".into())
    );
    s
}

/// Self-contained HTML: the Markdown content's structure with inline SVG figures.
fn html(q: &Qualification, figs: &[Figure]) -> String {
    let mut s = String::new();
    let title = esc(q.title.as_deref().unwrap_or(&q.scene));
    let _ = write!(
        s,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Qualification: {title}</title>\n<style>\nbody{{font-family:sans-serif;max-width:1000px;margin:2em auto;color:#222}}\ntable{{border-collapse:collapse;margin:1em 0;font-size:90%}}\ntd,th{{border:1px solid #bbb;padding:3px 8px}}\nth{{background:#eee}}\ntr.fail td{{color:#b00;font-weight:bold;background:#fee}}\n.verdict{{font-size:150%;padding:.5em;border:2px solid}}\n.pass{{color:#060;border-color:#060}}\n.failv{{color:#b00;border-color:#b00}}\nfigure{{margin:1em 0;page-break-inside:avoid}} figure svg{{max-width:100%;height:auto}}\n@media print{{body{{max-width:none}}}}\n</style></head><body>\n<h1>Qualification report: {title}</h1>\n"
    );
    let nfail = q.gates.iter().filter(|g| !g.pass).count();
    let _ = writeln!(
        s,
        "<p class=\"verdict {}\">Verdict: <b>{}</b> — {} gates, {} failed.</p>",
        if q.pass { "pass" } else { "failv" },
        if q.pass { "PASS" } else { "FAIL" },
        q.gates.len(),
        nfail
    );
    let _ = writeln!(
        s,
        "<h2>Gates</h2>\n<table><tr><th>gate</th><th>value</th><th>limit</th><th>margin</th><th>verdict</th><th>source</th></tr>"
    );
    for (g, r) in q.gates.iter().zip(gate_rows(q)) {
        let _ = writeln!(
            s,
            "<tr{}><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            if g.pass { "" } else { " class=\"fail\"" },
            esc(&r[0]),
            r[1],
            r[2],
            r[3],
            r[4],
            esc(&r[5])
        );
    }
    let _ = writeln!(s, "</table>");
    // Re-use the Markdown body for the remaining sections, rendered as simple HTML.
    let md = markdown(q, &[]);
    let body = md
        .split("\n## Analyses")
        .nth(1)
        .map(|b| format!("## Analyses{b}"))
        .unwrap_or_default();
    s.push_str(&md_to_html(&body));
    if !figs.is_empty() {
        let _ = writeln!(s, "<h2>Plots</h2>");
        for f in figs {
            let svg = f.svg.trim_start_matches(|c| c != '<');
            let svg = svg
                .strip_prefix("<?xml version=\"1.0\" encoding=\"UTF-8\"?>")
                .unwrap_or(svg);
            let _ = writeln!(
                s,
                "<figure>{svg}<figcaption>{}</figcaption></figure>",
                esc(&f.caption)
            );
        }
    }
    s.push_str("</body></html>\n");
    s
}

/// Just enough Markdown for the report's own output: headings, tables, lists, paragraphs.
fn md_to_html(md: &str) -> String {
    let mut out = String::new();
    let mut in_table = false;
    let mut in_list = false;
    let inline = |t: &str| -> String {
        let mut r = String::new();
        let mut bold = false;
        let mut code = false;
        let e = esc(t);
        let mut chars = e.chars().peekable();
        while let Some(c) = chars.next() {
            if c == '*' && chars.peek() == Some(&'*') {
                chars.next();
                r.push_str(if bold { "</b>" } else { "<b>" });
                bold = !bold;
            } else if c == '`' {
                r.push_str(if code { "</code>" } else { "<code>" });
                code = !code;
            } else {
                r.push(c);
            }
        }
        r
    };
    for line in md.lines() {
        let t = line.trim();
        if t.starts_with('|') {
            if !in_table {
                out.push_str("<table>\n");
                in_table = true;
            }
            if t.starts_with("|---") || t.starts_with("|:") {
                continue;
            }
            let cells: Vec<&str> = t.trim_matches('|').split('|').map(|c| c.trim()).collect();
            out.push_str("<tr>");
            for c in cells {
                let _ = write!(out, "<td>{}</td>", inline(c));
            }
            out.push_str("</tr>\n");
            continue;
        } else if in_table {
            out.push_str("</table>\n");
            in_table = false;
        }
        if let Some(item) = t.strip_prefix("- ") {
            if !in_list {
                out.push_str("<ul>\n");
                in_list = true;
            }
            let _ = writeln!(out, "<li>{}</li>", inline(item));
            continue;
        } else if in_list {
            out.push_str("</ul>\n");
            in_list = false;
        }
        if let Some(h) = t.strip_prefix("## ") {
            let _ = writeln!(out, "<h2>{}</h2>", inline(h));
        } else if !t.is_empty() {
            let _ = writeln!(out, "<p>{}</p>", inline(t));
        }
    }
    if in_table {
        out.push_str("</table>\n");
    }
    if in_list {
        out.push_str("</ul>\n");
    }
    out
}

/// Renders every file of the report in memory.
pub fn render(q: &Qualification) -> Result<Files, Error> {
    let mut files: Files = Vec::new();
    let figs = figures(q, &mut files)?;
    let json =
        serde_json::to_string_pretty(q).map_err(|e| Error::Other(format!("results.json: {e}")))?;
    files.push(("results.json".into(), (json + "\n").into_bytes()));
    files.push(("report.md".into(), markdown(q, &figs).into_bytes()));
    files.push(("report.html".into(), html(q, &figs).into_bytes()));
    for f in &figs {
        files.push((format!("plots/{}.svg", f.stem), f.svg.clone().into_bytes()));
    }
    Ok(files)
}

/// Writes the report folder: everything into a temporary sibling folder first, then swapped
/// in. An existing report is replaced only once the new one is complete; on failure nothing
/// half-written is left behind.
pub fn write(dir: &Path, q: &Qualification) -> Result<Vec<PathBuf>, Error> {
    let files = render(q)?;
    let parent = dir
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
    let name = dir
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "report".into());
    let tmp = parent.join(format!(".{name}.tmp-{}", std::process::id()));
    let cleanup = |p: &Path| {
        let _ = std::fs::remove_dir_all(p);
    };
    cleanup(&tmp);
    let mut written = Vec::new();
    for (rel, bytes) in &files {
        let p = tmp.join(rel);
        if let Err(e) = super::write_atomic(&p, bytes) {
            cleanup(&tmp);
            return Err(e);
        }
        written.push(dir.join(rel));
    }
    let old = parent.join(format!(".{name}.old-{}", std::process::id()));
    if dir.exists() {
        std::fs::rename(dir, &old).map_err(|e| {
            cleanup(&tmp);
            Error::io(dir, e)
        })?;
    }
    if let Err(e) = std::fs::rename(&tmp, dir) {
        // Put the previous report back.
        let _ = std::fs::rename(&old, dir);
        cleanup(&tmp);
        return Err(Error::io(dir, e));
    }
    cleanup(&old);
    Ok(written)
}
