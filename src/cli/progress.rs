//! Progress on stderr for the commands that can run longer than a couple of seconds
//! (qualify, modal and sine and random on large models, separate with a Monte Carlo, bench,
//! sweep): an indicatif spinner with the current stage and the elapsed time, redrawn at most a
//! few times a second. It stays silent with `--quiet`, with `--json` when stdout is not a terminal (the
//! output is piped to a program), and whenever stderr is not a terminal (indicatif draws
//! nothing there), so logs and pipes never receive spinner frames.

use std::io::IsTerminal;
use std::time::Duration;

/// A running spinner, or nothing when progress is silenced.
pub struct Progress {
    bar: Option<indicatif::ProgressBar>,
}

/// Whether progress may be drawn, by the rules of the module comment.
pub fn visible(quiet: bool, json: bool) -> bool {
    let json_piped = json && !std::io::stdout().is_terminal();
    !quiet && !json_piped && std::io::stderr().is_terminal()
}

impl Progress {
    /// Starts the spinner on `stage`, unless silenced.
    pub fn start(quiet: bool, json: bool, stage: &str) -> Progress {
        if !visible(quiet, json) {
            return Progress { bar: None };
        }
        let bar = indicatif::ProgressBar::new_spinner();
        let style = indicatif::ProgressStyle::with_template("{spinner} {msg} [{elapsed}]")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner());
        bar.set_style(style);
        bar.set_message(stage.to_string());
        bar.enable_steady_tick(Duration::from_millis(200));
        Progress { bar: Some(bar) }
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
        if let Some(b) = &self.bar {
            b.set_message(name.to_string());
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}
