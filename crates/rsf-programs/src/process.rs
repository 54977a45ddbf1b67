//! How a program's process ends: its body's error printed with its causes (one line each)
//! and the exit code, the body run on a rayon pool of the run's threads if it asks for one.

use std::process::ExitCode;

/// Runs an example's body: on error prints `error: …` and its causes (one line each, at
/// most five) to stderr and exits with code 1.
pub fn main_with(body: impl FnOnce() -> Result<(), Box<dyn std::error::Error>>) -> ExitCode {
    exit_with(body().map_err(|e| error_lines(&*e)))
}

/// [`main_with`] with the body run on a rayon pool of `threads` threads when `threads > 1`
/// (on the calling thread otherwise). A run whose steps have short parallel regions (the
/// fault ODE's evaluations) must run on a thread of the pool: a region entered from
/// outside it hands all its work to the pool and puts the caller to sleep until it is
/// done, a wake-up of a thread per region (docs/scaling.md, "From inside the pool").
/// The results do not depend on it.
pub fn main_on_threads(
    threads: usize,
    body: impl FnOnce() -> Result<(), Box<dyn std::error::Error>> + Send,
) -> ExitCode {
    exit_with(on_threads(threads, body))
}

/// `body` on a rayon pool of `threads` threads when `threads > 1` (on the calling thread
/// otherwise); its error as the lines [`main_with`] prints.
pub(crate) fn on_threads(
    threads: usize,
    body: impl FnOnce() -> Result<(), Box<dyn std::error::Error>> + Send,
) -> Result<(), Vec<String>> {
    if threads <= 1 {
        return body().map_err(|e| error_lines(&*e));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        // The main thread's stack, not a spawned thread's default.
        .stack_size(8 << 20)
        .build()
        .map_err(|e| error_lines(&e))?;
    // The error's text crosses back: a boxed error need not be `Send`.
    pool.install(|| body().map_err(|e| error_lines(&*e)))
}

/// An error and at most five of its causes, one line each.
pub(crate) fn error_lines(e: &dyn std::error::Error) -> Vec<String> {
    let mut lines = vec![format!("error: {e}")];
    let mut cause = e.source();
    for _ in 0..5 {
        let Some(c) = cause else { break };
        lines.push(format!("  caused by: {c}"));
        cause = c.source();
    }
    lines
}

fn exit_with(outcome: Result<(), Vec<String>>) -> ExitCode {
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(lines) => {
            for line in lines {
                eprintln!("{line}");
            }
            ExitCode::FAILURE
        }
    }
}
