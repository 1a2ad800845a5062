//! Progress on the terminal: the bindings report long kernel work
//! ([`blocksmith_script::progress`]) and this draws it with indicatif on standard error — a bar
//! when the length is known (a long meshing), a spinner when not (a boolean) — and nothing
//! when standard error is not a terminal, so pipes, tests and CI see no extra output.

use std::io::IsTerminal;
use std::time::Duration;

use blocksmith_script::progress::{Progress, ProgressSink, ProgressTask};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// The progress of the command's runs: bars on standard error when it is a terminal.
#[must_use]
pub fn on_terminal() -> Progress {
    Progress::new(TerminalBars)
}

/// Draws each task as an indicatif bar or spinner on standard error, if it is a terminal.
struct TerminalBars;

impl ProgressSink for TerminalBars {
    fn start(&self, task: &str, total: Option<u64>) -> Box<dyn ProgressTask> {
        if !std::io::stderr().is_terminal() {
            return Box::new(Hidden);
        }
        let bar = match total {
            Some(total) => {
                let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
                if let Ok(style) = ProgressStyle::with_template("{msg}: {bar:40} {percent:>3}% ({elapsed} / ~{eta})") {
                    bar.set_style(style);
                }
                bar
            }
            None => {
                let spinner = ProgressBar::new_spinner();
                spinner.enable_steady_tick(Duration::from_millis(120));
                spinner
            }
        };
        bar.set_message(task.to_string());
        Box::new(Shown(bar))
    }
}

/// A task drawn on the terminal; cleared when it ends.
struct Shown(ProgressBar);

impl ProgressTask for Shown {
    fn set(&mut self, done: u64) {
        self.0.set_position(done);
    }
}

impl Drop for Shown {
    fn drop(&mut self) {
        self.0.finish_and_clear();
    }
}

/// A task on a standard error that is not a terminal: nothing is drawn.
struct Hidden;

impl ProgressTask for Hidden {
    fn set(&mut self, _done: u64) {}
}
