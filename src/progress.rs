//! Signs of life for long work (`synth`, `verify`, `bench`): a stage shows
//! what runs and for how long, on standard error so that standard output
//! stays the report. On a terminal a spinner (indicatif) with the elapsed
//! time; otherwise one line when the stage starts, one every
//! [`QUIET_LINE_EVERY`] while it runs and one when it ends, so a CI log or
//! a pipe shows a hung tool apart from a slow one.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How often a stage says it still runs when standard error is no
/// terminal.
pub const QUIET_LINE_EVERY: Duration = Duration::from_secs(30);

enum Display {
    Spinner(ProgressBar),
    Lines {
        stop: Arc<AtomicBool>,
        ticker: Option<JoinHandle<()>>,
    },
}

/// One stage of long work, from [`Stage::start`] to [`Stage::finish`]
/// (or its drop, when the work failed).
pub struct Stage {
    what: String,
    started: Instant,
    display: Display,
}

impl Stage {
    /// Starts showing `what`.
    pub fn start(what: impl Into<String>) -> Self {
        Self::start_with(what, std::io::stderr().is_terminal(), QUIET_LINE_EVERY)
    }

    fn start_with(what: impl Into<String>, terminal: bool, every: Duration) -> Self {
        let what = what.into();
        let display = if terminal {
            let bar = ProgressBar::new_spinner();
            bar.set_style(
                ProgressStyle::with_template("{spinner} {msg} {elapsed}")
                    .expect("a fixed template"),
            );
            bar.set_message(what.clone());
            bar.enable_steady_tick(Duration::from_millis(120));
            Display::Spinner(bar)
        } else {
            eprintln!("{what}: started");
            let stop = Arc::new(AtomicBool::new(false));
            let (flag, name) = (stop.clone(), what.clone());
            let ticker = std::thread::spawn(move || {
                let started = Instant::now();
                let mut next = every;
                while !flag.load(Ordering::Relaxed) {
                    std::thread::sleep(Duration::from_millis(50).min(every));
                    if started.elapsed() >= next && !flag.load(Ordering::Relaxed) {
                        eprintln!("{name}: still running, {} s", next.as_secs());
                        next += every;
                    }
                }
            });
            Display::Lines {
                stop,
                ticker: Some(ticker),
            }
        };
        Self {
            what,
            started: Instant::now(),
            display,
        }
    }

    /// Runs `work` as a stage named `what`.
    pub fn run<T>(what: impl Into<String>, work: impl FnOnce() -> T) -> T {
        let stage = Self::start(what);
        let out = work();
        stage.finish();
        out
    }

    /// Ends the stage, saying how long it took; returns that.
    pub fn finish(mut self) -> Duration {
        let took = self.started.elapsed();
        self.stop();
        eprintln!("{}: done in {:.1} s", self.what, took.as_secs_f64());
        took
    }

    fn stop(&mut self) {
        match &mut self.display {
            Display::Spinner(bar) => bar.finish_and_clear(),
            Display::Lines { stop, ticker } => {
                stop.store(true, Ordering::Relaxed);
                if let Some(t) = ticker.take() {
                    let _ = t.join();
                }
            }
        }
    }
}

impl Drop for Stage {
    fn drop(&mut self) {
        self.stop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quiet_stage_ticks_and_finishes_with_its_time() {
        // The ticker's lines go to standard error; what is checked here is
        // that it stops with the stage and the time is measured.
        let stage = Stage::start_with("test stage", false, Duration::from_millis(60));
        std::thread::sleep(Duration::from_millis(150));
        let took = stage.finish();
        assert!(took >= Duration::from_millis(150), "{took:?}");
        // A dropped stage (the work failed) stops its ticker too.
        drop(Stage::start_with(
            "dropped",
            false,
            Duration::from_millis(10),
        ));
    }
}
