//! Progress on stderr for the commands that can run longer than a couple of seconds
//! (qualify, modal and sine and random on large models, separate with a Monte Carlo, bench,
//! sweep): an indicatif spinner with the current stage and the elapsed time, redrawn at most a
//! few times a second. It stays silent with `--quiet`, with `--json` when stdout is not a terminal (the
//! output is piped to a program), and whenever stderr is not a terminal (indicatif draws
//! nothing there), so logs and pipes never receive spinner frames.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// A running spinner, or nothing when progress is silenced.
pub struct Progress {
    bar: Option<indicatif::ProgressBar>,
    /// The current stage's name, to which a count is appended, and when it began.
    stage: std::sync::Mutex<(String, Instant)>,
}

/// Whether progress may be drawn, by the rules of the module comment.
pub fn visible(quiet: bool, json: bool) -> bool {
    let json_piped = json && !std::io::stdout().is_terminal();
    !quiet && !json_piped && std::io::stderr().is_terminal()
}

impl Progress {
    /// Starts the spinner on `stage`, unless silenced.
    pub fn start(quiet: bool, json: bool, stage: &str) -> Progress {
        let stage_name = std::sync::Mutex::new((stage.to_string(), Instant::now()));
        if !visible(quiet, json) {
            return Progress {
                bar: None,
                stage: stage_name,
            };
        }
        let bar = indicatif::ProgressBar::new_spinner();
        let style = indicatif::ProgressStyle::with_template("{spinner} {msg} [{elapsed}]")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner());
        bar.set_style(style);
        bar.set_message(stage.to_string());
        bar.enable_steady_tick(Duration::from_millis(200));
        Progress {
            bar: Some(bar),
            stage: stage_name,
        }
    }

    /// Clears the spinner line, so the summary that follows starts on a clean line.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

impl satqual::pipeline::Progress for Progress {
    fn stage(&self, name: &str) {
        if let Ok(mut s) = self.stage.lock() {
            *s = (name.to_string(), Instant::now());
        }
        if let Some(b) = &self.bar {
            b.set_message(name.to_string());
        }
    }

    /// "separation Monte Carlo: 340/1109 runs, about 2 min 10 s left" (the rate so far).
    fn count(&self, done: usize, total: usize) {
        let (Some(b), Ok(stage)) = (&self.bar, self.stage.lock()) else {
            return;
        };
        let (stage, started) = &*stage;
        let elapsed = started.elapsed().as_secs_f64();
        let left = elapsed / done.max(1) as f64 * total.saturating_sub(done) as f64;
        b.set_message(format!(
            "{stage}: {done}/{total} runs, about {} left",
            duration(left)
        ));
    }
}

/// Seconds as "45 s" or "2 min 10 s".
fn duration(s: f64) -> String {
    let s = s.round() as u64;
    match s {
        0..=59 => format!("{s} s"),
        _ => format!("{} min {} s", s / 60, s % 60),
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}
