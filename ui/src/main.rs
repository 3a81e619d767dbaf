//! `vbrain`: with no subcommand, the desktop viewer; with one, a headless command (see `cli`).

use clap::Parser;
use vbrain_ui::cli;

fn main() -> std::process::ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let args = cli::Args::parse();
    match args.command {
        None => match vbrain_ui::viewer::run(args.path) {
            Ok(()) => std::process::ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e:#}");
                std::process::ExitCode::FAILURE
            }
        },
        Some(command) => {
            // Headless output piped into `head` and the like ends quietly, as other Unix tools do,
            // instead of failing on the closed pipe.
            #[cfg(unix)]
            // SAFETY: restores the default action of one signal before any other thread runs output.
            unsafe {
                libc::signal(libc::SIGPIPE, libc::SIG_DFL);
            }
            cli::run(command)
        }
    }
}
