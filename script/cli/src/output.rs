//! What the command prints: results on standard output (a closed pipe ends the command
//! quietly), summaries and errors on standard error, and the exit status that goes with them.

use std::process::ExitCode;

use blocksmith_script::printable::printable;

/// Writes `text` to standard output. A reader that stops early (`blocksmith doc | head`) closes
/// the pipe: the command then ends quietly, as other command-line tools do, instead of panicking.
pub fn print_out(text: &str) {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(text.as_bytes()).and_then(|()| stdout.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => eprintln!("error: could not write to standard output: {e}"),
        Ok(()) => {}
    }
}

/// Prints a command's result on standard error: the summary on success, the error on failure.
pub fn report<E: std::fmt::Display>(result: Result<String, E>) -> ExitCode {
    match result {
        Ok(summary) => {
            eprintln!("{}", printable(&summary));
            ExitCode::SUCCESS
        }
        Err(e) => fail(e),
    }
}

/// Prints `error` on standard error (control characters escaped,
/// [`printable`]): the command failed.
pub fn fail(error: impl std::fmt::Display) -> ExitCode {
    eprintln!("{}", printable(&error.to_string()));
    ExitCode::FAILURE
}
