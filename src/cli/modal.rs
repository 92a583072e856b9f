//! `satqual modal`: natural frequencies, effective masses and, when the scene has static
//! loads, the prestress and buckling factor. Optional export of K, M, K_G, K + K_G and the DOF
//! map.

use super::{Outcome, Printer};
use satqual::Error;
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Highest frequency to extract, Hz (overrides the scene).
    #[arg(long, conflicts_with = "modes")]
    pub fmax: Option<f64>,
    /// Number of modes to extract (overrides the scene).
    #[arg(long)]
    pub modes: Option<usize>,
    /// Print the machine-readable result to stdout.
    #[arg(long)]
    pub json: bool,
    /// Eigen-solver: auto (dense up to a size threshold, sparse above), dense or sparse
    /// (overrides `[modal] solver`).
    #[arg(long, value_enum)]
    pub solver: Option<Solver>,
    /// Write K, M, K_G (Matrix Market, reduced DOFs) and the DOF map (CSV) to this folder.
    #[arg(long)]
    pub export_matrices: Option<PathBuf>,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum Solver {
    Auto,
    Dense,
    Sparse,
}

impl From<Solver> for satqual::spec::SolverChoice {
    fn from(s: Solver) -> Self {
        match s {
            Solver::Auto => satqual::spec::SolverChoice::Auto,
            Solver::Dense => satqual::spec::SolverChoice::Dense,
            Solver::Sparse => satqual::spec::SolverChoice::Sparse,
        }
    }
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    if let Some(f) = args.fmax
        && !(f > 0.0 && f.is_finite())
    {
        return Err(Error::Other(format!(
            "--fmax must be a positive frequency in Hz, got {f}"
        )));
    }
    let scene = satqual::spec::Scene::load(&args.scene)?;
    // A 20 000-DOF stack takes a minute: say what runs (silent off a terminal or piped).
    let progress = super::progress::Progress::start(false, args.json, "modal solve");
    let solved = satqual::pipeline::modal_summary(
        &scene,
        args.fmax,
        args.modes,
        args.solver.map(Into::into),
    );
    progress.finish();
    let (model, sys) = solved?;
    let p = Printer::new(args.json);
    let r = &sys.result;
    for w in &r.warnings {
        eprintln!("warning: {}: {w}", args.scene.display());
    }
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{}: {} DOFs, total mass {:.6} kg, solver {}",
        args.scene.display(),
        r.dofs,
        r.total_mass_kg,
        r.solver
    );
    let _ = writeln!(
        t,
        "{:>5} {:>12} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7}",
        "mode", "freq [Hz]", "x", "y", "z", "rx", "ry", "rz"
    );
    let mut sum = [0.0; 6];
    for m in &r.modes {
        let f = m.effective_mass_fraction.to_array();
        for a in 0..6 {
            sum[a] += f[a];
        }
        let _ = writeln!(
            t,
            "{:>5} {:>12.4} {:>7.4} {:>7.4} {:>7.4} {:>7.4} {:>7.4} {:>7.4}",
            m.index, m.frequency_hz, f[0], f[1], f[2], f[3], f[4], f[5]
        );
    }
    let _ = writeln!(
        t,
        "{:>5} {:>12} {:>7.4} {:>7.4} {:>7.4} {:>7.4} {:>7.4} {:>7.4}   (effective-mass fractions)",
        "sum", "", sum[0], sum[1], sum[2], sum[3], sum[4], sum[5]
    );
    if r.rigid_body_modes > r.free_rigid_motions {
        let _ = writeln!(
            t,
            "zero-frequency modes: {} at 0 Hz ({}), more than the {} rigid-body motions the supports leave free (see the warning)",
            r.rigid_body_modes,
            r.rigid_body_directions.join(", "),
            r.free_rigid_motions
        );
    } else if r.rigid_body_modes > 0 {
        let _ = writeln!(
            t,
            "rigid-body modes: {} at 0 Hz ({}); the model is not supported against them",
            r.rigid_body_modes,
            r.rigid_body_directions.join(", ")
        );
    }
    if let Some(ps) = &r.prestress {
        match ps.buckling_factor {
            Some(l) => {
                let _ = writeln!(
                    t,
                    "prestress: buckling factor {l:.6} (margin {:+.1}%)",
                    (l - 1.0) * 100.0
                );
                if let Some(on) = &ps.buckling_model {
                    let _ = writeln!(t, "  taken on {on}");
                }
            }
            None => {
                let _ = writeln!(
                    t,
                    "prestress: no buckling (the prestress stiffens the structure everywhere)"
                );
            }
        }
    }
    p.human(t.trim_end());
    p.json(r)?;
    if let Some(dir) = &args.export_matrices {
        satqual::pipeline::workflows::matrices::export(dir, &model, &sys)?;
        p.human(&format!("matrices written to {}", dir.display()));
    }
    Ok(Outcome::Pass)
}
