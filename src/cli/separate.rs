//! `satqual separate SCENE [--monte-carlo N --seed S] [--out DIR] [--json]`: the in-orbit
//! release of a `[stack]` + `[separation]` scene, and optionally a seeded Monte Carlo.

use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::Silent;
use satqual::pipeline::plan::MonteCarloPlan;
use satqual::pipeline::workflows::{self, separate::SeparateRequest, separate::SeparateRun};
use satqual::report::write_atomic;
use satqual::separation::{self, SeparationResult};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML) with [stack] and [separation].
    pub scene: PathBuf,
    /// Number of dispersed Monte Carlo runs (dispersions from [separation.dispersion]).
    #[arg(long, requires = "seed")]
    pub monte_carlo: Option<usize>,
    /// Seed of the Monte Carlo streams.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Write CSV histories of the nominal run to this folder.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the machine-readable result to stdout.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct Output<'a> {
    scene: String,
    #[serde(flatten)]
    result: &'a SeparationResult,
    #[serde(skip_serializing_if = "Option::is_none")]
    monte_carlo: Option<separation::MonteCarloResult>,
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let p = Printer::new(args.json);
    let scene = satqual::spec::Scene::load(&args.scene)?;
    let req = SeparateRequest {
        record_history: args.out.is_some(),
        monte_carlo: args.monte_carlo.map(|runs| MonteCarloPlan {
            runs,
            seed: args.seed.unwrap_or(0),
        }),
    };
    let SeparateRun {
        result,
        monte_carlo: mc,
        ..
    } = workflows::separate::run(&scene, &req, &Silent)?;
    if let (Some(dir), Some(h)) = (&args.out, &result.history) {
        write_histories(dir, h)?;
    }
    let mut s = String::new();
    let _ = writeln!(
        s,
        "separation of {} ({} satellites)",
        scene.name(),
        result.satellites.len()
    );
    let _ = writeln!(
        s,
        "  sat  release_s  max_speed  final_speed  final_rate  exit_time_s  contacts"
    );
    for r in &result.satellites {
        let _ = writeln!(
            s,
            "  {:>3}  {:>9}  {:>9.4}  {:>11.4}  {:>10.3}  {:>11}  {:>8}",
            r.index,
            r.release_time_s
                .map_or("never".into(), |t| format!("{t:.3}")),
            r.max_speed_m_s,
            r.final_speed_m_s,
            r.final_rate_deg_s,
            r.exit_time_s
                .map_or("on bars".into(), |t| format!("{t:.3}")),
            r.contacts
        );
    }
    let _ = writeln!(s, "  speeds in m/s, rates in deg/s at bar exit");
    let _ = writeln!(
        s,
        "  energy residual {:.3e} of the spring energy (max over the run {:.3e}); {} steps, {} RHS evaluations",
        result.energy.relative_residual,
        result.energy.max_relative_residual,
        result.stats.steps,
        result.stats.rhs_evals
    );
    if let Some(c) = result.min_clearance_m {
        let _ = writeln!(s, "  minimum inter-satellite clearance {c:.4} m");
    }
    if let Some(mc) = &mc {
        let _ = writeln!(
            s,
            "  Monte Carlo {} runs (seed {}): final speed P1 {:.4} P50 {:.4} P99 {:.4} P99.73 {:.4} m/s; tip-off rate P99.73 {:.3} deg/s; min clearance P0.27 {:.4} m",
            mc.runs,
            mc.seed,
            mc.final_speed_m_s.p1,
            mc.final_speed_m_s.p50,
            mc.final_speed_m_s.p99,
            mc.final_speed_m_s.p99_73,
            mc.tip_off_rate_deg_s.p99_73,
            mc.min_clearance_m.p0_27
        );
    }
    p.human(s.trim_end());
    p.json(&Output {
        scene: scene.path.display().to_string(),
        result: &result,
        monte_carlo: mc,
    })?;
    Ok(Outcome::Pass)
}

fn write_histories(dir: &Path, h: &separation::History) -> Result<(), Error> {
    for (i, rows) in h.satellites.iter().enumerate() {
        let mut s = String::from(
            "time_s,x_m,y_m,z_m,vx_m_s,vy_m_s,vz_m_s,speed_m_s,wx_deg_s,wy_deg_s,wz_deg_s,rate_deg_s\n",
        );
        for (t, r) in h.times_s.iter().zip(rows) {
            let _ = write!(s, "{t}");
            for v in r {
                let _ = write!(s, ",{v}");
            }
            s.push('\n');
        }
        write_atomic(&dir.join(format!("satellite-{}.csv", i + 1)), s.as_bytes())?;
    }
    let mut s = String::from(
        "time_s,spring_work_j,kinetic_j,bar_j,contact_elastic_j,losses_j,residual_j\n",
    );
    for (t, r) in h.times_s.iter().zip(&h.energy) {
        let _ = write!(s, "{t}");
        for v in r {
            let _ = write!(s, ",{v}");
        }
        s.push('\n');
    }
    write_atomic(&dir.join("energy.csv"), s.as_bytes())
}
