//! `satqual expand`: writes a `[stack]` scene out as the generic model (TOML), so an engineer
//! can inspect or hand-edit every node, beam and joint the stack expands into.

use super::{Outcome, Printer};
use satqual::Error;
use std::io::Write;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
#[command(
    after_help = "With --json, stdout holds one JSON document instead of the TOML: {\"scene\": <scene file>, \"satqual_version\": <version>, \"model\": <the expanded model as data, the same keys as the TOML>}."
)]
pub struct Args {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Print the expanded model as a JSON document (scene, satqual_version, model) instead of
    /// the TOML.
    #[arg(long)]
    pub json: bool,
}

#[derive(serde::Serialize)]
struct Output<'a> {
    scene: String,
    satqual_version: &'static str,
    model: &'a satqual::spec::SceneFile,
}

/// Sections that only a `[stack]` gives a meaning (their keys name stack parameters, or they
/// simulate the stack's release), with why they are left out of the generic model.
const STACK_ONLY: &str =
    "[separation], [calibration], [update] and [sweep] (they act on the stack's parameters)";

/// The generic model of `scene`: the expanded nodes, beams and joints, the stack's default
/// response points named in the model, and no section that needs the `[stack]` itself.
fn generic_model(scene: &satqual::spec::Scene) -> satqual::spec::SceneFile {
    let mut model = scene.model.clone();
    if scene.file.stack.is_some() {
        model.response = satqual::spec::analysis::response_points(scene);
        model.separation = None;
        model.calibration = None;
        model.update = None;
        model.sweep = None;
    }
    model
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let scene = satqual::spec::Scene::load(&args.scene)?;
    let model = generic_model(&scene);
    if args.json {
        Printer::new(true).json(&Output {
            scene: args.scene.display().to_string(),
            satqual_version: env!("CARGO_PKG_VERSION"),
            model: &model,
        })?;
        return Ok(Outcome::Pass);
    }
    let body = toml::to_string(&model)
        .map_err(|e| Error::Other(format!("cannot write the expanded model: {e}")))?;
    let stack_note = if scene.file.stack.is_some() {
        format!(
            "# Left out: {STACK_ONLY}. The lock-integrity margins (gapping, slip, bar strength)\n# are the stack's: this model gives the same modes and responses, not those margins.\n"
        )
    } else {
        String::new()
    };
    let header = format!(
        "# Generic model expanded by satqual {} from {}.\n# Node ids: satellite i = 1000·i; its column c bottom/mid/top = 1000·i + 10·c + 1/2/3;\n# platform under column c = 10·c; guide bar c level j = 10000000·c + 10 + j (root 10000000·c).\n{stack_note}\n",
        env!("CARGO_PKG_VERSION"),
        args.scene.display()
    );
    let _ = std::io::stdout().write_all(header.as_bytes());
    let _ = std::io::stdout().write_all(body.as_bytes());
    Ok(Outcome::Pass)
}
