//! `vbrain`: with no subcommand, the desktop viewer; with one, a headless command (see `cli`).

use clap::Parser;
use vbrain_ui::cli;

fn main() -> std::process::ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let args = cli::Args::parse();
    match args.command {
        None => match vbrain_ui::app::run(args.path) {
            Ok(()) => std::process::ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e:#}");
                std::process::ExitCode::FAILURE
            }
        },
        Some(command) => cli::run(command),
    }
}
