//! `vbrain`: with no subcommand, the desktop viewer; with one, a headless command (see `cli`).
//!
//! - The viewer's errors go to stderr with a failure exit status; a command's exit status is
//!   `cli::run`'s.

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
            quiet_device_select();
            // Headless output piped into `head` and the like ends quietly, as other Unix tools do,
            // instead of failing on the closed pipe. Not for `video`, which pipes frames into an
            // encoder: if that fails, vbrain must live to remove the partial file.
            #[cfg(unix)]
            if !matches!(command, cli::Command::Video(_)) {
                // SAFETY: restores the default action of one signal before any other thread runs.
                unsafe {
                    libc::signal(libc::SIGPIPE, libc::SIG_DFL);
                }
            }
            cli::run(command)
        }
    }
}

/// Mesa's Vulkan device-select layer asks the Wayland compositor which GPU to prefer; with no
/// `XDG_RUNTIME_DIR` there is none to ask, and the layer only prints "XDG_RUNTIME_DIR is invalid".
/// Headless commands need no display, so there they turn the layer off (its documented switch,
/// `NODEVICE_SELECT`) unless the user set it. Called before any other thread starts.
fn quiet_device_select() {
    let runtime_dir = std::env::var_os("XDG_RUNTIME_DIR").filter(|d| std::path::Path::new(d).is_dir());
    if runtime_dir.is_none() && std::env::var_os("NODEVICE_SELECT").is_none() {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}
