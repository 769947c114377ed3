//! The `wrinkle` command: the library's command line on the process's arguments.

use std::process::ExitCode;

fn main() -> ExitCode {
    remove_temporaries_on_signals();
    match wrinkle_cli::execute(std::env::args_os()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("error: {}", failure.message);
            ExitCode::from(failure.code)
        }
    }
}

/// Ctrl-C, SIGTERM and SIGHUP end the process as they would, but first remove the temporary files of
/// outputs being written, so that an interrupted job leaves nothing behind.
fn remove_temporaries_on_signals() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        return;
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            wrinkle::image::output::remove_temporaries();
            std::process::exit(128 + signal);
        }
    });
}
